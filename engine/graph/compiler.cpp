#include "graph/compiler.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <queue>
#include <set>
#include <sstream>

#include "core/suggest.h"
#include "graph/expression.h"
#include "io/json_reader.h"

namespace caustica::graph {

MemoryRequirements estimate_memory_requirements(const PlannedResource& resource) {
  if (resource.kind == ResourceKind::buffer) return {(resource.buffer_size + 255) & ~uint64_t{255}, 256, ~0u};
  uint64_t bytes = 0;
  uint64_t w = resource.width;
  uint64_t h = resource.height;
  for (uint32_t level = 0; level < resource.mips; ++level) {
    bytes += w * h * resource.layers * format_info(resource.format).bytes_per_texel;
    w = std::max<uint64_t>(1, w / 2);
    h = std::max<uint64_t>(1, h / 2);
  }
  return {(bytes + 4095) & ~uint64_t{4095}, 4096, ~0u};
}

namespace {

std::string mib(uint64_t bytes) {
  std::ostringstream out;
  out.precision(1);
  out << std::fixed << static_cast<double>(bytes) / (1024.0 * 1024.0) << " MiB";
  return out.str();
}

struct PortAccessInfo {
  VkPipelineStageFlags2 stages;
  VkAccessFlags2 reads;
  VkAccessFlags2 writes;
  VkImageLayout layout;
};

PortAccessInfo port_access(const PortDecl& port, PassQueue queue) {
  const VkPipelineStageFlags2 shader = queue == PassQueue::compute
                                           ? VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT
                                           : VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT;
  const bool reads = port.access != PortAccess::write;
  const bool writes = port.access != PortAccess::read;
  const bool image = port.kind == ResourceKind::image;
  switch (port.usage) {
    case PortUsage::sampled: return {shader, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT, 0, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
    case PortUsage::storage:
      return {shader, reads ? VK_ACCESS_2_SHADER_STORAGE_READ_BIT : 0, writes ? VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT : 0,
              image ? VK_IMAGE_LAYOUT_GENERAL : VK_IMAGE_LAYOUT_UNDEFINED};
    case PortUsage::color_attachment:
      return {VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, reads ? VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT : 0,
              VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    case PortUsage::depth_attachment:
      return {VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
              VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT, writes ? VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT : 0,
              writes ? VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL : VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL};
    case PortUsage::transfer_src:
      return {VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT, 0,
              image ? VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL : VK_IMAGE_LAYOUT_UNDEFINED};
    case PortUsage::transfer_dst:
      return {VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, 0, VK_ACCESS_2_TRANSFER_WRITE_BIT,
              image ? VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL : VK_IMAGE_LAYOUT_UNDEFINED};
    case PortUsage::uniform: return {shader, VK_ACCESS_2_UNIFORM_READ_BIT, 0, VK_IMAGE_LAYOUT_UNDEFINED};
    case PortUsage::indirect:
      return {VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT, VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT, 0, VK_IMAGE_LAYOUT_UNDEFINED};
  }
  return {};
}

void add_usage(PlannedResource& r, PortUsage usage) {
  if (r.kind == ResourceKind::image) {
    switch (usage) {
      case PortUsage::sampled: r.image_usage |= VK_IMAGE_USAGE_SAMPLED_BIT; break;
      case PortUsage::storage: r.image_usage |= VK_IMAGE_USAGE_STORAGE_BIT; break;
      case PortUsage::color_attachment: r.image_usage |= VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT; break;
      case PortUsage::depth_attachment: r.image_usage |= VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT; break;
      case PortUsage::transfer_src: r.image_usage |= VK_IMAGE_USAGE_TRANSFER_SRC_BIT; break;
      case PortUsage::transfer_dst: r.image_usage |= VK_IMAGE_USAGE_TRANSFER_DST_BIT; break;
      case PortUsage::uniform:
      case PortUsage::indirect: break;
    }
  } else {
    switch (usage) {
      case PortUsage::storage: r.buffer_usage |= VK_BUFFER_USAGE_STORAGE_BUFFER_BIT; break;
      case PortUsage::uniform: r.buffer_usage |= VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT; break;
      case PortUsage::indirect: r.buffer_usage |= VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT; break;
      case PortUsage::transfer_src: r.buffer_usage |= VK_BUFFER_USAGE_TRANSFER_SRC_BIT; break;
      case PortUsage::transfer_dst: r.buffer_usage |= VK_BUFFER_USAGE_TRANSFER_DST_BIT; break;
      case PortUsage::sampled:
      case PortUsage::color_attachment:
      case PortUsage::depth_attachment: break;
    }
  }
}

struct Binding {
  const PortDecl* port;
  uint32_t resource;
  std::string pointer;
};

class Compiler {
 public:
  Compiler(const GraphDesc& graph, const PassRegistry& registry, const CompileOptions& options)
      : graph_(graph), registry_(registry), options_(options) {}

  Plan run() {
    plan_.graph_name = graph_.name;
    plan_.graph_path = graph_.doc.path();
    plan_.output_width = options_.output_width;
    plan_.output_height = options_.output_height;
    decide_enabled_and_fallbacks();
    size_resources();
    resolve_passes();
    build_edges();
    find_cycle();
    check_writer_order();
    cull_and_order();
    compute_lifetimes_and_usage();
    check_extent_groups();
    place_memory();
    record_barriers();
    return std::move(plan_);
  }

 private:
  const GraphDesc& graph_;
  const PassRegistry& registry_;
  const CompileOptions& options_;
  Plan plan_;

  // Per pass of the graph file (index = file order); disabled passes keep a slot with decl == nullptr.
  struct Node {
    const PassDesc* desc = nullptr;
    const PassTypeDecl* decl = nullptr;
    nlohmann::json params;
    std::vector<Binding> bindings;
    std::vector<uint32_t> successors;
    std::vector<uint32_t> predecessors;
  };
  std::vector<Node> nodes_;
  std::vector<std::vector<uint32_t>> writers_;  // per resource, node indices
  std::vector<std::vector<uint32_t>> readers_;
  std::vector<bool> enabled_;                    // per pass of the file
  std::map<std::string, std::string> redirect_;  // resource no enabled pass writes -> its fallback

  // ---- enabled passes and fallbacks -----------------------------------------------------------

  std::string redirected(const std::string& name) const {
    auto it = redirect_.find(name);
    return it == redirect_.end() ? name : it->second;
  }

  void decide_enabled_and_fallbacks() {
    std::set<std::string> written;
    for (const auto& pass : graph_.passes) {
      const bool on = evaluate(pass.enabled, pass.pointer + "/enabled") != 0.0;
      enabled_.push_back(on);
      if (!on) {
        plan_.disabled.push_back(pass.name);
        continue;
      }
      for (const auto& [port, resource] : pass.outputs) written.insert(resource);
    }
    for (const auto& r : graph_.resources) {
      if (r.fallback_to_nothing && !written.count(r.name)) {
        redirect_[r.name] = "";
        plan_.fallbacks[r.name] = "";
        continue;
      }
      if (r.fallback.empty() || written.count(r.name)) continue;
      // Follow the chain to a resource that is written (or has no fallback of its own).
      std::string target = r.name;
      std::vector<std::string> chain{target};
      while (true) {
        const ResourceDesc* d = graph_.find_resource(target);
        if (d->fallback.empty() || written.count(target)) break;
        const ResourceDesc* next = graph_.find_resource(d->fallback);
        if (!next) {
          throw graph_.error(d->pointer + "/fallback", "fallback '" + d->fallback + "' of '" + d->name +
                                                           "' is not a resource of this graph" +
                                                           did_you_mean(d->fallback, resource_names_of_file()));
        }
        if (next->kind != d->kind || (d->kind == ResourceKind::image && next->format != d->format)) {
          throw graph_.error(d->pointer + "/fallback", "fallback '" + next->name + "' of '" + d->name + "' must have the same " +
                                                           (next->kind != d->kind ? "type" : "format"));
        }
        if (std::find(chain.begin(), chain.end(), next->name) != chain.end()) {
          std::string cycle;
          for (const auto& c : chain) cycle += c + " -> ";
          throw graph_.error(d->pointer + "/fallback", "fallback cycle: " + cycle + next->name);
        }
        target = next->name;
        chain.push_back(target);
      }
      if (target != r.name) {
        redirect_[r.name] = target;
        plan_.fallbacks[r.name] = target;
      }
    }
  }

  std::vector<std::string> resource_names_of_file() const {
    std::vector<std::string> names;
    for (const auto& r : graph_.resources) names.push_back(r.name);
    return names;
  }

  // ---- parameters and expressions -------------------------------------------------------------

  ExpressionScope scope() const {
    ExpressionScope s;
    s.known_names = {"output.width", "output.height"};
    for (const auto& [name, value] : options_.scene_values) s.known_names.push_back(name);
    for (const auto& p : graph_.parameters) {
      if (p.decl.type != ParamType::choice) s.known_names.push_back(p.decl.name);
    }
    s.lookup = [this](std::string_view name) -> std::optional<double> {
      if (name == "output.width") return options_.output_width;
      if (name == "output.height") return options_.output_height;
      if (auto it = options_.scene_values.find(std::string(name)); it != options_.scene_values.end()) return it->second;
      const GraphParameter* p = graph_.find_parameter(name);
      if (!p || p->decl.type == ParamType::choice) return std::nullopt;
      if (p->value.is_boolean()) return p->value.get<bool>() ? 1.0 : 0.0;
      return p->value.get<double>();
    };
    return s;
  }

  // Every value an expression gives is finite: the sizes, counts and flags computed from it are
  // converted to integers, which is undefined for NaN and infinities.
  double evaluate(const std::string& text, const std::string& pointer) const {
    double v = 0;
    try {
      v = evaluate_expression(text, scope());
    } catch (const std::invalid_argument& e) {
      throw graph_.error(pointer, e.what());
    }
    if (!std::isfinite(v))
      throw graph_.error(pointer, "\"" + text + "\" evaluates to " + JsonReader::format_number(v) + ", not a finite number");
    return v;
  }

  uint32_t extent(const std::string& text, const std::string& pointer, const char* what, const std::string& resource) const {
    double v = std::floor(evaluate(text, pointer));
    if (v < 1) {
      throw graph_.error(pointer, "the " + std::string(what) + " of '" + resource + "' evaluates to " + JsonReader::format_number(v) +
                                      "; it must be at least 1");
    }
    if (v > options_.limits.max_image_dimension_2d) {
      throw graph_.error(pointer, "the " + std::string(what) + " of '" + resource + "' evaluates to " + JsonReader::format_number(v) +
                                      ", above the device limit of " + std::to_string(options_.limits.max_image_dimension_2d) +
                                      " (maxImageDimension2D)");
    }
    return static_cast<uint32_t>(v);
  }

  void size_resources() {
    for (const auto& desc : graph_.resources) {
      PlannedResource r;
      r.name = desc.name;
      r.pointer = desc.pointer;
      r.kind = desc.kind;
      r.format = desc.format;
      if (desc.kind == ResourceKind::image) {
        r.width = extent(desc.width, desc.pointer + "/width", "width", desc.name);
        r.height = extent(desc.height, desc.pointer + "/height", "height", desc.name);
        double mips = std::floor(evaluate(desc.mips, desc.pointer + "/mips"));
        uint32_t max_mips = static_cast<uint32_t>(std::floor(std::log2(std::max(r.width, r.height)))) + 1;
        if (mips < 1 || mips > max_mips) {
          throw graph_.error(desc.pointer + "/mips", "'" + desc.name + "' asks for " + JsonReader::format_number(mips) + " mip levels; a " +
                                                         std::to_string(r.width) + "x" + std::to_string(r.height) + " image has 1 to " +
                                                         std::to_string(max_mips));
        }
        r.mips = static_cast<uint32_t>(mips);
        double layers = std::floor(evaluate(desc.layers, desc.pointer + "/layers"));
        if (layers < 1 || layers > kMaxImageLayers) {
          throw graph_.error(desc.pointer + "/layers", "'" + desc.name + "' asks for " + JsonReader::format_number(layers) +
                                                           " array layers; an image has 1 to " + std::to_string(kMaxImageLayers));
        }
        r.layers = static_cast<uint32_t>(layers);
        if (r.layers > 1 && r.format != Format::r32f) {
          throw graph_.error(desc.pointer + "/layers",
                             "'" + desc.name + "' is " + format_info(r.format).name + "; only r32f images can have layers");
        }
      } else {
        double bytes = std::floor(evaluate(desc.size, desc.pointer + "/size"));
        if (bytes < 4) {
          throw graph_.error(desc.pointer + "/size", "the size of buffer '" + desc.name + "' evaluates to " +
                                                         JsonReader::format_number(bytes) + " bytes; it must be at least 4");
        }
        if (bytes > static_cast<double>(options_.limits.max_buffer_size)) {
          throw graph_.error(desc.pointer + "/size",
                             "buffer '" + desc.name + "' would be " + JsonReader::format_number(std::floor(bytes / 1048576.0)) + " MiB" +
                                 ", above the largest buffer allowed (" + mib(options_.limits.max_buffer_size) + ")");
        }
        r.buffer_size = static_cast<uint64_t>(bytes);
      }
      plan_.resources.push_back(std::move(r));
    }
    for (size_t i = 0; i < graph_.outputs.size(); ++i) {
      int index = plan_.find_resource(redirected(graph_.outputs[i]));
      std::string pointer = "/outputs/" + std::to_string(i);
      if (index < 0) {
        throw graph_.error(pointer, "output '" + graph_.outputs[i] + "' is not a resource of this graph" +
                                        did_you_mean(graph_.outputs[i], resource_names()));
      }
      auto& r = plan_.resources[static_cast<size_t>(index)];
      if (r.kind != ResourceKind::image) throw graph_.error(pointer, "output '" + r.name + "' is a buffer; outputs are images");
      if (r.output) throw graph_.error(pointer, "output '" + r.name + "' is listed twice");
      r.output = true;
      r.transient = false;
      plan_.outputs.push_back(static_cast<uint32_t>(index));
    }
    for (const auto& name : options_.retained) {
      if (auto it = redirect_.find(name); it != redirect_.end() && it->second.empty()) continue;  // nothing writes it for this scene
      int index = plan_.find_resource(redirected(name));
      if (index < 0) {
        throw InputError(graph_.doc.path() + ": no resource named '" + name + "' to keep" + did_you_mean(name, resource_names()));
      }
      plan_.resources[static_cast<size_t>(index)].transient = false;
    }
  }

  std::vector<std::string> resource_names() const {
    std::vector<std::string> names;
    for (const auto& r : graph_.resources) names.push_back(r.name);
    return names;
  }

  nlohmann::json resolve_params(const PassDesc& pass, const PassTypeDecl& decl) const {
    std::vector<std::string> declared;
    for (const auto& p : decl.params) declared.push_back(p.name);
    std::vector<std::string> graph_params;
    for (const auto& p : graph_.parameters) graph_params.push_back(p.decl.name);

    nlohmann::json out = nlohmann::json::object();
    for (const auto& [key, raw] : pass.params.items()) {
      std::string pointer = json_pointer_append(pass.pointer + "/params", key);
      const ParamDecl* param = decl.find_param(key);
      if (!param) {
        throw graph_.error(pointer, "pass type '" + decl.type + "' has no parameter '" + key + "'" + did_you_mean(key, declared));
      }
      nlohmann::json value = raw;
      std::string via;
      if (raw.is_string() && raw.get<std::string>().starts_with('$')) {
        std::string name = raw.get<std::string>().substr(1);
        const GraphParameter* gp = graph_.find_parameter(name);
        if (!gp) throw graph_.error(pointer, "no graph parameter '" + name + "'" + did_you_mean(name, graph_params));
        value = gp->value;
        via = " (through graph parameter '" + name + "')";
      }
      std::string problem = check_param_value(*param, value);
      if (!problem.empty()) throw graph_.error(pointer, "parameter '" + key + "' of pass '" + pass.name + "' " + problem + via);
      out[key] = value;
    }
    for (const auto& p : decl.params) {
      if (!out.contains(p.name)) out[p.name] = p.default_value;
    }
    return out;
  }

  void bind_section(Node& node, const std::map<std::string, std::string>& section, bool outputs) {
    const PassDesc& pass = *node.desc;
    const PassTypeDecl& decl = *node.decl;
    const char* section_name = outputs ? "outputs" : "inputs";
    std::vector<std::string> port_names;
    for (const auto& p : decl.ports) port_names.push_back(p.name);
    for (const auto& [port_name, resource_name] : section) {
      std::string pointer = json_pointer_append(pass.pointer + "/" + section_name, port_name);
      const PortDecl* port = decl.find_port(port_name);
      if (!port) {
        throw graph_.error(pointer, "pass type '" + decl.type + "' has no port '" + port_name + "'" + did_you_mean(port_name, port_names));
      }
      bool port_writes = port->access != PortAccess::read;
      if (port_writes != outputs) {
        throw graph_.error(pointer, std::string("port '") + port_name + "' of pass type '" + decl.type + "' is an " +
                                        (port_writes ? "output" : "input") + "; list it under \"" + (port_writes ? "outputs" : "inputs") +
                                        "\"");
      }
      const std::string source = outputs ? resource_name : redirected(resource_name);
      if (source.empty()) {  // "fallback": null and nothing writes it
        if (port->optional) continue;
        throw graph_.error(pointer, "input '" + port_name + "' of pass '" + pass.name + "' reads '" + resource_name +
                                        "', which no enabled pass writes and whose fallback is null; only optional inputs may");
      }
      int index = plan_.find_resource(source);
      if (index < 0) {
        throw graph_.error(pointer, "no resource named '" + resource_name + "'" + did_you_mean(resource_name, resource_names()));
      }
      const PlannedResource& r = plan_.resources[static_cast<size_t>(index)];
      if (r.kind != port->kind) {
        throw graph_.error(pointer, "port '" + port_name + "' of pass '" + pass.name + "' takes " +
                                        (port->kind == ResourceKind::image ? "an image" : "a buffer") + ", but '" + r.name + "' is " +
                                        (r.kind == ResourceKind::image ? "an image" : "a buffer"));
      }
      if (r.kind == ResourceKind::image) check_format(*port, r, pass, pointer);
      for (const auto& other : node.bindings) {
        if (other.resource == static_cast<uint32_t>(index)) {
          throw graph_.error(pointer, "pass '" + pass.name + "' binds '" + r.name + "' to two ports ('" + other.port->name + "' and '" +
                                          port_name + "'); use one read_write port instead");
        }
      }
      // An optional output nobody asks for (a debug view such as the caustic-map levels) stays
      // unbound, so the pass skips the work and the resource takes no memory; one the pass samples
      // itself (scratch, such as refraction_layers' front_tint) is bound wherever it is connected.
      if (outputs && port->optional && !port->also_sampled && !wanted(resource_name)) continue;
      node.bindings.push_back({port, static_cast<uint32_t>(index), pointer});
    }
  }

  // Whether an enabled pass reads `resource`, it is a graph output, or it is kept (--dump, the viewer).
  bool wanted(const std::string& resource) const {
    if (std::count(graph_.outputs.begin(), graph_.outputs.end(), resource) || options_.retained.count(resource)) return true;
    for (size_t i = 0; i < graph_.passes.size(); ++i) {
      if (!enabled_[i]) continue;
      for (const auto& [port, read] : graph_.passes[i].inputs) {
        if (read == resource) return true;
      }
    }
    return false;
  }

  void check_format(const PortDecl& port, const PlannedResource& r, const PassDesc& pass, const std::string& pointer) const {
    const FormatInfo& info = format_info(r.format);
    if (!port.formats.empty() && std::find(port.formats.begin(), port.formats.end(), r.format) == port.formats.end()) {
      std::string accepted;
      for (Format f : port.formats) accepted += std::string(accepted.empty() ? "" : ", ") + format_info(f).name;
      throw graph_.error(pointer, "format mismatch: port '" + port.name + "' of pass '" + pass.name + "' accepts " + accepted + ", but '" +
                                      r.name + "' is " + info.name);
    }
    if (port.kind == ResourceKind::image && r.layers != port.layers) {
      throw graph_.error(pointer, "layer mismatch: port '" + port.name + "' of pass '" + pass.name + "' takes an image of " +
                                      std::to_string(port.layers) + (port.layers == 1 ? " layer" : " array layers") + ", but '" + r.name +
                                      "' has " + std::to_string(r.layers) + " (its \"layers\")");
    }
    if (port.usage == PortUsage::storage && std::string_view(info.glsl_qualifier).empty()) {
      throw graph_.error(pointer, "'" + r.name + "' (" + info.name + ") cannot be a storage image (port '" + port.name + "')");
    }
    if (port.usage == PortUsage::color_attachment && info.depth) {
      throw graph_.error(pointer, "'" + r.name + "' is a depth format and cannot be a color attachment (port '" + port.name + "')");
    }
    if (port.usage == PortUsage::depth_attachment && !info.depth) {
      throw graph_.error(pointer, "'" + r.name + "' (" + info.name + ") is not a depth format (port '" + port.name + "')");
    }
  }

  void resolve_passes() {
    std::vector<std::string> type_names = registry_.names();
    nodes_.resize(graph_.passes.size());
    for (size_t i = 0; i < graph_.passes.size(); ++i) {
      const PassDesc& pass = graph_.passes[i];
      Node& node = nodes_[i];
      node.desc = &pass;
      const PassTypeDecl* decl = registry_.find(pass.type);
      if (!decl) {
        throw graph_.error(pass.pointer + "/type", "unknown pass type '" + pass.type + "'" + did_you_mean(pass.type, type_names));
      }
      if (!enabled_[i]) continue;
      node.decl = decl;
      node.params = resolve_params(pass, *decl);
      bind_section(node, pass.inputs, false);
      bind_section(node, pass.outputs, true);
      for (const auto& port : decl->ports) {
        if (port.optional) continue;
        bool bound = std::any_of(node.bindings.begin(), node.bindings.end(), [&](const Binding& b) { return b.port == &port; });
        if (!bound) {
          bool input = port.access == PortAccess::read;
          throw graph_.error(pass.pointer, std::string(input ? "input" : "output") + " '" + port.name + "' of pass '" + pass.name +
                                               "' (type " + decl->type + ") is not connected");
        }
      }
    }
  }

  // ---- dependencies --------------------------------------------------------------------------

  int node_index(std::string_view name) const {
    for (size_t i = 0; i < nodes_.size(); ++i) {
      if (nodes_[i].desc->name == name) return static_cast<int>(i);
    }
    return -1;
  }

  void add_edge(uint32_t from, uint32_t to) {
    auto& s = nodes_[from].successors;
    if (std::find(s.begin(), s.end(), to) != s.end()) return;
    s.push_back(to);
    nodes_[to].predecessors.push_back(from);
  }

  void build_edges() {
    writers_.assign(plan_.resources.size(), {});
    readers_.assign(plan_.resources.size(), {});
    for (uint32_t i = 0; i < nodes_.size(); ++i) {
      for (const auto& b : nodes_[i].bindings) {
        (b.port->access == PortAccess::read ? readers_ : writers_)[b.resource].push_back(i);
      }
    }
    for (uint32_t i = 0; i < nodes_.size(); ++i) {
      if (!nodes_[i].decl) continue;
      for (const auto& b : nodes_[i].bindings) {
        if (b.port->access != PortAccess::read || !writers_[b.resource].empty()) continue;
        std::string why = "input '" + b.port->name + "' of pass '" + nodes_[i].desc->name + "' reads '" + plan_.resources[b.resource].name +
                          "', which no pass writes";
        for (const auto& other : nodes_) {
          if (other.decl) continue;
          for (const auto& [port, resource] : other.desc->outputs) {
            if (resource == plan_.resources[b.resource].name) why += " (pass '" + other.desc->name + "' that writes it is disabled)";
          }
        }
        throw graph_.error(b.pointer, why);
      }
    }
    for (uint32_t r = 0; r < plan_.resources.size(); ++r) {
      for (uint32_t w : writers_[r]) {
        for (uint32_t reader : readers_[r]) add_edge(w, reader);
      }
    }
    std::vector<std::string> names;
    for (const auto& n : nodes_) names.push_back(n.desc->name);
    for (uint32_t i = 0; i < nodes_.size(); ++i) {
      if (!nodes_[i].decl) continue;
      const auto& after = nodes_[i].desc->after;
      for (size_t j = 0; j < after.size(); ++j) {
        std::string pointer = nodes_[i].desc->pointer + "/after/" + std::to_string(j);
        int other = node_index(after[j]);
        if (other < 0) throw graph_.error(pointer, "no pass named '" + after[j] + "'" + did_you_mean(after[j], names));
        if (static_cast<uint32_t>(other) == i) throw graph_.error(pointer, "pass '" + after[j] + "' cannot come after itself");
        if (!nodes_[static_cast<size_t>(other)].decl) continue;  // ordering against a disabled pass is moot
        add_edge(static_cast<uint32_t>(other), i);
      }
    }
  }

  void find_cycle() const {
    enum Mark : uint8_t { unseen, open, done };
    std::vector<Mark> mark(nodes_.size(), unseen);
    std::vector<uint32_t> path;
    // Iterative DFS: the stack holds (node, next successor index) so deep graphs cannot overflow.
    for (uint32_t start = 0; start < nodes_.size(); ++start) {
      if (mark[start] != unseen || !nodes_[start].decl) continue;
      std::vector<std::pair<uint32_t, size_t>> stack{{start, 0}};
      mark[start] = open;
      path.assign(1, start);
      while (!stack.empty()) {
        auto& [node, next] = stack.back();
        if (next < nodes_[node].successors.size()) {
          uint32_t succ = nodes_[node].successors[next++];
          if (mark[succ] == open) {
            auto begin = std::find(path.begin(), path.end(), succ);
            std::string text;
            for (auto it = begin; it != path.end(); ++it) text += nodes_[*it].desc->name + " -> ";
            text += nodes_[succ].desc->name;
            throw graph_.error(nodes_[succ].desc->pointer, "cycle: " + text);
          }
          if (mark[succ] == unseen) {
            mark[succ] = open;
            path.push_back(succ);
            stack.emplace_back(succ, 0);
          }
        } else {
          mark[node] = done;
          path.pop_back();
          stack.pop_back();
        }
      }
    }
  }

  bool reaches(uint32_t from, uint32_t to) const {
    std::vector<bool> seen(nodes_.size(), false);
    std::vector<uint32_t> stack{from};
    while (!stack.empty()) {
      uint32_t n = stack.back();
      stack.pop_back();
      if (n == to) return true;
      for (uint32_t s : nodes_[n].successors) {
        if (!seen[s]) {
          seen[s] = true;
          stack.push_back(s);
        }
      }
    }
    return false;
  }

  void check_writer_order() const {
    for (uint32_t r = 0; r < plan_.resources.size(); ++r) {
      const auto& w = writers_[r];
      for (size_t a = 0; a < w.size(); ++a) {
        for (size_t b = a + 1; b < w.size(); ++b) {
          if (!nodes_[w[a]].decl || !nodes_[w[b]].decl) continue;
          if (reaches(w[a], w[b]) || reaches(w[b], w[a])) continue;
          const auto& second = *nodes_[w[b]].desc;
          std::string pointer = second.pointer;
          for (const auto& binding : nodes_[w[b]].bindings) {
            if (binding.resource == r) pointer = binding.pointer;
          }
          throw graph_.error(pointer, "'" + plan_.resources[r].name + "' is written by passes '" + nodes_[w[a]].desc->name + "' and '" +
                                          second.name + "' with no order between them; add \"after\": [\"" + nodes_[w[a]].desc->name +
                                          "\"] to pass '" + second.name + "'");
        }
      }
    }
  }

  std::vector<uint32_t> order_;  // node indices in execution order

  // The execution order: of the orders the edges allow, one with the least peak of live transient
  // memory (the lifetimes, and so what aliasing can share, follow from the order), found by a
  // search over the sets of passes already run; among the best, file order. Sizes are the
  // device-independent estimate, so that every device gets the same order. Graphs with more
  // passes than the search takes keep file order.
  std::vector<uint32_t> least_memory_order(const std::vector<bool>& live) const {
    constexpr size_t kMaxSearchedPasses = 16;
    std::vector<uint32_t> nodes;
    std::vector<int> index(nodes_.size(), -1);
    for (uint32_t i = 0; i < nodes_.size(); ++i) {
      if (!live[i]) continue;
      index[i] = static_cast<int>(nodes.size());
      nodes.push_back(i);
    }
    if (nodes.size() > kMaxSearchedPasses) {
      // Kahn's algorithm, the ready pass that comes first in the file: the plan is stable under
      // unrelated edits.
      std::vector<uint32_t> pending(nodes_.size(), 0), order;
      for (uint32_t i : nodes) {
        for (uint32_t s : nodes_[i].successors) pending[s] += live[s] ? 1 : 0;
      }
      std::priority_queue<uint32_t, std::vector<uint32_t>, std::greater<>> ready;
      for (uint32_t i : nodes) {
        if (pending[i] == 0) ready.push(i);
      }
      while (!ready.empty()) {
        uint32_t n = ready.top();
        ready.pop();
        order.push_back(n);
        for (uint32_t s : nodes_[n].successors) {
          if (live[s] && --pending[s] == 0) ready.push(s);
        }
      }
      return order;
    }
    std::vector<uint32_t> before(nodes.size(), 0);  // bit j: nodes[j] must run first
    for (uint32_t k = 0; k < nodes.size(); ++k) {
      for (uint32_t p : nodes_[nodes[k]].predecessors) {
        if (live[p]) before[k] |= 1u << index[p];
      }
    }
    struct Use {
      uint32_t passes;  // bit k: nodes[k] binds the resource
      uint64_t bytes;
    };
    std::vector<Use> uses;
    for (uint32_t r = 0; r < plan_.resources.size(); ++r) {
      if (!plan_.resources[r].transient) continue;
      uint32_t passes = 0;
      for (uint32_t k = 0; k < nodes.size(); ++k) {
        for (const auto& b : nodes_[nodes[k]].bindings) passes |= b.resource == r ? 1u << k : 0u;
      }
      if (passes != 0) uses.push_back({passes, estimate_memory_requirements(plan_.resources[r]).size});
    }
    // Bytes live while nodes[k] runs after the passes in `done`: what it binds, and what was used
    // before and is still to be used after.
    auto live_bytes = [&](uint32_t done, uint32_t k) {
      const uint32_t after = done | 1u << k;
      uint64_t bytes = 0;
      for (const Use& u : uses) {
        if ((u.passes >> k & 1u) != 0 || ((u.passes & done) != 0 && (u.passes & ~after) != 0)) bytes += u.bytes;
      }
      return bytes;
    };
    const uint32_t all = (1u << nodes.size()) - 1u;
    constexpr uint64_t kUnknown = ~uint64_t{0};
    std::vector<uint64_t> least_peak_after(size_t{1} << nodes.size(), kUnknown);  // of the passes still to run
    auto peak_from = [&](auto& self, uint32_t done) -> uint64_t {
      if (done == all) return 0;
      uint64_t& memo = least_peak_after[done];
      if (memo != kUnknown) return memo;
      uint64_t best = kUnknown;
      for (uint32_t k = 0; k < nodes.size(); ++k) {
        if ((done >> k & 1u) == 0 && (before[k] & ~done) == 0)
          best = std::min(best, std::max(live_bytes(done, k), self(self, done | 1u << k)));
      }
      return memo = best;
    };
    // Kahn's rule (the ready pass first in the file) among the passes that keep the least peak.
    const uint64_t least_peak = peak_from(peak_from, 0);
    std::vector<uint32_t> order;
    for (uint32_t done = 0; done != all;) {
      for (uint32_t k = 0; k < nodes.size(); ++k) {
        if ((done >> k & 1u) == 0 && (before[k] & ~done) == 0 &&
            std::max(live_bytes(done, k), peak_from(peak_from, done | 1u << k)) <= least_peak) {
          order.push_back(nodes[k]);
          done |= 1u << k;
          break;
        }
      }
    }
    return order;
  }

  void cull_and_order() {
    std::vector<bool> live(nodes_.size(), false);
    std::vector<uint32_t> stack;
    auto keep = [&](uint32_t n) {
      if (!live[n]) {
        live[n] = true;
        stack.push_back(n);
      }
    };
    for (uint32_t i = 0; i < nodes_.size(); ++i) {
      if (!nodes_[i].decl) continue;
      if (nodes_[i].decl->side_effects) keep(i);
      for (const auto& b : nodes_[i].bindings) {
        if (b.port->access != PortAccess::read && plan_.resources[b.resource].output) keep(i);
      }
    }
    for (size_t i = 0; i < graph_.outputs.size(); ++i) {
      uint32_t r = plan_.outputs[i];
      bool written = std::any_of(writers_[r].begin(), writers_[r].end(), [&](uint32_t w) { return nodes_[w].decl != nullptr; });
      if (!written)
        throw graph_.error("/outputs/" + std::to_string(i), "output '" + plan_.resources[r].name + "' is not written by any enabled pass");
    }
    while (!stack.empty()) {
      uint32_t n = stack.back();
      stack.pop_back();
      for (uint32_t p : nodes_[n].predecessors) keep(p);
    }
    order_ = least_memory_order(live);
    for (uint32_t i = 0; i < nodes_.size(); ++i) {
      if (nodes_[i].decl && !live[i]) plan_.culled.push_back(nodes_[i].desc->name);
    }
    std::map<int, std::string> unlit;  // light -> the passes that need it to be a spot light
    for (uint32_t n : order_) {
      const Node& node = nodes_[n];
      PlannedPass pass;
      pass.name = node.desc->name;
      pass.type = node.decl->type;
      pass.pointer = node.desc->pointer;
      pass.decl = node.decl;
      pass.params = node.params;
      for (const auto& b : node.bindings) pass.ports[b.port->name] = b.resource;
      if (pass.decl->uses_ray_queries && pass.decl->uses_ray_queries(pass.params)) {
        if (!options_.ray_queries) {
          throw graph_.error(pass.pointer, "pass '" + pass.name + "' (" + pass.type +
                                               ") traces exact paths with ray queries (VK_KHR_ray_query, VK_KHR_acceleration_structure), "
                                               "and this device lacks " +
                                               options_.ray_queries_missing + "; " + pass.decl->ray_query_alternative);
        }
        plan_.ray_query_passes.push_back(pass.name);
      }
      if (pass.decl->uses_light_view && pass.decl->uses_light_view(pass.params)) {
        const int light = pass.params.value("light", 0);
        const auto view = options_.scene_values.find("scene.light" + std::to_string(light) + ".view");
        if (view != options_.scene_values.end() && view->second == 0.0) unlit[light] += (unlit[light].empty() ? "" : ", ") + pass.name;
      }
      plan_.passes.push_back(std::move(pass));
    }
    for (const auto& [light, names] : unlit) {
      plan_.warnings.push_back("light " + std::to_string(light) +
                               " is a point light, which has no light view: only spot and directional lights cast shadows "
                               "and caustics (a point light's cube map is not implemented), so the passes that draw from its "
                               "view add nothing to the picture (" +
                               names + "); give the scene a spot or directional light, or use a graph without them");
    }
  }

  void compute_lifetimes_and_usage() {
    for (uint32_t i = 0; i < order_.size(); ++i) {
      for (const auto& b : nodes_[order_[i]].bindings) {
        PlannedResource& r = plan_.resources[b.resource];
        if (r.first_use == kNoPass) r.first_use = i;
        r.last_use = i;
        add_usage(r, b.port->usage);
        if (b.port->also_sampled) add_usage(r, PortUsage::sampled);
        if (r.kind == ResourceKind::buffer && b.port->usage == PortUsage::storage &&
            r.buffer_size > options_.limits.max_storage_buffer_range) {
          throw graph_.error(b.pointer, "buffer '" + r.name + "' is " + mib(r.buffer_size) +
                                            ", above this device's maxStorageBufferRange (" +
                                            mib(options_.limits.max_storage_buffer_range) + ") for storage port '" + b.port->name + "'");
        }
      }
    }
    for (auto& r : plan_.resources) {
      if (r.transient) continue;  // read back after the frame
      if (r.kind == ResourceKind::image)
        r.image_usage |= VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
      else
        r.buffer_usage |= VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
    }
  }

  void check_extent_groups() const {
    for (uint32_t n : order_) {
      const auto& bindings = nodes_[n].bindings;
      for (size_t a = 0; a < bindings.size(); ++a) {
        for (size_t b = a + 1; b < bindings.size(); ++b) {
          const auto& pa = *bindings[a].port;
          const auto& pb = *bindings[b].port;
          if (pa.extent_group.empty() || pa.extent_group != pb.extent_group) continue;
          const auto& ra = plan_.resources[bindings[a].resource];
          const auto& rb = plan_.resources[bindings[b].resource];
          if (ra.width == rb.width && ra.height == rb.height) continue;
          throw graph_.error(bindings[b].pointer, "extent mismatch in pass '" + nodes_[n].desc->name + "': '" + rb.name + "' (port '" +
                                                      pb.name + "') is " + std::to_string(rb.width) + "x" + std::to_string(rb.height) +
                                                      " but '" + ra.name + "' (port '" + pa.name + "') is " + std::to_string(ra.width) +
                                                      "x" + std::to_string(ra.height));
        }
      }
    }
  }

  // ---- memory --------------------------------------------------------------------------------

  // Places the transient resources in `order`, each at the first gap between its live neighbours
  // that fits (or the tightest such gap); returns the blocks' total size.
  uint64_t place_in_order(const std::vector<uint32_t>& order, bool tightest) {
    plan_.blocks.clear();
    std::vector<uint32_t> placed;
    for (uint32_t index : order) {
      PlannedResource& r = plan_.resources[index];
      uint32_t block = kNoBlock;
      // One block per memory type and alignment: with equal alignments and sizes rounded to them,
      // every gap search lands at or below the sum of the live neighbours' sizes, so aliasing can
      // never cost more memory than separate allocations.
      for (uint32_t b = 0; b < plan_.blocks.size(); ++b) {
        if (plan_.blocks[b].type_bits == r.memory.type_bits && plan_.blocks[b].alignment == r.memory.alignment) block = b;
      }
      if (block == kNoBlock || !options_.alias) {
        block = static_cast<uint32_t>(plan_.blocks.size());
        plan_.blocks.push_back({0, r.memory.alignment, r.memory.type_bits});
      }
      std::vector<std::pair<uint64_t, uint64_t>> busy;  // [begin, end) of live neighbours in this block
      for (uint32_t other : placed) {
        const PlannedResource& o = plan_.resources[other];
        if (o.block != block) continue;
        if (o.first_use <= r.last_use && r.first_use <= o.last_use) busy.emplace_back(o.offset, o.offset + o.memory.size);
      }
      std::sort(busy.begin(), busy.end());
      auto align = [&](uint64_t v) { return (v + r.memory.alignment - 1) / r.memory.alignment * r.memory.alignment; };
      constexpr uint64_t kNoOffset = ~uint64_t{0};
      uint64_t offset = kNoOffset, free_from = 0, best_gap = ~uint64_t{0};
      for (const auto& [begin, end] : busy) {
        if (begin >= free_from + r.memory.size && (!tightest || begin - free_from < best_gap)) {
          best_gap = begin - free_from;
          offset = free_from;
          if (!tightest) break;
        }
        free_from = std::max(free_from, align(end));
      }
      if (offset == kNoOffset) offset = free_from;
      r.block = block;
      r.offset = offset;
      plan_.blocks[block].size = std::max(plan_.blocks[block].size, offset + r.memory.size);
      placed.push_back(index);
    }
    uint64_t total = 0;
    for (const auto& b : plan_.blocks) total += b.size;
    return total;
  }

  void place_memory() {
    std::vector<uint32_t> transient;
    for (uint32_t i = 0; i < plan_.resources.size(); ++i) {
      PlannedResource& r = plan_.resources[i];
      if (!r.used()) continue;
      r.memory = options_.memory_requirements(r);
      assert(r.memory.alignment > 0 && (r.memory.alignment & (r.memory.alignment - 1)) == 0);
      r.memory.size = (r.memory.size + r.memory.alignment - 1) & ~(r.memory.alignment - 1);
      if (r.transient) {
        transient.push_back(i);
        plan_.transient_bytes_unaliased += r.memory.size;
      } else {
        plan_.persistent_bytes += r.memory.size;
      }
    }
    for (uint32_t at = 0; at < order_.size(); ++at) {
      uint64_t live = 0;
      for (uint32_t index : transient) {
        const PlannedResource& r = plan_.resources[index];
        live += r.first_use <= at && at <= r.last_use ? r.memory.size : 0;
      }
      plan_.transient_bytes_lifetime_bound = std::max(plan_.transient_bytes_lifetime_bound, live);
    }
    // Greedy placement is not optimal, so a few orders and both gap rules are tried and the least
    // memory kept: largest first (big resources claim offset 0 and smaller ones fill the gaps
    // between lifetimes), longest-lived first, earliest first; the first gap that fits or the
    // tightest one.
    auto by = [&](auto key) {
      std::vector<uint32_t> order = transient;
      std::stable_sort(order.begin(), order.end(),
                       [&](uint32_t x, uint32_t y) { return key(plan_.resources[x]) > key(plan_.resources[y]); });
      return order;
    };
    const std::vector<std::vector<uint32_t>> orders{
        by([](const PlannedResource& r) { return r.memory.size; }),
        by([](const PlannedResource& r) { return std::make_pair(r.last_use - r.first_use, r.memory.size); }),
        by([](const PlannedResource& r) { return std::make_pair(r.memory.size * (r.last_use - r.first_use + 1), r.memory.size); }),
        by([](const PlannedResource& r) { return std::make_pair(-static_cast<int64_t>(r.first_use), r.memory.size); }),
    };
    uint64_t least = ~uint64_t{0};
    size_t best_order = 0;
    bool best_tightest = false;
    for (size_t o = 0; o < orders.size(); ++o) {
      for (bool tightest : {false, true}) {
        const uint64_t bytes = place_in_order(orders[o], tightest);
        if (bytes < least) {
          least = bytes;
          best_order = o;
          best_tightest = tightest;
        }
      }
    }
    place_in_order(orders[best_order], best_tightest);
    for (const auto& b : plan_.blocks) plan_.transient_bytes_aliased += b.size;

    uint64_t total = plan_.transient_bytes_aliased + plan_.persistent_bytes;
    if (total > options_.memory_limit_bytes) {
      std::vector<const PlannedResource*> largest;
      for (const auto& r : plan_.resources) {
        if (r.used()) largest.push_back(&r);
      }
      // Ties in the plan's (name) order, so that the message does not depend on the sort.
      std::stable_sort(largest.begin(), largest.end(), [](auto* a, auto* b) { return a->memory.size > b->memory.size; });
      std::string names;
      for (size_t i = 0; i < std::min<size_t>(3, largest.size()); ++i) {
        names += std::string(i ? ", " : "") + "'" + largest[i]->name + "' " + mib(largest[i]->memory.size);
      }
      throw graph_.error(largest.empty() ? "" : largest.front()->pointer,
                         "graph needs " + mib(total) + " of device memory (" + mib(plan_.transient_bytes_aliased) +
                             " transient after aliasing, " + mib(plan_.persistent_bytes) + " persistent), above the limit of " +
                             mib(options_.memory_limit_bytes) + "; largest: " + names);
    }
  }

  // ---- barriers ------------------------------------------------------------------------------

  struct Tracker {
    bool touched = false;
    VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;
    VkPipelineStageFlags2 write_stages = 0;  // last write (or layout transition), not yet waited on by all
    VkAccessFlags2 write_access = 0;
    VkPipelineStageFlags2 read_stages = 0;     // reads since the last write (for write-after-read)
    VkPipelineStageFlags2 visible_stages = 0;  // stages that already waited on the last write
    VkAccessFlags2 visible_access = 0;
  };

  bool memory_overlaps(const PlannedResource& a, const PlannedResource& b) const {
    return a.block == b.block && a.offset < b.offset + b.memory.size && b.offset < a.offset + a.memory.size;
  }

  void record_barriers() {
    std::vector<Tracker> trackers(plan_.resources.size());
    for (uint32_t i = 0; i < order_.size(); ++i) {
      const Node& node = nodes_[order_[i]];
      for (const auto& b : node.bindings) {
        const PlannedResource& r = plan_.resources[b.resource];
        const bool image = r.kind == ResourceKind::image;
        Tracker& t = trackers[b.resource];
        PortAccessInfo a = port_access(*b.port, node.decl->queue);
        PlannedBarrier barrier;
        barrier.resource = b.resource;
        barrier.dst_stages = a.stages;
        barrier.dst_access = a.reads | a.writes;
        barrier.old_layout = t.layout;
        barrier.new_layout = image ? a.layout : VK_IMAGE_LAYOUT_UNDEFINED;
        const bool layout_change = image && t.layout != a.layout;
        bool needed = false;
        if (!t.touched) {
          // The memory may still be in use by an earlier resource of this frame that it aliases.
          if (r.transient) {
            for (uint32_t other = 0; other < plan_.resources.size(); ++other) {
              const PlannedResource& o = plan_.resources[other];
              if (other == b.resource || !o.used() || !o.transient || o.last_use >= i || !memory_overlaps(o, r)) continue;
              barrier.src_stages |= trackers[other].write_stages | trackers[other].read_stages;
              barrier.src_access |= trackers[other].write_access;
              barrier.aliasing = true;
            }
          }
          needed = image || barrier.aliasing;
        } else if (layout_change || a.writes) {
          barrier.src_stages = t.write_stages | t.read_stages;
          barrier.src_access = t.write_access;
          needed = layout_change || barrier.src_stages != 0;
        } else {
          bool covered = (a.stages & ~t.visible_stages) == 0 && (a.reads & ~t.visible_access) == 0;
          if (t.write_stages && !covered) {
            barrier.src_stages = t.write_stages;
            barrier.src_access = t.write_access;
            needed = true;
          }
        }
        if (needed) plan_.passes[i].barriers.push_back(barrier);

        if (a.writes) {
          t.write_stages = a.stages;
          t.write_access = a.writes;
          t.read_stages = 0;
          t.visible_stages = 0;
          t.visible_access = 0;
        } else if (layout_change) {
          t.write_stages = a.stages;  // later readers wait on the transition
          t.write_access = 0;
          t.read_stages = a.stages;
          t.visible_stages = a.stages;
          t.visible_access = a.reads;
        } else {
          t.read_stages |= a.stages;
          if (needed) {
            t.visible_stages |= a.stages;
            t.visible_access |= a.reads;
          }
        }
        t.layout = image ? a.layout : VK_IMAGE_LAYOUT_UNDEFINED;
        t.touched = true;
      }
    }
    for (uint32_t r = 0; r < plan_.resources.size(); ++r) {
      const Tracker& t = trackers[r];
      plan_.resources[r].final_state = {t.layout, t.write_stages | t.read_stages, t.write_access};
    }
  }
};

}  // namespace

std::map<std::string, double> typical_scene_values() {
  return {{"scene.refractors", 1}, {"scene.lights", 1}, {"scene.objects", 2}};
}

Plan compile_graph(const GraphDesc& graph, const PassRegistry& registry, const CompileOptions& options) {
  return Compiler(graph, registry, options).run();
}

}  // namespace caustica::graph
