// Per-light passes and resources: the instances the compiler makes before it compiles (per_light.h).
#include "graph/per_light.h"

#include <algorithm>
#include <cctype>
#include <optional>
#include <set>
#include <vector>

#include "graph/plan.h"

namespace caustica::graph {
namespace {

class Expansion {
 public:
  Expansion(const GraphDesc& graph, uint32_t lights) : graph_(graph), lights_(lights) {
    for (const auto& r : graph.resources) {
      if (!r.for_each.empty()) per_light_resources_.insert(r.name);
    }
    for (const auto& p : graph.passes) {
      if (!p.for_each.empty()) per_light_passes_.insert(p.name);
    }
  }

  GraphDesc run() {
    GraphDesc out;
    out.doc = graph_.doc;
    out.name = graph_.name;
    out.description = graph_.description;
    out.parameters = graph_.parameters;
    for (const auto& r : graph_.resources) add_resource(out, r);
    for (const auto& p : graph_.passes) add_pass(out, p);
    for (size_t i = 0; i < graph_.outputs.size(); ++i) refuse_per_light_output(graph_.outputs[i], "/outputs/" + std::to_string(i));
    if (!graph_.linear_output.empty()) refuse_per_light_output(graph_.linear_output, "/linear_output");
    out.outputs = graph_.outputs;
    out.linear_output = graph_.linear_output;
    return out;
  }

 private:
  const GraphDesc& graph_;
  uint32_t lights_;
  std::set<std::string> per_light_resources_;
  std::set<std::string> per_light_passes_;

  bool per_light(std::string_view resource) const {
    const std::string source = history_source(resource);
    return per_light_resources_.count(source.empty() ? std::string(resource) : source) != 0;
  }
  // Light K's instance of a per-light binding, "NAME@previous" kept as the previous frame's.
  static std::string instance_binding(const std::string& binding, uint32_t light) {
    const std::string source = history_source(binding);
    return source.empty() ? light_instance(binding, light) : history_of(light_instance(source, light));
  }

  void refuse_per_light_output(const std::string& name, const std::string& pointer) const {
    if (per_light_resources_.count(name)) {
      throw graph_.error(pointer, "'" + name + "' is a per-light resource (one image per light), which a graph output cannot be; " +
                                      "output what a pass that runs once makes of it");
    }
  }

  void add_resource(GraphDesc& out, const ResourceDesc& r) const {
    if (r.for_each.empty()) {
      if (!r.fallback.empty() && per_light_resources_.count(r.fallback)) {
        throw graph_.error(r.pointer + "/fallback", "'" + r.name + "' is one resource and its fallback '" + r.fallback +
                                                        "' one per light; give '" + r.name + "' \"for_each\": \"light\" too");
      }
      out.resources.push_back(r);
      return;
    }
    for (uint32_t light = 0; light < lights_; ++light) {
      ResourceDesc instance = r;
      instance.for_each.clear();
      instance.name = light_instance(r.name, light);
      instance.light = static_cast<int>(light);
      if (per_light_resources_.count(r.fallback)) instance.fallback = light_instance(r.fallback, light);
      out.resources.push_back(std::move(instance));
    }
  }

  void add_pass(GraphDesc& out, const PassDesc& pass) const {
    if (pass.for_each.empty()) {
      out.passes.push_back(once(pass));
      return;
    }
    for (const auto& [port, resource] : pass.outputs) {
      if (!per_light(resource)) {
        throw graph_.error(json_pointer_append(pass.pointer + "/outputs", port),
                           "pass '" + pass.name + "' runs once per light and writes '" + resource +
                               "', which is one resource that every light's instance would write; declare '" + resource +
                               "' with \"for_each\": \"light\"");
      }
    }
    for (uint32_t light = 0; light < lights_; ++light) out.passes.push_back(instance(pass, light));
  }

  PassDesc instance(const PassDesc& pass, uint32_t light) const {
    PassDesc p = pass;
    p.for_each.clear();
    p.light = static_cast<int>(light);
    p.name = light_instance(pass.name, light);
    for (auto& value : p.params) {
      if (value == "$light") value = light;
    }
    for (auto* section : {&p.inputs, &p.outputs}) {
      for (auto& [port, resource] : *section) {
        if (per_light(resource)) resource = instance_binding(resource, light);
      }
    }
    for (auto& after : p.after) {
      if (per_light_passes_.count(after)) after = light_instance(after, light);
    }
    return p;
  }

  PassDesc once(const PassDesc& pass) const {
    PassDesc p = pass;
    for (const auto& [port, resource] : pass.outputs) {
      if (per_light(resource)) {
        throw graph_.error(json_pointer_append(pass.pointer + "/outputs", port),
                           "'" + resource + "' is a per-light resource (one image per light), which only a pass with \"for_each\": " +
                               "\"light\" writes; pass '" + pass.name + "' runs once");
      }
    }
    p.inputs.clear();
    for (const auto& [port, resource] : pass.inputs) {
      if (!per_light(resource)) {
        p.inputs[port] = resource;
        continue;
      }
      // Each light's instance as an element of the port; a port that names its element takes that light's.
      const auto [base, element] = split_port_element(port);
      if (element >= 0) {
        if (static_cast<uint32_t>(element) < lights_) p.inputs[port] = instance_binding(resource, static_cast<uint32_t>(element));
        continue;
      }
      for (uint32_t light = 0; light < lights_; ++light) p.inputs[port_element(port, light)] = instance_binding(resource, light);
    }
    p.after.clear();
    for (const auto& after : pass.after) {
      if (!per_light_passes_.count(after)) {
        p.after.push_back(after);
        continue;
      }
      for (uint32_t light = 0; light < lights_; ++light) p.after.push_back(light_instance(after, light));
    }
    return p;
  }
};

}  // namespace

ExpressionScope light_scope(ExpressionScope scope, int light) {
  if (light < 0) return scope;
  const std::string prefix = "scene.light" + std::to_string(light) + ".";
  std::vector<std::string> names{"light.index"};
  for (const auto& name : scope.known_names) {
    if (name.starts_with(prefix)) names.push_back("light." + name.substr(prefix.size()));
  }
  scope.known_names.insert(scope.known_names.end(), names.begin(), names.end());
  scope.lookup = [lookup = std::move(scope.lookup), prefix, light](std::string_view name) -> std::optional<double> {
    if (name == "light.index") return light;
    if (name.starts_with("light.")) return lookup(prefix + std::string(name.substr(6)));
    return lookup(name);
  };
  return scope;
}

std::string as_read_by_light(std::string_view text, uint32_t light) {
  std::string out;
  size_t i = 0;
  while (i < text.size()) {
    if (!is_name_start(text[i]) || (i > 0 && is_name_char(text[i - 1]))) {
      out += text[i++];
      continue;
    }
    size_t end = i;
    while (end < text.size() && is_name_char(text[end])) ++end;
    const std::string_view name = text.substr(i, end - i);
    if (name == "light.index")
      out += std::to_string(light);
    else if (name.starts_with("light."))
      out += "scene.light" + std::to_string(light) + "." + std::string(name.substr(6));
    else
      out += name;
    i = end;
  }
  return out;
}

std::string light_instance(std::string_view name, uint32_t light) {
  return std::string(name) + "#" + std::to_string(light);
}

std::string_view instance_of(std::string_view name) {
  const size_t hash = name.rfind('#');
  if (hash == std::string_view::npos || hash + 1 == name.size()) return name;
  for (size_t i = hash + 1; i < name.size(); ++i) {
    if (!std::isdigit(static_cast<unsigned char>(name[i]))) return name;
  }
  return name.substr(0, hash);
}

int instance_light(std::string_view name) {
  const std::string_view file = instance_of(name);
  if (file.size() == name.size() || name.size() - file.size() > 3) return -1;
  return std::stoi(std::string(name.substr(file.size() + 1)));
}

std::string port_element(std::string_view port, uint32_t element) {
  return std::string(port) + "[" + std::to_string(element) + "]";
}

std::pair<std::string, int> split_port_element(std::string_view key) {
  const size_t open = key.find('[');
  if (open == std::string_view::npos || !key.ends_with(']') || open + 2 >= key.size()) return {std::string(key), -1};
  int element = 0;
  for (size_t i = open + 1; i + 1 < key.size(); ++i) {
    if (!std::isdigit(static_cast<unsigned char>(key[i])) || element > 1000) return {std::string(key), -1};
    element = element * 10 + (key[i] - '0');
  }
  return {std::string(key.substr(0, open)), element};
}

bool has_per_light(const GraphDesc& graph) {
  return std::any_of(graph.passes.begin(), graph.passes.end(), [](const PassDesc& p) { return !p.for_each.empty(); }) ||
         std::any_of(graph.resources.begin(), graph.resources.end(), [](const ResourceDesc& r) { return !r.for_each.empty(); });
}

GraphDesc expand_per_light(const GraphDesc& graph, uint32_t lights) {
  return Expansion(graph, lights).run();
}

}  // namespace caustica::graph
