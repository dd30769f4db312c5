#include "graph/graph_desc.h"

#include <algorithm>

#include <set>

#include "core/suggest.h"
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

void load_parameters(GraphDesc& graph, const Reader& read, ErrorList& errors) {
  const auto& root = graph.doc.root();
  if (!root.contains("parameters")) return;
  const auto& params = read.object(root["parameters"], "/parameters", "\"parameters\"");
  for (const auto& [key, value] : params.items()) {
    errors.attempt([&, &key = key, &value = value] {
      std::string pointer = json_pointer_append("/parameters", key);
      GraphParameter p;
      p.pointer = pointer;
      p.decl.name = read.name(nlohmann::json(key), pointer, "a parameter name");
      read.object(value, pointer, "a parameter");
      read.only_keys(value, pointer,
                     {"type", "default", "min", "max", "power_of_two", "choices", "description", "while_moving", "while_still"},
                     "a parameter");
      if (!value.contains("type")) throw graph.error(pointer, "parameter '" + key + "' needs a \"type\"");
      if (!value.contains("default")) throw graph.error(pointer, "parameter '" + key + "' needs a \"default\"");
      p.decl.type = parse_param_type(graph.doc, value["type"], pointer + "/type");
      for (const char* bound : {"min", "max"}) {
        if (!value.contains(bound)) continue;
        if (!value[bound].is_number()) throw graph.error(pointer + "/" + bound, std::string("\"") + bound + "\" must be a number");
        (std::string(bound) == "min" ? p.decl.min : p.decl.max) = value[bound].get<double>();
      }
      if (p.decl.min && p.decl.max && *p.decl.min > *p.decl.max) {
        throw graph.error(pointer + "/min", "parameter '" + key + "' has min above max");
      }
      if (value.contains("power_of_two")) {
        const std::string at = pointer + "/power_of_two";
        if (!value["power_of_two"].is_boolean()) throw graph.error(at, "\"power_of_two\" must be true or false");
        p.decl.power_of_two = value["power_of_two"].get<bool>();
        if (p.decl.power_of_two && (p.decl.type != ParamType::int_ || !p.decl.min || *p.decl.min < 1 || !p.decl.max)) {
          throw graph.error(
              at, "parameter '" + key + "' is a power of two, so it needs \"type\": \"int\", a \"min\" of at least 1 and a \"max\"");
        }
      }
      if (value.contains("choices")) {
        const auto& choices = value["choices"];
        if (!choices.is_array() || choices.empty())
          throw graph.error(pointer + "/choices", "\"choices\" must be a non-empty array of strings");
        for (size_t i = 0; i < choices.size(); ++i) {
          p.decl.choices.push_back(read.string(choices[i], pointer + "/choices/" + std::to_string(i), "a choice"));
        }
      } else if (p.decl.type == ParamType::choice) {
        throw graph.error(pointer, "parameter '" + key + "' of type choice needs \"choices\"");
      }
      if (value.contains("description")) p.decl.description = read.string(value["description"], pointer + "/description", "a description");
      p.decl.default_value = value["default"];
      std::string problem = check_param_value(p.decl, p.decl.default_value);
      if (!problem.empty()) throw graph.error(pointer + "/default", "the default of parameter '" + key + "' " + problem);
      p.value = p.decl.default_value;
      for (auto [name, target] : {std::pair{"while_moving", &p.while_moving}, std::pair{"while_still", &p.while_still}}) {
        if (!value.contains(name)) continue;
        problem = check_param_value(p.decl, value[name]);
        if (!problem.empty())
          throw graph.error(pointer + "/" + name, std::string("the ") + name + " value of parameter '" + key + "' " + problem);
        *target = value[name];
      }
      graph.parameters.push_back(std::move(p));
    });
  }
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
      read.only_keys(value, pointer, {"type", "format", "width", "height", "mips", "layers", "size", "fallback", "description"},
                     "a resource");
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
      read.only_keys(value, pointer, {"name", "type", "params", "inputs", "outputs", "after", "enabled", "description"}, "a pass");
      PassDesc p;
      p.pointer = pointer;
      if (!value.contains("type")) throw graph.error(pointer, "pass needs a \"type\"");
      p.type = read.string(value["type"], pointer + "/type", "\"type\"");
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
