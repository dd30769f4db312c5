#include "graph/plan.h"

#include "core/error.h"
#include "graph/per_light.h"

#include <cstdlib>
#include <utility>

namespace caustica::graph {

std::string Plan::resolve(const std::string& name) const {
  auto it = fallbacks.find(name);
  if (it != fallbacks.end()) return it->second;
  // A per-light resource's own name stands for light 0's instance, as a plain resource bound to a
  // per-light port is its element 0 (graph/per_light.h).
  const std::string first = light_instance(name, 0);
  if (find_resource(name) < 0 && (find_resource(first) >= 0 || fallbacks.count(first))) return resolve(first);
  return name;
}

int Plan::find_resource(std::string_view name) const {
  for (size_t i = 0; i < resources.size(); ++i) {
    if (resources[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

namespace {
template <typename Flags, size_t N>
std::string flag_names(Flags flags, const std::pair<Flags, const char*> (&table)[N]) {
  std::string out;
  for (const auto& [bit, name] : table) {
    if ((flags & bit) == bit && bit != 0) {
      out += out.empty() ? "" : "|";
      out += name;
      flags &= ~bit;
    }
  }
  if (flags != 0) out += out.empty() ? "OTHER" : "|OTHER";
  return out.empty() ? "NONE" : out;
}
}  // namespace

std::string stage_names(VkPipelineStageFlags2 stages) {
  static const std::pair<VkPipelineStageFlags2, const char*> table[] = {
      {VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT, "DRAW_INDIRECT"},
      {VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT, "VERTEX_SHADER"},
      {VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, "FRAGMENT_SHADER"},
      {VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT, "EARLY_FRAGMENT_TESTS"},
      {VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT, "LATE_FRAGMENT_TESTS"},
      {VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, "COLOR_ATTACHMENT_OUTPUT"},
      {VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, "COMPUTE_SHADER"},
      {VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, "ALL_TRANSFER"},
      {VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, "ALL_COMMANDS"},
  };
  return flag_names(stages, table);
}

std::string access_names(VkAccessFlags2 access) {
  static const std::pair<VkAccessFlags2, const char*> table[] = {
      {VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT, "INDIRECT_COMMAND_READ"},
      {VK_ACCESS_2_UNIFORM_READ_BIT, "UNIFORM_READ"},
      {VK_ACCESS_2_SHADER_SAMPLED_READ_BIT, "SHADER_SAMPLED_READ"},
      {VK_ACCESS_2_SHADER_STORAGE_READ_BIT, "SHADER_STORAGE_READ"},
      {VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, "SHADER_STORAGE_WRITE"},
      {VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT, "COLOR_ATTACHMENT_READ"},
      {VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT, "COLOR_ATTACHMENT_WRITE"},
      {VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT, "DEPTH_STENCIL_ATTACHMENT_READ"},
      {VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT, "DEPTH_STENCIL_ATTACHMENT_WRITE"},
      {VK_ACCESS_2_TRANSFER_READ_BIT, "TRANSFER_READ"},
      {VK_ACCESS_2_TRANSFER_WRITE_BIT, "TRANSFER_WRITE"},
  };
  return flag_names(access, table);
}

std::string layout_name(VkImageLayout layout) {
  switch (layout) {
    case VK_IMAGE_LAYOUT_UNDEFINED: return "UNDEFINED";
    case VK_IMAGE_LAYOUT_GENERAL: return "GENERAL";
    case VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL: return "COLOR_ATTACHMENT_OPTIMAL";
    case VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL: return "DEPTH_ATTACHMENT_OPTIMAL";
    case VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL: return "DEPTH_READ_ONLY_OPTIMAL";
    case VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL: return "SHADER_READ_ONLY_OPTIMAL";
    case VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL: return "TRANSFER_SRC_OPTIMAL";
    case VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL: return "TRANSFER_DST_OPTIMAL";
    default: return "LAYOUT_" + std::to_string(static_cast<int>(layout));
  }
}

const char* tracer_name(Tracer tracer) {
  return tracer == Tracer::ray_query ? "ray_query" : tracer == Tracer::compute ? "compute" : "none";
}

std::optional<Tracer> parse_tracer(std::string_view name) {
  if (name == "ray_query") return Tracer::ray_query;
  if (name == "compute") return Tracer::compute;
  return std::nullopt;
}

std::optional<Tracer> tracer_from_environment() {
  const char* value = std::getenv("CAUSTICA_TRACER");
  if (!value || !*value || std::string_view(value) == "auto") return std::nullopt;
  if (auto tracer = parse_tracer(value)) return tracer;
  throw InputError(std::string("CAUSTICA_TRACER=") + value + ": the tracer is ray_query, compute or auto");
}

nlohmann::json plan_to_json(const Plan& plan) {
  using json = nlohmann::ordered_json;
  json out;
  out["graph"] = plan.graph_name;
  out["file"] = plan.graph_path;
  out["output_size"] = {plan.output_width, plan.output_height};
  out["order"] = json::array();
  for (const auto& p : plan.passes) out["order"].push_back(p.name);
  out["culled"] = plan.culled;
  out["traced_passes"] = plan.traced_passes;
  if (plan.tracer != Tracer::none) out["tracer"] = tracer_name(plan.tracer);
  out["warnings"] = plan.warnings;
  out["disabled"] = plan.disabled;
  out["disabled_by"] = plan.disabled_by;
  out["fallbacks"] = plan.fallbacks;
  out["reuses_unchanged_passes"] = plan.reuses_unchanged_passes;
  out["jitters_camera"] = plan.jitters_camera;
  out["refines_apart"] = plan.refines_apart;
  out["passes"] = json::array();
  for (const auto& p : plan.passes) {
    json pass;
    pass["name"] = p.name;
    pass["type"] = p.type;
    pass["params"] = json::parse(p.params.dump());
    // Parameters that follow the frame: their expressions (params holds the first frame's values).
    if (!p.frame_params.empty()) pass["frame_params"] = p.frame_params;
    // What its result depends on besides parameters (its inputs' dependencies included), and whether
    // a plan that reuses unchanged passes may skip it.
    pass["depends_on"] = dependency_names(p.depends);
    // Of the lights, those it follows where not every one (a per-light pass's own): moving another
    // light leaves it.
    if ((p.depends & kDependsOnLights) && p.lights != kAllLights) {
      pass["follows_lights"] = json::array();
      for (uint32_t k = 0; k < 32; ++k) {
        if (p.lights >> k & 1u) pass["follows_lights"].push_back(k);
      }
    }
    if (plan.refines_apart) pass["refines"] = p.refines;
    pass["ports"] = json::object();
    for (const auto& [port, r] : p.ports) pass["ports"][port] = plan.resources[r].name;
    pass["barriers"] = json::array();
    for (const auto& b : p.barriers) {
      json barrier;
      barrier["resource"] = plan.resources[b.resource].name;
      barrier["src_stages"] = stage_names(b.src_stages);
      barrier["src_access"] = access_names(b.src_access);
      barrier["dst_stages"] = stage_names(b.dst_stages);
      barrier["dst_access"] = access_names(b.dst_access);
      if (plan.resources[b.resource].kind == ResourceKind::image) {
        barrier["old_layout"] = layout_name(b.old_layout);
        barrier["new_layout"] = layout_name(b.new_layout);
      }
      if (b.aliasing) barrier["aliasing"] = true;
      pass["barriers"].push_back(barrier);
    }
    out["passes"].push_back(pass);
  }
  out["resources"] = json::array();
  for (const auto& r : plan.resources) {
    json res;
    res["name"] = r.name;
    res["kind"] = r.kind == ResourceKind::image ? "image" : "buffer";
    if (r.kind == ResourceKind::image) {
      res["format"] = format_info(r.format).name;
      res["extent"] = {r.width, r.height};
      res["mips"] = r.mips;
      res["layers"] = r.layers;
    } else {
      res["size"] = r.buffer_size;
    }
    res["used"] = r.used();
    if (r.used()) {
      res["first_use"] = plan.passes[r.first_use].name;
      res["last_use"] = plan.passes[r.last_use].name;
      res["lifetime"] = {r.first_use, r.last_use};
      res["transient"] = r.transient;
      if (r.previous_of != kNoResource) {
        // The previous frame's content of this resource, and what restarts it (as all zeros).
        res["previous_of"] = plan.resources[r.previous_of].name;
        res["restarts_on"] = dependency_names(r.history_depends & kDependsOnScene);
      }
      res["bytes"] = r.memory.size;
      if (r.transient) {
        res["block"] = r.block;
        res["offset"] = r.offset;
      }
    }
    out["resources"].push_back(res);
  }
  json memory;
  memory["transient_bytes_aliased"] = plan.transient_bytes_aliased;
  memory["transient_bytes_unaliased"] = plan.transient_bytes_unaliased;
  memory["transient_bytes_lifetime_bound"] = plan.transient_bytes_lifetime_bound;
  memory["persistent_bytes"] = plan.persistent_bytes;
  memory["blocks"] = json::array();
  for (const auto& b : plan.blocks) memory["blocks"].push_back({{"bytes", b.size}, {"memory_type_bits", b.type_bits}});
  out["memory"] = memory;
  return nlohmann::json::parse(out.dump());
}

std::string plan_to_dot(const Plan& plan) {
  auto quote = [](const std::string& s) {
    std::string out = "\"";
    for (char c : s) {
      if (c == '\n') {  // a line break inside a Graphviz label
        out += "\\n";
        continue;
      }
      if (c == '"' || c == '\\') out += '\\';
      out += c;
    }
    return out + "\"";
  };
  std::string out = "digraph " + quote(plan.graph_name) + " {\n  rankdir=LR;\n  node [fontname=\"Helvetica\"];\n";
  for (size_t i = 0; i < plan.passes.size(); ++i) {
    const auto& p = plan.passes[i];
    out += "  " + quote("pass:" + p.name) +
           " [shape=box, style=filled, fillcolor=\"#cfe2ff\", label=" + quote(std::to_string(i) + ": " + p.name + "\n(" + p.type + ")") +
           "];\n";
  }
  for (const auto& name : plan.culled) {
    out += "  " + quote("pass:" + name) +
           " [shape=box, style=\"filled,dashed\", fillcolor=\"#eeeeee\", fontcolor=\"#888888\", label=" + quote(name + "\n(culled)") +
           "];\n";
  }
  for (const auto& r : plan.resources) {
    if (!r.used()) continue;
    std::string label = r.name + "\n";
    label += r.kind == ResourceKind::image ? std::to_string(r.width) + "x" + std::to_string(r.height) + " " + format_info(r.format).name
                                           : std::to_string(r.buffer_size) + " B";
    if (r.previous_of != kNoResource)
      label += "\nlast frame's " + plan.resources[r.previous_of].name;
    else if (!r.transient)
      label += r.output ? "\noutput" : "\nretained";
    out += "  " + quote("res:" + r.name) + " [shape=ellipse, style=filled, fillcolor=" + (r.output ? "\"#ffe5b4\"" : "\"#ffffff\"") +
           ", label=" + quote(label) + "];\n";
  }
  for (const auto& p : plan.passes) {
    for (const auto& [port, index] : p.ports) {
      const auto* decl = p.decl ? p.decl->find_port(port) : nullptr;
      bool writes = decl && decl->access != PortAccess::read;
      bool reads = !decl || decl->access != PortAccess::write;
      const std::string res = quote("res:" + plan.resources[index].name);
      const std::string pass = quote("pass:" + p.name);
      if (reads) out += "  " + res + " -> " + pass + " [label=" + quote(port) + "];\n";
      if (writes) out += "  " + pass + " -> " + res + " [label=" + quote(port) + "];\n";
    }
  }
  return out + "}\n";
}

}  // namespace caustica::graph
