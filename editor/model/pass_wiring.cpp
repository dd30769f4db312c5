#include "model/pass_wiring.h"

#include <algorithm>

#include "core/error.h"
#include "graph/format.h"
#include "graph/per_light.h"

namespace caustica::editor {
namespace {

using nlohmann::ordered_json;

// An image resource's "layers" when written as a number (an expression counts as unknown: 0).
uint32_t written_layers(const ordered_json& resource) {
  if (!resource.contains("layers")) return 1;
  const ordered_json& layers = resource["layers"];
  if (layers.is_number_unsigned()) return layers.get<uint32_t>();
  if (!layers.is_string()) return 0;
  const std::string text = layers.get<std::string>();
  if (text.empty() || text.size() > 2 || text.find_first_not_of("0123456789") != std::string::npos) return 0;
  return static_cast<uint32_t>(std::stoul(text));
}

// `doc`'s `section`, or an empty one: the const document's operator[] cannot add it.
const ordered_json& section_of(const ordered_json& doc, const char* section, const ordered_json& empty) {
  return doc.contains(section) ? doc[section] : empty;
}

// The resources the graph's passes write, the latest writer in the file first.
std::vector<std::string> written_resources(const ordered_json& passes) {
  std::vector<std::string> written;
  for (auto it = passes.rbegin(); it != passes.rend(); ++it) {
    if (!it->contains("outputs")) continue;
    for (const auto& [port, resource] : (*it)["outputs"].items()) {
      if (std::find(written.begin(), written.end(), resource.get<std::string>()) == written.end()) written.push_back(resource);
    }
  }
  return written;
}

bool port_accepts(const graph::PortDecl& port, const ordered_json& resources, const std::string& resource) {
  if (!resources.contains(resource)) return false;
  const ordered_json& r = resources[resource];
  const bool buffer = r.value("type", "image") == "buffer";
  if (buffer != (port.kind == graph::ResourceKind::buffer)) return false;
  if (buffer) return true;
  if (written_layers(r) != port.layers) return false;
  if (port.formats.empty()) return true;
  const auto format = graph::parse_format(r.value("format", ""));
  return format && std::find(port.formats.begin(), port.formats.end(), *format) != port.formats.end();
}

const ordered_json kNoResources = ordered_json::object();
const ordered_json kNoPasses = ordered_json::array();

}  // namespace

PassWiring::PassWiring(const ordered_json& doc, const graph::PassTypeDecl& decl, std::string name, const std::string& path)
    : doc_(doc), resources_(section_of(doc, "resources", kNoResources)), decl_(decl), name_(std::move(name)) {
  const std::vector<std::string> written = written_resources(section_of(doc, "passes", kNoPasses));
  for (const auto& port : decl_.ports) {
    if (port.optional || port.access == graph::PortAccess::write) continue;
    inputs_.push_back(&port);
    candidates_.emplace_back();
    for (const auto& r : written) {
      if (port_accepts(port, resources_, r)) candidates_.back().push_back(r);
    }
    // One resource before a per-light (or per-view) one, which would make the new pass run once per
    // light (wired()).
    std::stable_partition(candidates_.back().begin(), candidates_.back().end(),
                          [&](const std::string& r) { return port.per_light || resources_[r].value("for_each", "").empty(); });
    if (candidates_.back().empty()) {
      std::string formats;
      for (auto f : port.formats) formats += std::string(formats.empty() ? "" : ", ") + graph::format_info(f).name;
      throw InputError(path + ": cannot add a " + decl_.type + " pass: its input '" + port.name + "' needs " +
                       (port.kind == graph::ResourceKind::buffer ? "a buffer"
                        : formats.empty()                        ? "an image"
                                                                 : "an image of " + formats) +
                       " that a pass writes, and the graph has none yet");
    }
  }
}

std::string PassWiring::size_of(const std::string& resource) const {
  const ordered_json& r = resources_[resource];
  return r.value("width", std::string("output.width")) + "," + r.value("height", std::string("output.height"));
}

ordered_json PassWiring::outputs_for(const std::vector<std::string>& chosen, ordered_json& new_resources) const {
  ordered_json bound = ordered_json::object();
  for (const auto& port : decl_.ports) {
    if (port.optional || port.access != graph::PortAccess::write) continue;
    std::string resource = name_ + "_" + port.name;
    for (int i = 2; resources_.contains(resource) || new_resources.contains(resource); ++i)
      resource = name_ + "_" + port.name + "_" + std::to_string(i);
    ordered_json r;
    if (port.kind == graph::ResourceKind::buffer) {
      r = {{"type", "buffer"}, {"size", "65536"}};
    } else {
      r = {{"type", "image"}, {"format", graph::format_info(port.formats.empty() ? graph::Format::rgba16f : port.formats.front()).name}};
      if (port.layers > 1) r["layers"] = port.layers;
      for (size_t i = 0; i < inputs_.size(); ++i) {
        if (port.extent_group.empty() || inputs_[i]->extent_group != port.extent_group) continue;
        const ordered_json& source = resources_[chosen[i]];
        for (const char* axis : {"width", "height"}) {
          if (source.contains(axis)) r[axis] = source[axis];
        }
        break;
      }
    }
    new_resources[resource] = r;
    bound[port.name] = resource;
  }
  return bound;
}

ordered_json PassWiring::wired(const ordered_json& pass, const std::vector<std::string>& chosen) const {
  ordered_json next = doc_;
  ordered_json candidate = pass;
  ordered_json in = ordered_json::object();
  ordered_json new_resources = ordered_json::object();
  ordered_json out = outputs_for(chosen, new_resources);
  // A read_write port reads an existing resource but is listed with the outputs.
  for (size_t k = 0; k < inputs_.size(); ++k) (inputs_[k]->access == graph::PortAccess::read ? in : out)[inputs_[k]->name] = chosen[k];
  if (!in.empty()) candidate["inputs"] = in;
  if (!out.empty()) candidate["outputs"] = out;
  for (auto& [key, value] : new_resources.items()) next["resources"][key] = value;
  next["passes"].push_back(candidate);
  // A pass that reads a per-light (per-view) resource through a port of one resource runs once per
  // light (view), and what it writes is too (a pass that runs once cannot read it so).
  for (size_t k = 0; k < inputs_.size(); ++k) {
    const std::string kind = resources_[chosen[k]].value("for_each", "");
    if (!inputs_[k]->per_light && !kind.empty()) {
      wire_for_each(next, next["passes"].back(), &decl_, kind);
      break;
    }
  }
  return next;
}

bool PassWiring::try_each(const ordered_json& pass, const std::function<bool(ordered_json next)>& accept) const {
  std::vector<std::string> chosen(inputs_.size());
  int tries = 0;
  std::function<bool(size_t)> choose = [&](size_t i) -> bool {
    if (i == inputs_.size()) {
      ++tries;
      return accept(wired(pass, chosen));
    }
    for (const auto& r : candidates_[i]) {
      if (tries >= kMaxTries) return false;
      bool fits = true;  // one size per extent group
      for (size_t k = 0; k < i; ++k) {
        if (!inputs_[i]->extent_group.empty() && inputs_[k]->extent_group == inputs_[i]->extent_group && size_of(chosen[k]) != size_of(r))
          fits = false;
      }
      if (!fits) continue;
      chosen[i] = r;
      if (choose(i + 1)) return true;
    }
    return false;
  };
  return choose(0);
}

void wire_for_each(nlohmann::ordered_json& doc, nlohmann::ordered_json& pass, const graph::PassTypeDecl* type, std::string_view kind) {
  const bool per_light = !kind.empty();
  auto mark = [kind](nlohmann::ordered_json& part) {
    if (!kind.empty())
      part["for_each"] = std::string(kind);
    else
      part.erase("for_each");
  };
  mark(pass);
  if (pass.contains("outputs") && pass["outputs"].is_object()) {
    for (const auto& [port, resource] : pass["outputs"].items()) {
      if (resource.is_string() && doc["resources"].contains(resource.get<std::string>()))
        mark(doc["resources"][resource.get<std::string>()]);
    }
  }
  if (!type || !type->find_param("light")) return;
  if (per_light) {
    pass["params"]["light"] = "$light";
  } else if (pass.contains("params") && pass["params"].value("light", nlohmann::ordered_json()) == "$light") {
    pass["params"].erase("light");
    if (pass["params"].empty()) pass.erase("params");
  }
}

}  // namespace caustica::editor
