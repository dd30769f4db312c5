#include "graph/graph_desc.h"

#include <algorithm>

#include <set>

#include "core/suggest.h"
#include "graph/per_light.h"
#include "graph/plan.h"
#include "io/json_reader.h"

namespace caustica::graph {

const ResourceDesc* GraphDesc::find_resource(std::string_view wanted) const {
  for (const auto& r : resources) {
    if (r.name == wanted) return &r;
  }
  return nullptr;
}

const GraphParameter* GraphDesc::find_parameter(std::string_view wanted) const {
  for (const auto& p : parameters) {
    if (p.decl.name == wanted) return &p;
  }
  return nullptr;
}

namespace {

using Reader = JsonReader;

ParamType parse_param_type(const JsonDocument& doc, const nlohmann::json& value, const std::string& pointer) {
  static const std::vector<std::string> names{"float", "int", "bool", "choice"};
  std::string text = Reader(doc).string(value, pointer, "a parameter type");
  if (text == "float") return ParamType::float_;
  if (text == "int") return ParamType::int_;
  if (text == "bool") return ParamType::bool_;
  if (text == "choice") return ParamType::choice;
  throw doc.error(pointer, "unknown parameter type '" + text + "'" + did_you_mean(text, names));
}

// A parameter's declaration (a graph's, or a user pass's): type, default, range, choices.
ParamDecl read_param_decl(const GraphDesc& graph, const Reader& read, const std::string& key, const nlohmann::json& value,
                          const std::string& pointer) {
  ParamDecl decl;
  decl.name = read.name(nlohmann::json(key), pointer, "a parameter name");
  if (!value.contains("type")) throw graph.error(pointer, "parameter '" + key + "' needs a \"type\"");
  if (!value.contains("default")) throw graph.error(pointer, "parameter '" + key + "' needs a \"default\"");
  decl.type = parse_param_type(graph.doc, value["type"], pointer + "/type");
  for (const char* bound : {"min", "max"}) {
    if (!value.contains(bound)) continue;
    if (!value[bound].is_number()) throw graph.error(pointer + "/" + bound, std::string("\"") + bound + "\" must be a number");
    (std::string(bound) == "min" ? decl.min : decl.max) = value[bound].get<double>();
  }
  if (decl.min && decl.max && *decl.min > *decl.max) {
    throw graph.error(pointer + "/min", "parameter '" + key + "' has min above max");
  }
  if (value.contains("power_of_two")) {
    const std::string at = pointer + "/power_of_two";
    if (!value["power_of_two"].is_boolean()) throw graph.error(at, "\"power_of_two\" must be true or false");
    decl.power_of_two = value["power_of_two"].get<bool>();
    if (decl.power_of_two && (decl.type != ParamType::int_ || !decl.min || *decl.min < 1 || !decl.max)) {
      throw graph.error(at,
                        "parameter '" + key + "' is a power of two, so it needs \"type\": \"int\", a \"min\" of at least 1 and a \"max\"");
    }
  }
  if (value.contains("choices")) {
    const auto& choices = value["choices"];
    if (!choices.is_array() || choices.empty()) throw graph.error(pointer + "/choices", "\"choices\" must be a non-empty array of strings");
    for (size_t i = 0; i < choices.size(); ++i) {
      decl.choices.push_back(read.string(choices[i], pointer + "/choices/" + std::to_string(i), "a choice"));
    }
  } else if (decl.type == ParamType::choice) {
    throw graph.error(pointer, "parameter '" + key + "' of type choice needs \"choices\"");
  }
  if (value.contains("description")) decl.description = read.string(value["description"], pointer + "/description", "a description");
  decl.default_value = value["default"];
  const std::string problem = check_param_value(decl, decl.default_value);
  if (!problem.empty()) throw graph.error(pointer + "/default", "the default of parameter '" + key + "' " + problem);
  return decl;
}

void load_parameters(GraphDesc& graph, const Reader& read, ErrorList& errors) {
  const auto& root = graph.doc.root();
  if (!root.contains("parameters")) return;
  const auto& params = read.object(root["parameters"], "/parameters", "\"parameters\"");
  for (const auto& [key, value] : params.items()) {
    errors.attempt([&, &key = key, &value = value] {
      std::string pointer = json_pointer_append("/parameters", key);
      GraphParameter p;
      p.pointer = pointer;
      read.object(value, pointer, "a parameter");
      read.only_keys(value, pointer,
                     {"type", "default", "min", "max", "power_of_two", "choices", "description", "while_moving", "while_still"},
                     "a parameter");
      p.decl = read_param_decl(graph, read, key, value, pointer);
      p.value = p.decl.default_value;
      auto checked = [&](const char* name, const nlohmann::json& v, const std::string& at) {
        const std::string problem = check_param_value(p.decl, v);
        if (!problem.empty()) throw graph.error(at, std::string("the ") + name + " value of parameter '" + key + "' " + problem);
        return v;
      };
      if (value.contains("while_moving")) p.while_moving = checked("while_moving", value["while_moving"], pointer + "/while_moving");
      if (value.contains("while_still")) {
        const nlohmann::json& still = value["while_still"];
        if (!still.is_array()) {
          p.while_still.push_back(checked("while_still", still, pointer + "/while_still"));
        } else {
          if (still.empty())
            throw graph.error(pointer + "/while_still", "the while_still values of parameter '" + key + "' are an empty list");
          for (size_t i = 0; i < still.size(); ++i)
            p.while_still.push_back(checked("while_still", still[i], pointer + "/while_still/" + std::to_string(i)));
        }
      }
      graph.parameters.push_back(std::move(p));
    });
  }
}

// "for_each": what a pass or resource is made once per: the scene's lights or its caustic views.
std::string read_for_each(const GraphDesc& graph, const Reader& read, const nlohmann::json& value, const std::string& pointer) {
  const std::string text = read.string(value, pointer, "\"for_each\"");
  if (text != kForEachLight && text != kForEachCausticView) {
    throw graph.error(pointer, "unknown \"for_each\" '" + text + "'" +
                                   did_you_mean(text, {std::string(kForEachLight), std::string(kForEachCausticView)}) +
                                   "; passes and resources are made once per light (\"light\"), once per caustic view "
                                   "(\"caustic_view\": a light's, or each cube face of a point light among its refractors) or once");
  }
  return text;
}

void load_resources(GraphDesc& graph, const Reader& read, ErrorList& errors) {
  const auto& root = graph.doc.root();
  if (!root.contains("resources")) throw graph.error("", "a graph needs \"resources\"");
  const auto& resources = read.object(root["resources"], "/resources", "\"resources\"");
  for (const auto& [key, value] : resources.items()) {
    errors.attempt([&, &key = key, &value = value] {
      std::string pointer = json_pointer_append("/resources", key);
      ResourceDesc r;
      r.pointer = pointer;
      r.name = read.name(nlohmann::json(key), pointer, "a resource name");
      read.object(value, pointer, "a resource");
      read.only_keys(value, pointer, {"type", "format", "width", "height", "mips", "layers", "size", "fallback", "for_each", "description"},
                     "a resource");
      if (value.contains("for_each")) r.for_each = read_for_each(graph, read, value["for_each"], pointer + "/for_each");
      std::string type = value.contains("type") ? read.string(value["type"], pointer + "/type", "\"type\"") : "image";
      if (type == "image") {
        r.kind = ResourceKind::image;
        if (!value.contains("format")) throw graph.error(pointer, "image '" + key + "' needs a \"format\"");
        std::string format = read.string(value["format"], pointer + "/format", "\"format\"");
        auto parsed = parse_format(format);
        if (!parsed) throw graph.error(pointer + "/format", "unknown format '" + format + "'" + did_you_mean(format, format_names()));
        r.format = *parsed;
        if (value.contains("width")) r.width = read.expression(value["width"], pointer + "/width", "\"width\"");
        if (value.contains("height")) r.height = read.expression(value["height"], pointer + "/height", "\"height\"");
        if (value.contains("mips")) r.mips = read.expression(value["mips"], pointer + "/mips", "\"mips\"");
        if (value.contains("layers")) r.layers = read.expression(value["layers"], pointer + "/layers", "\"layers\"");
        if (value.contains("size")) throw graph.error(pointer + "/size", "\"size\" is for buffers; an image has \"width\" and \"height\"");
      } else if (type == "buffer") {
        r.kind = ResourceKind::buffer;
        if (!value.contains("size")) throw graph.error(pointer, "buffer '" + key + "' needs a \"size\" in bytes");
        r.size = read.expression(value["size"], pointer + "/size", "\"size\"");
        for (const char* image_only : {"format", "width", "height", "mips", "layers"}) {
          if (value.contains(image_only))
            throw graph.error(pointer + "/" + image_only, std::string("\"") + image_only + "\" is for images, not buffers");
        }
      } else {
        throw graph.error(pointer + "/type", "unknown resource type '" + type + "'" + did_you_mean(type, {"image", "buffer"}));
      }
      if (value.contains("fallback")) {
        if (value["fallback"].is_null())
          r.fallback_to_nothing = true;
        else
          r.fallback = read.name(value["fallback"], pointer + "/fallback", "\"fallback\" (a resource name, or null)");
      }
      graph.resources.push_back(std::move(r));
    });
  }
}

std::map<std::string, std::string> load_bindings(const Reader& read, const nlohmann::json& pass, const std::string& pointer,
                                                 const char* section) {
  std::map<std::string, std::string> out;
  if (!pass.contains(section)) return out;
  std::string section_pointer = pointer + "/" + section;
  read.object(pass[section], section_pointer, section);
  for (const auto& [port, resource] : pass[section].items()) {
    const std::string port_pointer = json_pointer_append(section_pointer, port);
    // "NAME@previous": resource NAME as the previous frame left it (a history input; the compiler
    // refuses it as an output).
    const std::string text = read.string(resource, port_pointer, "a resource name");
    if (const std::string source = history_source(text); !source.empty()) {
      out[port] = history_of(read.name(nlohmann::json(source), port_pointer, "a resource name"));
    } else {
      out[port] = read.name(resource, port_pointer, "a resource name");
    }
  }
  return out;
}

template <class T>
T read_choice(const GraphDesc& graph, const Reader& read, const nlohmann::json& value, const std::string& pointer, const char* what,
              const std::vector<std::pair<std::string, T>>& choices) {
  const std::string text = read.string(value, pointer, what);
  std::vector<std::string> names;
  for (const auto& [name, choice] : choices) {
    if (name == text) return choice;
    names.push_back(name);
  }
  throw graph.error(pointer, "unknown " + std::string(what) + " '" + text + "'" + did_you_mean(text, names));
}

// A user port, declared as a built-in pass type declares one (PortDecl).
PortDecl read_user_port(const GraphDesc& graph, const Reader& read, const std::string& key, const nlohmann::json& value,
                        const std::string& pointer, bool fullscreen) {
  read.object(value, pointer, "a port");
  read.only_keys(value, pointer, {"type", "access", "usage", "formats", "extent_group", "layers", "description"}, "a port");
  PortDecl port;
  port.name = read.name(nlohmann::json(key), pointer, "a port name");
  if (value.contains("type"))
    port.kind = read_choice<ResourceKind>(graph, read, value["type"], pointer + "/type", "port type",
                                          {{"image", ResourceKind::image}, {"buffer", ResourceKind::buffer}});
  if (!value.contains("access")) throw graph.error(pointer, "port '" + key + "' needs an \"access\": read, write or read_write");
  port.access = read_choice<PortAccess>(graph, read, value["access"], pointer + "/access", "access",
                                        {{"read", PortAccess::read}, {"write", PortAccess::write}, {"read_write", PortAccess::read_write}});
  // What a shader usually does with it: samples an image it reads; stores to one it writes (a
  // full-screen pass renders to it); a buffer is a storage buffer.
  port.usage = port.kind == ResourceKind::buffer ? PortUsage::storage
               : port.access == PortAccess::read ? PortUsage::sampled
               : fullscreen                      ? PortUsage::color_attachment
                                                 : PortUsage::storage;
  if (value.contains("usage"))
    port.usage = read_choice<PortUsage>(graph, read, value["usage"], pointer + "/usage", "usage",
                                        {{"sampled", PortUsage::sampled},
                                         {"storage", PortUsage::storage},
                                         {"color_attachment", PortUsage::color_attachment},
                                         {"uniform", PortUsage::uniform}});
  if (value.contains("formats")) {
    const auto& formats = value["formats"];
    if (!formats.is_array() || formats.empty()) throw graph.error(pointer + "/formats", "\"formats\" must be a non-empty array of formats");
    for (size_t i = 0; i < formats.size(); ++i) {
      const std::string at = pointer + "/formats/" + std::to_string(i);
      const std::string name = read.string(formats[i], at, "a format");
      const auto format = parse_format(name);
      if (!format) throw graph.error(at, "unknown format '" + name + "'" + did_you_mean(name, format_names()));
      port.formats.push_back(*format);
    }
  }
  if (value.contains("extent_group")) port.extent_group = read.name(value["extent_group"], pointer + "/extent_group", "\"extent_group\"");
  if (value.contains("layers"))
    port.layers = static_cast<uint32_t>(read.number(value["layers"], pointer + "/layers", "\"layers\"", 1, kMaxImageLayers));
  if (value.contains("description")) port.description = read.string(value["description"], pointer + "/description", "a description");
  if (port.kind == ResourceKind::buffer && port.usage != PortUsage::storage && port.usage != PortUsage::uniform)
    throw graph.error(pointer + "/usage", "buffer port '" + key + "' is used as \"storage\" or \"uniform\"");
  if (port.kind == ResourceKind::image && port.usage == PortUsage::uniform)
    throw graph.error(pointer + "/usage", "image port '" + key + "' is \"sampled\", \"storage\" or \"color_attachment\"");
  if (port.usage == PortUsage::color_attachment && (!fullscreen || port.access == PortAccess::read))
    throw graph.error(pointer + "/usage", "only a fullscreen pass's outputs are colour attachments (port '" + key + "')");
  if (port.usage == PortUsage::sampled && port.access != PortAccess::read)
    throw graph.error(pointer + "/usage", "a sampled port is read; port '" + key + "' writes: make it \"storage\"");
  return port;
}

UserPassDesc read_user_pass(const GraphDesc& graph, const Reader& read, const nlohmann::json& value, const std::string& pointer,
                            bool fullscreen) {
  UserPassDesc user;
  if (!value.contains("shader"))
    throw graph.error(pointer, std::string("a ") + (fullscreen ? "fullscreen" : "compute") + " pass needs a \"shader\": its " +
                                   (fullscreen ? ".frag" : ".comp") + " file, relative to the graph file");
  user.shader = read.string(value["shader"], pointer + "/shader", "\"shader\"");
  if (value.contains("ports")) {
    const auto& ports = read.object(value["ports"], pointer + "/ports", "\"ports\"");
    for (const auto& [key, port] : ports.items()) {
      const std::string at = json_pointer_append(pointer + "/ports", key);
      user.ports.push_back(read_user_port(graph, read, key, port, at, fullscreen));
      user.port_pointers.push_back(at);
    }
  }
  if (value.contains("parameters")) {
    const auto& params = read.object(value["parameters"], pointer + "/parameters", "\"parameters\"");
    for (const auto& [key, param] : params.items()) {
      const std::string at = json_pointer_append(pointer + "/parameters", key);
      read.object(param, at, "a parameter");
      read.only_keys(param, at, {"type", "default", "min", "max", "power_of_two", "choices", "description"}, "a parameter");
      user.params.push_back(read_param_decl(graph, read, key, param, at));
      user.param_pointers.push_back(at);
    }
  }
  if (value.contains("scene")) user.scene = read.boolean(value["scene"], pointer + "/scene", "\"scene\"");
  user.counters_pointer = pointer + "/counters";
  if (value.contains("counters")) {
    const auto& counters = value["counters"];
    if (!counters.is_array())
      throw graph.error(user.counters_pointer, "\"counters\" must be an array of counters, each a name (a count) or {\"name\", \"kind\"}");
    for (size_t i = 0; i < counters.size(); ++i) {
      const std::string at = user.counters_pointer + "/" + std::to_string(i);
      UserPassDesc::Counter counter;
      if (counters[i].is_object()) {
        read.only_keys(counters[i], at, {"name", "kind"}, "a counter");
        if (!counters[i].contains("name")) throw graph.error(at, "a counter needs a \"name\"");
        counter.name = read.string(counters[i]["name"], at + "/name", "a counter name");
        if (counters[i].contains("kind"))
          counter.sum =
              read_choice<bool>(graph, read, counters[i]["kind"], at + "/kind", "counter kind", {{"count", false}, {"sum", true}});
      } else {
        counter.name = read.string(counters[i], at, "a counter name, or {\"name\", \"kind\"}");
      }
      if (counter.name.empty()) throw graph.error(at, "a counter's name is empty");
      for (const auto& other : user.counters) {
        if (other.name == counter.name) throw graph.error(at, "two counters are named '" + counter.name + "'");
      }
      user.counters.push_back(std::move(counter));
    }
  }
  user.dispatch_pointer = pointer + "/dispatch";
  if (fullscreen) {
    if (value.contains("dispatch"))
      throw graph.error(user.dispatch_pointer, "a fullscreen pass draws over its outputs and has no \"dispatch\"");
  } else if (!value.contains("dispatch")) {
    throw graph.error(pointer,
                      "a compute pass needs a \"dispatch\": a port whose image it covers (one invocation a texel), or "
                      "[x, y, z] invocations as expressions");
  } else if (const auto& dispatch = value["dispatch"]; dispatch.is_string()) {
    user.dispatch_port = read.name(dispatch, user.dispatch_pointer, "\"dispatch\"");
  } else if (dispatch.is_array() && !dispatch.empty() && dispatch.size() <= 3) {
    for (size_t i = 0; i < dispatch.size(); ++i) {
      user.dispatch.push_back(read.expression(dispatch[i], user.dispatch_pointer + "/" + std::to_string(i), "an invocation count"));
    }
  } else {
    throw graph.error(user.dispatch_pointer, "\"dispatch\" is a port name, or an array of 1 to 3 invocation counts (expressions)");
  }
  return user;
}

void load_passes(GraphDesc& graph, const Reader& read, ErrorList& errors) {
  const auto& root = graph.doc.root();
  if (!root.contains("passes")) throw graph.error("", "a graph needs \"passes\"");
  const auto& passes = root["passes"];
  if (!passes.is_array()) throw graph.error("/passes", "\"passes\" must be an array of pass objects");
  if (passes.empty()) throw graph.error("/passes", "a graph needs at least one pass");
  if (passes.size() > 100000) throw graph.error("/passes", "more than 100000 passes");
  std::set<std::string> names;
  for (size_t i = 0; i < passes.size(); ++i) {
    errors.attempt([&] {
      std::string pointer = "/passes/" + std::to_string(i);
      const auto& value = read.object(passes[i], pointer, "a pass");
      PassDesc p;
      p.pointer = pointer;
      if (!value.contains("type")) throw graph.error(pointer, "pass needs a \"type\"");
      p.type = read.string(value["type"], pointer + "/type", "\"type\"");
      const bool user = std::find(std::begin(kUserPassTypes), std::end(kUserPassTypes), p.type) != std::end(kUserPassTypes);
      std::vector<std::string> keys{"name", "type", "params", "inputs", "outputs", "after", "enabled", "for_each", "description"};
      const std::vector<std::string> user_keys{"shader", "ports", "parameters", "dispatch", "scene", "counters"};
      if (user) keys.insert(keys.end(), user_keys.begin(), user_keys.end());
      for (const auto& key : user_keys) {
        if (!user && value.contains(key))
          throw graph.error(pointer + "/" + key, "\"" + key +
                                                     "\" is for passes of type compute or fullscreen, whose shader the graph names; '" +
                                                     p.type + "' is a built-in pass type");
      }
      read.only_keys(value, pointer, keys, "a pass");
      if (user) p.user = read_user_pass(graph, read, value, pointer, p.type == "fullscreen");
      if (!value.contains("name")) throw graph.error(pointer, "pass needs a \"name\"");
      p.name = read.name(value["name"], pointer + "/name", "a pass name");
      if (!names.insert(p.name).second) throw graph.error(pointer + "/name", "two passes are named '" + p.name + "'");
      if (value.contains("params")) p.params = read.object(value["params"], pointer + "/params", "\"params\"");
      p.inputs = load_bindings(read, value, pointer, "inputs");
      p.outputs = load_bindings(read, value, pointer, "outputs");
      if (value.contains("after")) {
        const auto& after = value["after"];
        if (!after.is_array()) throw graph.error(pointer + "/after", "\"after\" must be an array of pass names");
        for (size_t j = 0; j < after.size(); ++j) {
          p.after.push_back(read.name(after[j], pointer + "/after/" + std::to_string(j), "a pass name"));
        }
      }
      if (value.contains("for_each")) p.for_each = read_for_each(graph, read, value["for_each"], pointer + "/for_each");
      if (value.contains("enabled")) {
        const auto& enabled = value["enabled"];
        if (enabled.is_boolean())
          p.enabled = enabled.get<bool>() ? "1" : "0";
        else if (enabled.is_string())
          p.enabled = enabled.get<std::string>();
        else
          throw graph.error(pointer + "/enabled", "\"enabled\" must be true, false or an expression string such as \"scene.refractors\"");
      }
      graph.passes.push_back(std::move(p));
    });
  }
}

}  // namespace

GraphDesc load_graph(JsonDocument doc) {
  GraphDesc graph;
  graph.doc = std::move(doc);
  Reader read(graph.doc);
  const auto& root = read.object(graph.doc.root(), "", "a graph file");
  read.only_keys(root, "", {"$schema", "name", "description", "parameters", "resources", "passes", "outputs", "linear_output", "editor"},
                 "a graph");
  // The editor's layout (caustica edit): its own business, but it must be an object.
  if (root.contains("editor")) read.object(root["editor"], "/editor", "\"editor\"");
  graph.name = root.contains("name") ? read.name(root["name"], "/name", "the graph name") : "graph";
  if (root.contains("description")) graph.description = read.string(root["description"], "/description", "\"description\"");
  // Each parameter, resource and pass is read on its own, so that one run reports all their errors.
  ErrorList errors;
  errors.attempt([&] { load_parameters(graph, read, errors); });
  errors.attempt([&] { load_resources(graph, read, errors); });
  errors.attempt([&] { load_passes(graph, read, errors); });
  errors.attempt([&] {
    if (!root.contains("outputs")) throw graph.error("", "a graph needs \"outputs\": the resources it produces");
    const auto& outputs = root["outputs"];
    if (!outputs.is_array() || outputs.empty()) throw graph.error("/outputs", "\"outputs\" must be a non-empty array of resource names");
    for (size_t i = 0; i < outputs.size(); ++i) {
      graph.outputs.push_back(read.name(outputs[i], "/outputs/" + std::to_string(i), "an output"));
    }
  });
  errors.attempt([&] {
    if (root.contains("linear_output")) graph.linear_output = read.name(root["linear_output"], "/linear_output", "the linear output");
  });
  errors.throw_if_any();
  return graph;
}

GraphDesc load_graph_file(const std::string& path) {
  return load_graph(JsonDocument::load(path));
}

std::vector<std::string> apply_still_values(GraphDesc& graph, const std::set<std::string>& kept, size_t level) {
  std::vector<std::string> applied;
  for (auto& p : graph.parameters) {
    if (p.while_still.empty() || kept.count(p.decl.name)) continue;
    const nlohmann::json& still = p.while_still[std::min(level, p.while_still.size() - 1)];
    if (still == p.value) continue;
    p.value = still;
    applied.push_back(p.decl.name + "=" + (still.is_string() ? still.get<std::string>() : still.dump()));
  }
  return applied;
}

void apply_overrides(GraphDesc& graph, const std::vector<std::string>& assignments, std::string_view command) {
  std::vector<std::string> known;
  for (const auto& p : graph.parameters) known.push_back(p.decl.name);
  for (const auto& assignment : assignments) {
    size_t eq = assignment.find('=');
    if (eq == std::string::npos || eq == 0) {
      throw UsageError(std::string(command) + " " + assignment + ": expected NAME=VALUE");  // the form of the command line, not the graph
    }
    std::string name = assignment.substr(0, eq);
    std::string text = assignment.substr(eq + 1);
    GraphParameter* target = nullptr;
    for (auto& p : graph.parameters) {
      if (p.decl.name == name) target = &p;
    }
    if (!target) {
      // Say what there is: a pass's own parameter of that name, or else the graph's parameters.
      std::string what_there_is = did_you_mean(name, known);
      for (const auto& pass : graph.passes) {
        if (what_there_is.empty() && pass.params.contains(name)) {
          what_there_is = "; '" + name + "' is a parameter of pass '" + pass.name + "', which only the graph file sets (" + pass.pointer +
                          "/params/" + name + "), or a graph parameter that it names as \"$NAME\"";
        }
      }
      if (what_there_is.empty()) {
        std::string list;
        for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
        what_there_is = known.empty() ? "; it has none" : "; its parameters: " + list;
      }
      throw InputError(std::string(command) + " " + assignment + ": graph " + graph.doc.path() + " has no parameter '" + name + "'" +
                       what_there_is);
    }
    nlohmann::json value = nlohmann::json::parse(text, nullptr, false);
    // A choice is a string: "--set distance=dv" means the choice "dv", and in a graph file of old,
    // whose grid was a choice of strings, "--set grid=2048" the choice "2048".
    if (value.is_discarded() || target->decl.type == ParamType::choice) value = text;
    std::string problem = check_param_value(target->decl, value);
    if (!problem.empty()) throw InputError(std::string(command) + " " + assignment + ": parameter '" + name + "' " + problem);
    target->value = value;
  }
}

std::string graph_text_with_values(const GraphDesc& graph) {
  std::string text = read_text_file(graph.doc.path(), JsonDocument::kMaxBytes);
  if (JsonDocument::parse(text, graph.doc.path()).root() != graph.doc.root()) {
    throw InputError(graph.doc.path() + ": changed on disk since it was loaded; not overwritten");
  }
  // Byte offset of each line start, to turn a value's line and column into a position.
  std::vector<size_t> line_starts{0};
  for (size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '\n') line_starts.push_back(i + 1);
  }
  struct Replacement {
    size_t begin, end;
    std::string value;
  };
  std::vector<Replacement> replacements;
  for (const auto& p : graph.parameters) {
    const std::string pointer = json_pointer_append(p.pointer, "default");
    const nlohmann::json* in_file = graph.doc.root().contains(nlohmann::json::json_pointer(pointer))
                                        ? &graph.doc.root().at(nlohmann::json::json_pointer(pointer))
                                        : nullptr;
    if (!in_file || *in_file == p.value) continue;
    const SourceLocation at = graph.doc.locate(pointer);
    const size_t begin = line_starts.at(static_cast<size_t>(at.line - 1)) + static_cast<size_t>(at.column - 1);
    size_t end = begin;
    if (text[begin] == '"') {
      for (end = begin + 1; end < text.size() && text[end] != '"'; ++end) end += text[end] == '\\' ? 1 : 0;
      ++end;
    } else {
      while (end < text.size() && std::string_view(",}] \t\r\n").find(text[end]) == std::string_view::npos) ++end;
    }
    replacements.push_back({begin, end, p.value.dump()});
  }
  std::sort(replacements.begin(), replacements.end(), [](const auto& a, const auto& b) { return a.begin > b.begin; });
  for (const auto& r : replacements) text.replace(r.begin, r.end - r.begin, r.value);
  return text;
}

}  // namespace caustica::graph
