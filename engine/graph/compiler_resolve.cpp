// The graph compiler's first phases (compiler_internal.h): which passes are enabled and where the
// resources no enabled pass writes fall back to, the resources' sizes from their expressions, and
// each enabled pass's type, parameters and port bindings, checked against its declaration.
#include <algorithm>
#include <cmath>
#include <set>

#include "core/suggest.h"
#include "graph/compiler_internal.h"
#include "graph/expression.h"
#include "graph/per_light.h"
#include "graph/user_pass_type.h"
#include "io/json_reader.h"

namespace caustica::graph::compiler_internal {

// ---- enabled passes and fallbacks -----------------------------------------------------------

std::string Compiler::redirected(const std::string& name) const {
  auto it = redirect_.find(name);
  return it == redirect_.end() ? name : it->second;
}

void Compiler::decide_enabled_and_fallbacks() {
  std::set<std::string> written;
  for (const auto& pass : graph_.passes) {
    if (pass.instance.any()) plan_.instances[pass.name] = pass.instance;
    const bool on = evaluate(pass.enabled, pass.pointer + "/enabled", pass.instance) != 0.0;
    enabled_.push_back(on);
    if (!on) {
      plan_.disabled.push_back(pass.name);
      plan_.disabled_by[pass.name] = as_read_by_light(pass.enabled, pass.instance);
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
        throw graph_.error(d->pointer + "/fallback", "fallback '" + d->fallback + "' of '" + d->name + "' is not a resource of this graph" +
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

std::vector<std::string> Compiler::resource_names_of_file() const {
  std::vector<std::string> names;
  for (const auto& r : graph_.resources) names.push_back(r.name);
  return names;
}

// ---- parameters and expressions -------------------------------------------------------------

ExpressionScope Compiler::scope(Instance instance) const {
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
  return light_scope(std::move(s), instance);
}

// Every value an expression gives is finite: the sizes, counts and flags computed from it are
// converted to integers, which is undefined for NaN and infinities.
double Compiler::evaluate(const std::string& text, const std::string& pointer, Instance instance) const {
  double v = 0;
  try {
    v = evaluate_expression(text, scope(instance));
  } catch (const std::invalid_argument& e) {
    throw graph_.error(pointer, e.what());
  }
  if (!std::isfinite(v))
    throw graph_.error(pointer, "\"" + text + "\" evaluates to " + JsonReader::format_number(v) + ", not a finite number");
  return v;
}

uint32_t Compiler::extent(const std::string& text, const std::string& pointer, const char* what, const ResourceDesc& desc) const {
  const std::string& resource = desc.name;
  double v = std::floor(evaluate(text, pointer, desc.instance));
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

void Compiler::size_resources() {
  for (const auto& desc : graph_.resources) {
    errors_.attempt([&] {
      PlannedResource r;
      r.name = desc.name;
      r.pointer = desc.pointer;
      r.kind = desc.kind;
      r.format = desc.format;
      if (desc.kind == ResourceKind::image) {
        r.width = extent(desc.width, desc.pointer + "/width", "width", desc);
        r.height = extent(desc.height, desc.pointer + "/height", "height", desc);
        double mips = std::floor(evaluate(desc.mips, desc.pointer + "/mips", desc.instance));
        uint32_t max_mips = static_cast<uint32_t>(std::floor(std::log2(std::max(r.width, r.height)))) + 1;
        if (mips < 1 || mips > max_mips) {
          throw graph_.error(desc.pointer + "/mips", "'" + desc.name + "' asks for " + JsonReader::format_number(mips) + " mip levels; a " +
                                                         std::to_string(r.width) + "x" + std::to_string(r.height) + " image has 1 to " +
                                                         std::to_string(max_mips));
        }
        r.mips = static_cast<uint32_t>(mips);
        double layers = std::floor(evaluate(desc.layers, desc.pointer + "/layers", desc.instance));
        if (layers < 1 || layers > kMaxImageLayers) {
          throw graph_.error(desc.pointer + "/layers", "'" + desc.name + "' asks for " + JsonReader::format_number(layers) +
                                                           " array layers; an image has 1 to " + std::to_string(kMaxImageLayers));
        }
        r.layers = static_cast<uint32_t>(layers);
        // Read back a layer to a colour channel, or side by side: single-channel formats only.
        if (r.layers > 1 && r.format != Format::r32f && r.format != Format::d32f) {
          throw graph_.error(desc.pointer + "/layers",
                             "'" + desc.name + "' is " + format_info(r.format).name + "; only r32f and d32f images can have layers");
        }
      } else {
        double bytes = std::floor(evaluate(desc.size, desc.pointer + "/size", desc.instance));
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
    });
  }
  errors_.throw_if_any();
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
  if (!graph_.linear_output.empty()) {
    const int index = plan_.find_resource(redirected(graph_.linear_output));
    if (index < 0) {
      throw graph_.error("/linear_output", "linear_output '" + graph_.linear_output + "' is not a resource of this graph" +
                                               did_you_mean(graph_.linear_output, resource_names()));
    }
    const PlannedResource& r = plan_.resources[static_cast<size_t>(index)];
    const bool linear_float = r.kind == ResourceKind::image && r.format != Format::rgba8 && r.format != Format::rgba8_srgb &&
                              r.format != Format::r32ui && r.format != Format::rg32ui && r.format != Format::rgba32ui &&
                              r.format != Format::d32f;
    if (!linear_float) {
      throw graph_.error("/linear_output", "linear_output '" + r.name + "' is " +
                                               (r.kind == ResourceKind::image ? std::string(format_info(r.format).name) : "a buffer") +
                                               "; the linear result is a float colour image (rgba16f, rgba32f)");
    }
  }
  for (const auto& name : options_.retained) {
    if (auto it = redirect_.find(name); it != redirect_.end() && it->second.empty()) continue;  // nothing writes it for this scene
    int index = plan_.find_resource(redirected(name));
    if (index < 0) {
      std::string what_there_is = did_you_mean(name, resource_names());
      if (what_there_is.empty()) {
        for (const auto& r : resource_names()) what_there_is += (what_there_is.empty() ? "; its resources: " : ", ") + r;
      }
      throw InputError(graph_.doc.path() + ": no resource named '" + name + "' to keep" + what_there_is);
    }
    plan_.resources[static_cast<size_t>(index)].transient = false;
  }
}

std::vector<std::string> Compiler::resource_names() const {
  std::vector<std::string> names;
  for (const auto& r : graph_.resources) names.push_back(r.name);
  return names;
}

nlohmann::json Compiler::resolve_params(const PassDesc& pass, const PassTypeDecl& decl, std::map<std::string, std::string>& frame_params) {
  std::vector<std::string> declared;
  for (const auto& p : decl.params) declared.push_back(p.name);
  std::vector<std::string> graph_params;
  for (const auto& p : graph_.parameters) graph_params.push_back(p.decl.name);

  nlohmann::json out = nlohmann::json::object();
  for (const auto& [key, raw] : pass.params.items()) {
    errors_.attempt([&, &key = key, &raw = raw] {
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
        // Graph files of old declared a photon grid as a choice of numbers written as strings
        // ("2048"); a numeric parameter still reads such a choice, as its number.
        if (const bool numeric = param->type == ParamType::int_ || param->type == ParamType::float_;
            numeric && gp->decl.type == ParamType::choice) {
          if (const auto number = nlohmann::json::parse(value.get<std::string>(), nullptr, false); number.is_number()) {
            const std::string message =
                "graph parameter '" + name + "' is a choice of strings, and parameter '" + key + "' of pass '" + pass.name + "' (" +
                decl.type + ") takes " + (param->type == ParamType::int_ ? "an integer" : "a number") + ", so it reads " + value.dump() +
                " as " + number.dump() + "; declare '" + name + "' as \"type\": \"" + std::string(param_type_name(param->type)) +
                "\" with numbers" + (param->power_of_two ? " and \"power_of_two\": true" : "");
            plan_.warnings.push_back(graph_.error(gp->pointer, message).what());
            value = number;
          }
        }
      } else if (raw.is_string() && param->type != ParamType::choice) {
        // An expression of the output size, the scene and the graph's parameters, and for a parameter
        // the pass reads every frame, of the frame block too: evaluated here for the first frame,
        // and by the executor before every frame (PlannedPass::frame_params), clamped to the range.
        const std::string text = raw.get<std::string>();
        bool follows_frame = false;
        ExpressionScope s = scope(pass.instance);
        s.known_names.insert(s.known_names.end(), std::begin(kFrameNames), std::end(kFrameNames));
        s.lookup = [compile_time = s.lookup, &follows_frame](std::string_view name) -> std::optional<double> {
          if (std::find(std::begin(kFrameNames), std::end(kFrameNames), name) == std::end(kFrameNames)) return compile_time(name);
          follows_frame = true;
          return 0.0;
        };
        double number = 0;
        try {
          number = evaluate_expression(text, s);
        } catch (const std::invalid_argument& e) {
          const char* expects = param->type == ParamType::bool_  ? "true or false"
                                : param->type == ParamType::int_ ? "an integer"
                                                                 : "a number";
          throw graph_.error(pointer,
                             "parameter '" + key + "' of pass '" + pass.name + "' expects " + expects + " or an expression; " + e.what());
        }
        if (follows_frame && !param->per_frame) {
          std::string per_frame;
          for (const auto& p : decl.params) per_frame += p.per_frame ? (per_frame.empty() ? "" : ", ") + p.name : "";
          throw graph_.error(pointer, "parameter '" + key + "' of pass '" + pass.name + "' is fixed for a plan, so \"" + text +
                                          "\" cannot follow the frame; " +
                                          (per_frame.empty() ? "no parameter of pass type '" + decl.type + "' can"
                                                             : "the ones of pass type '" + decl.type + "' that can: " + per_frame));
        }
        value = param_value_of_number(*param, number, follows_frame);
        if (follows_frame) frame_params[key] = text;
        via = " (\"" + text + "\")";
        if (nlohmann::json::parse(text, nullptr, false).is_number()) {
          const std::string message = "parameter '" + key + "' of pass '" + pass.name + "' is the string \"" + text +
                                      "\", read as the number " + value.dump() + "; write it without quotes";
          plan_.warnings.push_back(graph_.error(pointer, message).what());
        }
      }
      std::string problem = check_param_value(*param, value);
      if (!problem.empty()) throw graph_.error(pointer, "parameter '" + key + "' of pass '" + pass.name + "' " + problem + via);
      out[key] = value;
    });
  }
  for (const auto& p : decl.params) {
    if (!out.contains(p.name)) out[p.name] = p.default_value;
  }
  return out;
}

void Compiler::bind_section(Node& node, const std::map<std::string, std::string>& section, bool outputs) {
  const PassDesc& pass = *node.desc;
  const PassTypeDecl& decl = *node.decl;
  const char* section_name = outputs ? "outputs" : "inputs";
  std::vector<std::string> port_names;
  for (const auto& p : decl.ports) port_names.push_back(p.name);
  for (const auto& [port_name, resource_name] : section) {
    const bool bound = errors_.attempt([&, &port_name = port_name, &resource_name = resource_name] {
      std::string pointer = json_pointer_append(pass.pointer + "/" + section_name, port_name);
      const auto [base_name, element] = split_port_element(port_name);
      const PortDecl* port = decl.find_port(base_name);
      if (!port) {
        throw graph_.error(pointer, "pass type '" + decl.type + "' has no port '" + port_name + "'" + did_you_mean(port_name, port_names));
      }
      if (element >= 0 && !port->per_light) {
        const size_t instance = resource_name.find('#');
        if (instance != std::string::npos) {
          throw graph_.error(pointer, "'" + resource_name.substr(0, instance) + "' is a per-light resource (one per light), and port '" +
                                          base_name + "' of pass type '" + decl.type +
                                          "' takes one resource; read it in a pass with \"for_each\": \"light\", whose instances "
                                          "each read their light's");
        }
        throw graph_.error(pointer, "'" + port_name + "' names an element of port '" + base_name + "' of pass type '" + decl.type +
                                        "', which takes one resource, not one per light");
      }
      const std::string key = port->per_light ? port_element(base_name, static_cast<uint32_t>(std::max(element, 0))) : base_name;
      bool port_writes = port->access != PortAccess::read;
      if (port_writes != outputs) {
        throw graph_.error(pointer, std::string("port '") + port_name + "' of pass type '" + decl.type + "' is an " +
                                        (port_writes ? "output" : "input") + "; list it under \"" + (port_writes ? "outputs" : "inputs") +
                                        "\"");
      }
      int index = -1;
      if (const std::string history_of_resource = history_source(resource_name); !history_of_resource.empty()) {
        if (outputs) {
          throw graph_.error(pointer, "'" + resource_name + "' is the previous frame's '" + history_of_resource +
                                          "', which passes read and do not write; bind output '" + port_name + "' to a resource");
        }
        index = static_cast<int>(history_resource(resource_name, history_of_resource, pointer));
      } else {
        const std::string source = outputs ? resource_name : redirected(resource_name);
        if (source.empty()) {  // "fallback": null and nothing writes it
          if (port->optional) return;
          throw graph_.error(pointer, "input '" + port_name + "' of pass '" + pass.name + "' reads '" + resource_name +
                                          "', which no enabled pass writes and whose fallback is null; only optional inputs may");
        }
        index = plan_.find_resource(source);
        if (index < 0) {
          throw graph_.error(pointer, "no resource named '" + resource_name + "'" + did_you_mean(resource_name, resource_names()));
        }
      }
      const PlannedResource& r = plan_.resources[static_cast<size_t>(index)];
      if (r.kind != port->kind) {
        throw graph_.error(pointer, "port '" + port_name + "' of pass '" + pass.name + "' takes " +
                                        (port->kind == ResourceKind::image ? "an image" : "a buffer") + ", but '" + r.name + "' is " +
                                        (r.kind == ResourceKind::image ? "an image" : "a buffer"));
      }
      if (r.kind == ResourceKind::image) check_format(*port, r, pass, pointer);
      for (const auto& other : node.bindings) {
        if (other.key == key) throw graph_.error(pointer, "pass '" + pass.name + "' binds '" + key + "' twice");
        if (other.resource == static_cast<uint32_t>(index) && other.port != port) {
          throw graph_.error(pointer, "pass '" + pass.name + "' binds '" + r.name + "' to two ports ('" + other.port->name + "' and '" +
                                          port_name + "'); use one read_write port instead");
        }
      }
      // An optional output nobody asks for (a debug view such as the caustic-map levels) stays
      // unbound, so the pass skips the work and the resource takes no memory; one the pass samples
      // itself (scratch, such as refraction_layers' front_tint) is bound wherever it is connected.
      if (outputs && port->optional && !port->also_sampled && !wanted(resource_name)) return;
      node.bindings.push_back({port, static_cast<uint32_t>(index), pointer, key});
    });
    if (!bound) node.refused_binding = true;
  }
}

// The history resource `name` ("SOURCE@previous"), made on its first binding: SOURCE's kind, format
// and extent, kept across frames with SOURCE (PlannedResource::previous_of).
uint32_t Compiler::history_resource(const std::string& name, const std::string& source_name, const std::string& pointer) {
  if (const int made = plan_.find_resource(name); made >= 0) return static_cast<uint32_t>(made);
  const int source = plan_.find_resource(source_name);
  if (source < 0 || redirect_.count(source_name)) {
    throw graph_.error(pointer, "'" + name + "' reads the previous frame's '" + source_name + "', " +
                                    (source < 0 ? "which is not a resource of this graph" + did_you_mean(source_name, resource_names())
                                                : "which no enabled pass writes"));
  }
  PlannedResource history = plan_.resources[static_cast<size_t>(source)];
  history.name = name;
  history.pointer = pointer;
  history.output = false;
  history.transient = false;
  history.kept_across_frames = true;
  history.previous_of = static_cast<uint32_t>(source);
  plan_.resources[static_cast<size_t>(source)].transient = false;
  plan_.resources[static_cast<size_t>(source)].kept_across_frames = true;
  plan_.resources.push_back(std::move(history));
  return static_cast<uint32_t>(plan_.resources.size() - 1);
}

// Whether an enabled pass reads `resource`, it is a graph output, or it is kept (--dump, the viewer).
bool Compiler::wanted(const std::string& resource) const {
  if (std::count(graph_.outputs.begin(), graph_.outputs.end(), resource) || options_.retained.count(resource)) return true;
  for (size_t i = 0; i < graph_.passes.size(); ++i) {
    if (!enabled_[i]) continue;
    for (const auto& [port, read] : graph_.passes[i].inputs) {
      if (read == resource || history_source(read) == resource) return true;
    }
  }
  return false;
}

void Compiler::check_format(const PortDecl& port, const PlannedResource& r, const PassDesc& pass, const std::string& pointer) const {
  const FormatInfo& info = format_info(r.format);
  if (!port.formats.empty() && std::find(port.formats.begin(), port.formats.end(), r.format) == port.formats.end()) {
    std::string accepted;
    for (Format f : port.formats) accepted += std::string(accepted.empty() ? "" : ", ") + format_info(f).name;
    throw graph_.error(pointer, "format mismatch: port '" + port.name + "' of pass '" + pass.name + "' accepts " + accepted + ", but '" +
                                    r.name + "' is " + info.name);
  }
  if (port.kind == ResourceKind::image && r.layers != port.layers && !(port.cube_layers && r.layers == 6)) {
    throw graph_.error(pointer, "layer mismatch: port '" + port.name + "' of pass '" + pass.name + "' takes an image of " +
                                    std::to_string(port.layers) + (port.layers == 1 ? " layer" : " array layers") +
                                    (port.cube_layers ? " or 6 (a point light's cube faces)" : "") + ", but '" + r.name + "' has " +
                                    std::to_string(r.layers) + " (its \"layers\")");
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

void Compiler::resolve_dispatch(const PassDesc& pass, const nlohmann::json& params, const std::map<std::string, std::string>& frame_params,
                                UserShader& shader) const {
  const UserPassDesc& user = *pass.user;
  // Expressions of the sizes, the scene, the graph's parameters and the pass's own (by name, before
  // a graph parameter of the same name).
  ExpressionScope s = scope(pass.instance);
  for (const auto& p : user.params) {
    if (p.type != ParamType::choice) s.known_names.push_back(p.name);
  }
  std::string follows_frame;  // a parameter named that follows the frame, which a dispatch fixed for the plan cannot
  s.lookup = [graph_scope = s.lookup, &params, &user, &frame_params, &follows_frame](std::string_view name) -> std::optional<double> {
    for (const auto& p : user.params) {
      if (p.name != name || p.type == ParamType::choice) continue;
      if (frame_params.contains(p.name)) follows_frame = p.name;
      const nlohmann::json& value = params[p.name];
      return value.is_boolean() ? (value.get<bool>() ? 1.0 : 0.0) : value.get<double>();
    }
    return graph_scope(name);
  };
  for (size_t i = 0; i < user.dispatch.size(); ++i) {
    const std::string pointer = user.dispatch_pointer + "/" + std::to_string(i);
    double v = 0;
    try {
      v = std::floor(evaluate_expression(user.dispatch[i], s));
    } catch (const std::invalid_argument& e) {
      throw graph_.error(pointer, e.what());
    }
    if (!follows_frame.empty()) {
      throw graph_.error(pointer, "\"dispatch\" of pass '" + pass.name + "' names parameter '" + follows_frame +
                                      "', which follows the frame (\"" + frame_params.at(follows_frame) +
                                      "\"); a dispatch is fixed for the plan: size it by the output, the scene or parameters that do not");
    }
    if (!(v >= 1 && v <= 16777216)) {
      throw graph_.error(pointer, "\"dispatch\" of pass '" + pass.name + "': \"" + user.dispatch[i] + "\" evaluates to " +
                                      JsonReader::format_number(v) + " invocations; it must be 1 to 16777216");
    }
    shader.invocations[i] = static_cast<uint32_t>(v);
  }
}

void Compiler::resolve_passes() {
  std::vector<std::string> type_names = registry_.names();
  nodes_.resize(graph_.passes.size());
  // Every pass, and within it every parameter and port, is checked on its own: one run reports the
  // errors of all (a pass whose type changed has several), and what follows waits for them.
  for (size_t i = 0; i < graph_.passes.size(); ++i) {
    const PassDesc& pass = graph_.passes[i];
    Node& node = nodes_[i];
    node.desc = &pass;
    const PassTypeDecl* decl = registry_.find(pass.type);
    if (!decl) {
      errors_.attempt([&] {
        throw graph_.error(pass.pointer + "/type", "unknown pass type '" + pass.type + "'" + did_you_mean(pass.type, type_names));
      });
      continue;
    }
    if (!enabled_[i]) continue;
    std::shared_ptr<UserShader> user_shader;
    if (decl->user_kind != UserShaderKind::none) {
      const bool made = errors_.attempt([&] {
        std::shared_ptr<const PassTypeDecl> own = make_user_pass_type(*decl, graph_, pass, user_shader);
        decl = own.get();
        plan_.user_types.push_back(std::move(own));
      });
      if (!made) continue;
    }
    node.decl = decl;
    node.params = resolve_params(pass, *decl, node.frame_params);
    if (user_shader) errors_.attempt([&] { resolve_dispatch(pass, node.params, node.frame_params, *user_shader); });
    bind_section(node, pass.inputs, false);
    bind_section(node, pass.outputs, true);
    for (const auto& port : decl->ports) {
      // A refused binding (a misspelt port) was most likely meant for the port left unbound.
      if (port.optional || node.refused_binding) continue;
      bool bound = std::any_of(node.bindings.begin(), node.bindings.end(), [&](const Binding& b) { return b.port == &port; });
      if (!bound) {
        errors_.attempt([&] {
          bool input = port.access == PortAccess::read;
          throw graph_.error(pass.pointer, std::string(input ? "input" : "output") + " '" + port.name + "' of pass '" + pass.name +
                                               "' (type " + decl->type + ") is not connected");
        });
      }
    }
  }
  errors_.throw_if_any();
}

}  // namespace caustica::graph::compiler_internal
