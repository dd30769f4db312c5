// Per-light passes and resources: the instances the compiler makes before it compiles (per_light.h).
#include "graph/per_light.h"

#include <algorithm>
#include <cctype>
#include <map>
#include <optional>
#include <vector>

#include "graph/plan.h"

namespace caustica::graph {
namespace {

class Expansion {
 public:
  Expansion(const GraphDesc& graph, uint32_t lights, const std::vector<uint32_t>& view_lights)
      : graph_(graph), lights_(lights), view_lights_(view_lights) {
    for (const auto& r : graph.resources) {
      if (!r.for_each.empty()) resource_kinds_[r.name] = r.for_each;
    }
    for (const auto& p : graph.passes) {
      if (!p.for_each.empty()) pass_kinds_[p.name] = p.for_each;
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
  const std::vector<uint32_t>& view_lights_;
  std::map<std::string, std::string> resource_kinds_, pass_kinds_;  // "light" or "caustic_view"

  uint32_t count(std::string_view kind) const { return kind == kForEachLight ? lights_ : static_cast<uint32_t>(view_lights_.size()); }
  Instance instance_of_kind(std::string_view kind, uint32_t k) const {
    return kind == kForEachLight ? Instance{static_cast<int>(k), -1} : Instance{static_cast<int>(view_lights_[k]), static_cast<int>(k)};
  }
  static std::string once_per(std::string_view kind) { return kind == kForEachLight ? "light" : "caustic view"; }
  // A per-light or per-view resource's kind, "" for one made once ("NAME@previous" as NAME).
  std::string kind_of(std::string_view resource) const {
    const std::string source = history_source(resource);
    const auto it = resource_kinds_.find(source.empty() ? std::string(resource) : source);
    return it == resource_kinds_.end() ? "" : it->second;
  }
  // The instances of a per-`kind` resource or pass that instance `at` binds: the same where the
  // kinds agree, a view's light's, or (after a per-view pass) every view of the light.
  std::vector<uint32_t> related(std::string_view kind, Instance at) const {
    if (kind == kForEachLight) return {static_cast<uint32_t>(at.light)};
    if (at.view >= 0) return {static_cast<uint32_t>(at.view)};
    std::vector<uint32_t> views;
    for (uint32_t v = 0; v < view_lights_.size(); ++v) {
      if (static_cast<int>(view_lights_[v]) == at.light) views.push_back(v);
    }
    return views;
  }
  // What a pass's "after" names, for instance `at` (none: the pass runs once, after every instance).
  std::vector<std::string> after_instances(const PassDesc& pass, Instance at) const {
    std::vector<std::string> out;
    for (const auto& after : pass.after) {
      const auto kind = pass_kinds_.find(after);
      if (kind == pass_kinds_.end()) {
        out.push_back(after);
        continue;
      }
      if (at.any()) {
        for (uint32_t k : related(kind->second, at)) out.push_back(light_instance(after, k));
      } else {
        for (uint32_t k = 0; k < count(kind->second); ++k) out.push_back(light_instance(after, k));
      }
    }
    return out;
  }
  // Instance K's binding, "NAME@previous" kept as the previous frame's.
  static std::string instance_binding(const std::string& binding, uint32_t k) {
    const std::string source = history_source(binding);
    return source.empty() ? light_instance(binding, k) : history_of(light_instance(source, k));
  }

  void refuse_per_light_output(const std::string& name, const std::string& pointer) const {
    if (resource_kinds_.count(name)) {
      const std::string per = once_per(resource_kinds_.at(name));
      throw graph_.error(pointer, "'" + name + "' is a per-" + per + " resource (one image per " + per +
                                      "), which a graph output cannot be; output what a pass that runs once makes of it");
    }
  }

  void add_resource(GraphDesc& out, const ResourceDesc& r) const {
    const std::string fallback_kind = resource_kinds_.count(r.fallback) ? resource_kinds_.at(r.fallback) : "";
    if (r.for_each.empty()) {
      if (!fallback_kind.empty()) {
        throw graph_.error(r.pointer + "/fallback", "'" + r.name + "' is one resource and its fallback '" + r.fallback + "' one per " +
                                                        once_per(fallback_kind) + "; give '" + r.name + "' \"for_each\": \"" +
                                                        fallback_kind + "\" too");
      }
      out.resources.push_back(r);
      return;
    }
    if (!fallback_kind.empty() && fallback_kind != r.for_each) {
      throw graph_.error(r.pointer + "/fallback", "'" + r.name + "' is one resource per " + once_per(r.for_each) + " and its fallback '" +
                                                      r.fallback + "' one per " + once_per(fallback_kind) +
                                                      "; a fallback is made as often as what it stands in for");
    }
    for (uint32_t k = 0; k < count(r.for_each); ++k) {
      ResourceDesc instance = r;
      instance.for_each.clear();
      instance.name = light_instance(r.name, k);
      instance.instance = instance_of_kind(r.for_each, k);
      if (!fallback_kind.empty()) instance.fallback = light_instance(r.fallback, k);
      out.resources.push_back(std::move(instance));
    }
  }

  void add_pass(GraphDesc& out, const PassDesc& pass) const {
    if (pass.for_each.empty()) {
      out.passes.push_back(once(pass));
      return;
    }
    for (const auto& [port, resource] : pass.outputs) {
      const std::string kind = kind_of(resource);
      if (kind != pass.for_each) {
        throw graph_.error(json_pointer_append(pass.pointer + "/outputs", port),
                           "pass '" + pass.name + "' runs once per " + once_per(pass.for_each) + " and writes '" + resource +
                               "', which is " +
                               (kind.empty() ? "one resource that every instance would write" : "one resource per " + once_per(kind)) +
                               "; declare '" + resource + "' with \"for_each\": \"" + pass.for_each + "\"");
      }
    }
    for (const auto& [port, resource] : pass.inputs) {
      if (pass.for_each == kForEachLight && kind_of(resource) == kForEachCausticView) {
        throw graph_.error(json_pointer_append(pass.pointer + "/inputs", port),
                           "pass '" + pass.name + "' runs once per light and reads '" + resource +
                               "', one per caustic view (a point light may have several); read it in a pass with \"for_each\": "
                               "\"caustic_view\", or in one that runs once (each view an element of a per-light port)");
      }
    }
    for (uint32_t k = 0; k < count(pass.for_each); ++k) out.passes.push_back(instance(pass, instance_of_kind(pass.for_each, k)));
  }

  PassDesc instance(const PassDesc& pass, Instance at) const {
    PassDesc p = pass;
    p.for_each.clear();
    p.instance = at;
    p.name = light_instance(pass.name, static_cast<uint32_t>(at.index()));
    for (auto& value : p.params) {
      if (value == "$light") value = at.index();
    }
    for (auto* section : {&p.inputs, &p.outputs}) {
      for (auto& [port, resource] : *section) {
        const std::string kind = kind_of(resource);
        if (!kind.empty()) resource = instance_binding(resource, related(kind, at).front());
      }
    }
    p.after = after_instances(pass, at);
    return p;
  }

  PassDesc once(const PassDesc& pass) const {
    PassDesc p = pass;
    for (const auto& [port, resource] : pass.outputs) {
      const std::string kind = kind_of(resource);
      if (!kind.empty()) {
        throw graph_.error(json_pointer_append(pass.pointer + "/outputs", port),
                           "'" + resource + "' is a per-" + once_per(kind) + " resource (one image per " + once_per(kind) +
                               "), which only a pass with \"for_each\": \"" + kind + "\" writes; pass '" + pass.name + "' runs once");
      }
    }
    p.inputs.clear();
    for (const auto& [port, resource] : pass.inputs) {
      const std::string kind = kind_of(resource);
      if (kind.empty()) {
        p.inputs[port] = resource;
        continue;
      }
      // Each instance as an element of the port; a port that names its element takes that instance.
      const auto [base, element] = split_port_element(port);
      if (element >= 0) {
        if (static_cast<uint32_t>(element) < count(kind)) p.inputs[port] = instance_binding(resource, static_cast<uint32_t>(element));
        continue;
      }
      for (uint32_t k = 0; k < count(kind); ++k) p.inputs[port_element(port, k)] = instance_binding(resource, k);
    }
    p.after = after_instances(pass, {});
    return p;
  }
};

// The prefix of an instance's names in the scene's values.
std::string scene_prefix(Instance instance) {
  return instance.view >= 0 ? "scene.caustic" + std::to_string(instance.view) + "." : "scene.light" + std::to_string(instance.light) + ".";
}

}  // namespace

ExpressionScope light_scope(ExpressionScope scope, Instance instance) {
  if (!instance.any()) return scope;
  const std::string prefix = scene_prefix(instance);
  std::vector<std::string> names{"light.index"};
  for (const auto& name : scope.known_names) {
    if (name.starts_with(prefix)) names.push_back("light." + name.substr(prefix.size()));
  }
  scope.known_names.insert(scope.known_names.end(), names.begin(), names.end());
  scope.lookup = [lookup = std::move(scope.lookup), prefix, index = instance.index()](std::string_view name) -> std::optional<double> {
    if (name == "light.index") return index;
    if (name.starts_with("light.")) return lookup(prefix + std::string(name.substr(6)));
    return lookup(name);
  };
  return scope;
}

std::string as_read_by_light(std::string_view text, Instance instance) {
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
      out += std::to_string(instance.index());
    else if (name.starts_with("light."))
      out += scene_prefix(instance) + std::string(name.substr(6));
    else
      out += name;
    i = end;
  }
  return out;
}

std::string light_instance(std::string_view name, uint32_t index) {
  return std::string(name) + "#" + std::to_string(index);
}

std::string_view instance_of(std::string_view name) {
  const size_t hash = name.rfind('#');
  if (hash == std::string_view::npos || hash + 1 == name.size()) return name;
  for (size_t i = hash + 1; i < name.size(); ++i) {
    if (!std::isdigit(static_cast<unsigned char>(name[i]))) return name;
  }
  return name.substr(0, hash);
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

GraphDesc expand_per_light(const GraphDesc& graph, uint32_t lights, const std::vector<uint32_t>& view_lights) {
  return Expansion(graph, lights, view_lights).run();
}

}  // namespace caustica::graph
