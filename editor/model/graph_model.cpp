#include "model/graph_model.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <set>

#include "core/error.h"
#include "core/paths.h"
#include "core/suggest.h"
#include "graph/compiler.h"
#include "graph/per_light.h"
#include "graph/user_pass_type.h"
#include "io/files.h"
#include "io/json_document.h"
#include "model/json_text.h"
#include "model/pass_wiring.h"
#include "shader/shader_compiler.h"

namespace caustica::editor {
namespace {

using nlohmann::ordered_json;

std::vector<std::string> pass_names(const ordered_json& doc) {
  std::vector<std::string> names;
  for (const auto& pass : doc["passes"]) {
    if (pass.is_object() && pass.contains("name") && pass["name"].is_string()) names.push_back(pass["name"].get<std::string>());
  }
  return names;
}

std::vector<std::string> keys(const ordered_json& object) {
  std::vector<std::string> out;
  if (object.is_object()) {
    for (const auto& [key, value] : object.items()) out.push_back(key);
  }
  return out;
}

// Renames a key in place, keeping its position among the others.
void rename_key(ordered_json& object, const std::string& from, const std::string& to) {
  ordered_json renamed = ordered_json::object();
  for (auto& [key, value] : object.items()) renamed[key == from ? to : key] = std::move(value);
  object = std::move(renamed);
}

// The resource a binding names: itself, or the one whose last frame a history input reads.
std::string resource_of_binding(const std::string& binding) {
  std::string source = graph::history_source(binding);
  return source.empty() ? binding : source;
}

// Every place a resource's name appears outside "resources": bindings, outputs, fallbacks.
void for_each_resource_reference(ordered_json& doc, const std::function<void(ordered_json&)>& visit) {
  for (auto& pass : doc["passes"]) {
    for (const char* section : {"inputs", "outputs"}) {
      if (!pass.contains(section)) continue;
      for (auto& [port, resource] : pass[section].items()) visit(resource);
    }
  }
  for (auto& output : doc["outputs"]) visit(output);
  if (doc.contains("linear_output")) visit(doc["linear_output"]);
  for (auto& [name, resource] : doc["resources"].items()) {
    if (resource.contains("fallback") && resource["fallback"].is_string()) visit(resource["fallback"]);
  }
}

bool writes(const graph::PortDecl& port) {
  return port.access != graph::PortAccess::read;
}

}  // namespace

GraphModel GraphModel::open(const std::string& path, const graph::PassRegistry& registry) {
  return GraphModel(read_text_file(path, JsonDocument::kMaxBytes), path, registry);
}

GraphModel::GraphModel(std::string text, std::string path, const graph::PassRegistry& registry)
    : registry_(&registry), path_(std::move(path)), base_(std::move(text)) {
  // The engine's parser first: its messages name the line, and it refuses what nlohmann accepts
  // (duplicate keys).
  JsonDocument::parse(base_.original(), path_);
  doc_ = saved_ = ordered_json::parse(base_.original());
  Checked checked = check(doc_);
  text_ = std::move(checked.text);
  refusal_ = std::move(checked.refusal);
}

graph::GraphDesc GraphModel::desc() const {
  return graph::load_graph(JsonDocument::parse(text(), path_));
}

GraphModel::Checked GraphModel::check(const ordered_json& doc) const {
  Checked checked{base_.write(doc), ""};
  const graph::GraphDesc graph = graph::load_graph(JsonDocument::parse(checked.text, path_));
  graph::CompileOptions options;
  options.scene_values = graph::typical_scene_values();
  try {
    graph::compile_graph(graph, *registry_, options);
  } catch (const InputError& e) {
    checked.refusal = e.what();
  }
  return checked;
}

void GraphModel::commit(const std::string& label, ordered_json doc, Checked checked) {
  if (!checked.refusal.empty() && refusal_.empty()) throw InputError(checked.refusal);
  undo_.push_back({std::move(doc_), std::move(text_), label, std::move(refusal_)});
  redo_.clear();
  doc_ = std::move(doc);
  text_ = std::move(checked.text);
  refusal_ = std::move(checked.refusal);
}

template <class Change>
void GraphModel::apply(const std::string& label, Change&& change) {
  ordered_json next = doc_;
  change(next);
  if (next == doc_) return;  // nothing to undo
  Checked checked = check(next);
  commit(label, std::move(next), std::move(checked));
}

ordered_json& GraphModel::pass_json(ordered_json& doc, const std::string& pass) const {
  for (auto& p : doc["passes"]) {
    if (p.value("name", "") == pass) return p;
  }
  throw InputError(path_ + ": no pass named '" + pass + "'" + did_you_mean(pass, pass_names(doc)));
}

ordered_json& GraphModel::member(ordered_json& doc, const char* section, const std::string& name, const char* what) const {
  if (!doc.contains(section) || !doc[section].contains(name))
    throw InputError(path_ + ": no " + what + " named '" + name + "'" + did_you_mean(name, keys(doc.value(section, ordered_json()))));
  return doc[section][name];
}

graph::PassTypeDecl GraphModel::pass_type(const ordered_json& pass) const {
  const std::string type = pass.value("type", "");
  const graph::PassTypeDecl* decl = registry_->find(type);
  if (!decl) throw InputError(path_ + ": unknown pass type '" + type + "'" + did_you_mean(type, registry_->names()));
  if (decl->user_kind == graph::UserShaderKind::none) return *decl;
  // A user pass's ports and parameters are its own, as the graph declares them.
  graph::PassTypeDecl own = *decl;
  for (const auto& p : desc().passes) {
    if (p.name != pass.value("name", "") || !p.user) continue;
    own.ports = p.user->ports;
    own.params = p.user->params;
  }
  return own;
}

std::string GraphModel::add_pass(const std::string& type, const std::string& wanted_name) {
  const graph::PassTypeDecl* decl = registry_->find(type);
  if (!decl) throw InputError(path_ + ": unknown pass type '" + type + "'" + did_you_mean(type, registry_->names()));
  if (decl->user_kind != graph::UserShaderKind::none) {
    throw InputError(path_ + ": a " + type + " pass is declared from its shader: add it with its shader file (add_user_pass)");
  }
  return add_pass_of(*decl, ordered_json::object(), wanted_name);
}

std::string GraphModel::add_user_pass(const std::string& kind, const std::string& shader, const std::string& wanted_name) {
  const graph::PassTypeDecl* decl = registry_->find(kind);
  if (!decl || decl->user_kind == graph::UserShaderKind::none) {
    throw InputError(path_ + ": '" + kind + "' is not a kind of user pass (compute, fullscreen)");
  }
  graph::PassTypeDecl own = *decl;
  const ordered_json declared = declare_user_pass(own, shader);
  return add_pass_of(own, declared, wanted_name);
}

// A user pass's ports and parameters as its shader declares them (docs/shader_passes.md): each
// binding a port (a sampled image read, a storage image read, written or both by its qualifiers, a
// buffer), a fragment shader's outputs written ports, each push-constant member a parameter, and a
// compute pass dispatched over its first written image. What the shader cannot say (an array's
// layers, a colour attachment's format, ranges) is left at a default or refused, for the author.
ordered_json GraphModel::declare_user_pass(graph::PassTypeDecl& decl, const std::string& shader) const {
  std::filesystem::path file = shader;
  if (file.is_relative()) file = std::filesystem::absolute(path_).parent_path() / file;
  const shader::ReflectedShader compiled = shader::process_shader_compiler().compile_reflected(file.string());
  const shader::Reflection& reflection = compiled.reflection;
  const bool fullscreen = decl.user_kind == graph::UserShaderKind::fullscreen;
  if (file.extension() != (fullscreen ? ".frag" : ".comp")) {
    throw InputError(file.string() + ": a " + decl.type + " pass's shader is a " + (fullscreen ? ".frag" : ".comp") + " file");
  }
  ordered_json ports = ordered_json::object(), parameters = ordered_json::object();
  decl.ports.clear();
  decl.params.clear();
  auto add_port = [&](graph::PortDecl port, ordered_json json) {
    json["access"] = port.access == graph::PortAccess::read ? "read" : port.access == graph::PortAccess::write ? "write" : "read_write";
    if (!port.formats.empty()) json["formats"] = {graph::format_info(port.formats.front()).name};
    ports[port.name] = json;
    decl.ports.push_back(std::move(port));
  };
  // The parameters: the push-constant block's members, or a uniform block Params's (no port).
  const std::vector<shader::ReflectedMember>* parameter_members = &reflection.push_members;
  for (const auto& b : reflection.bindings) {
    if (b.kind == shader::BindingKind::uniform_buffer && b.block == graph::kParamsBlock) {
      parameter_members = &b.members;
      continue;
    }
    const std::string at = b.place.file + ":" + std::to_string(b.place.line) + ": '" + b.name + "'";
    if (b.arrayed) throw InputError(at + " is an array: declare its port with its layers by hand (docs/shader_passes.md)");
    graph::PortDecl port;
    port.name = b.name;
    ordered_json json = ordered_json::object();
    switch (b.kind) {
      case shader::BindingKind::sampled_image: break;
      case shader::BindingKind::storage_image:
        port.usage = graph::PortUsage::storage;
        port.access = b.readonly ? graph::PortAccess::read : b.writeonly ? graph::PortAccess::write : graph::PortAccess::read_write;
        if (const auto format = graph::parse_format(b.format)) port.formats = {*format};
        if (port.access == graph::PortAccess::read) json["usage"] = "storage";
        break;
      case shader::BindingKind::storage_buffer:
      case shader::BindingKind::uniform_buffer:
        port.kind = graph::ResourceKind::buffer;
        json["type"] = "buffer";
        port.usage = b.kind == shader::BindingKind::uniform_buffer ? graph::PortUsage::uniform : graph::PortUsage::storage;
        if (port.usage == graph::PortUsage::uniform) json["usage"] = "uniform";
        port.access = b.readonly || port.usage == graph::PortUsage::uniform ? graph::PortAccess::read : graph::PortAccess::read_write;
        break;
      default: throw InputError(at + " is no image or buffer a port can bind: declare the pass by hand (docs/shader_passes.md)");
    }
    add_port(std::move(port), std::move(json));
  }
  for (const auto& out : reflection.outputs) {
    graph::PortDecl port;
    port.name = out.name;
    port.access = graph::PortAccess::write;
    port.usage = graph::PortUsage::color_attachment;
    port.formats = {graph::Format::rgba16f};
    add_port(std::move(port), ordered_json::object());
  }
  for (const auto& m : *parameter_members) {
    graph::ParamDecl param;
    param.name = m.name;
    if (m.type == "float") {
      param.default_value = 0.0;
    } else if (m.type == "int" || m.type == "uint") {
      param.type = graph::ParamType::int_;
      param.default_value = 0;
    } else if (m.type == "bool") {
      param.type = graph::ParamType::bool_;
      param.default_value = false;
    } else {
      throw InputError(m.place.file + ":" + std::to_string(m.place.line) + ": parameter block member '" + m.name + "' is " + m.type +
                       "; a parameter is a float, int, uint or bool");
    }
    parameters[param.name] = {{"type", graph::param_type_name(param.type)}, {"default", param.default_value}};
    decl.params.push_back(std::move(param));
  }
  ordered_json declared = {{"shader", shader}, {"ports", ports}};
  if (!parameters.empty()) declared["parameters"] = parameters;
  if (!fullscreen) {
    const auto over = std::find_if(decl.ports.begin(), decl.ports.end(), [](const graph::PortDecl& p) {
      return p.kind == graph::ResourceKind::image && p.access != graph::PortAccess::read;
    });
    if (over == decl.ports.end())
      throw InputError(file.string() + ": it writes no image to dispatch over: declare its \"dispatch\" by hand");
    declared["dispatch"] = over->name;
  }
  return declared;
}

std::string GraphModel::add_pass_of(const graph::PassTypeDecl& decl_ref, const ordered_json& declared, const std::string& wanted_name) {
  const graph::PassTypeDecl* decl = &decl_ref;
  const std::string& type = decl->type;
  const std::vector<std::string> taken = pass_names(doc_);
  auto is_taken = [&](const std::string& n) { return std::find(taken.begin(), taken.end(), n) != taken.end(); };
  std::string name = wanted_name.empty() ? type : wanted_name;
  if (!wanted_name.empty() && is_taken(name)) throw InputError(path_ + ": a pass named '" + name + "' already exists");
  for (int i = 2; is_taken(name); ++i) name = type + "_" + std::to_string(i);

  ordered_json pass = {{"name", name}, {"type", type}};
  pass.update(declared);
  ordered_json params = ordered_json::object();
  for (const auto& p : decl->params) params[p.name] = p.default_value;
  if (!params.empty()) pass["params"] = params;

  // Inputs: resources of an accepted format that a pass writes, the latest writer in the file
  // first; ports of one extent group take resources of one size. Candidates are tried in that
  // order until the graph compiles.
  const PassWiring wiring(doc_, *decl, name, path_);
  std::string first_error;
  const bool added = wiring.try_each(pass, [&](ordered_json next) {
    try {
      Checked checked = check(next);
      commit("add pass " + name, std::move(next), std::move(checked));
    } catch (const InputError& e) {
      if (first_error.empty()) first_error = e.what();
      return false;
    }
    return true;
  });
  if (!added) {
    throw InputError(first_error.empty() ? path_ + ": cannot add a " + type + " pass: no resources of one size fit its inputs"
                                         : first_error);
  }
  return name;
}

void GraphModel::remove_pass(const std::string& name) {
  apply("remove pass " + name, [&](ordered_json& doc) {
    const ordered_json removed = pass_json(doc, name);
    auto& passes = doc["passes"];
    passes.erase(std::remove_if(passes.begin(), passes.end(), [&](const ordered_json& p) { return p.value("name", "") == name; }),
                 passes.end());
    for (auto& p : passes) {
      if (!p.contains("after")) continue;
      auto& after = p["after"];
      after.erase(std::remove(after.begin(), after.end(), ordered_json(name)), after.end());
      if (after.empty()) p.erase("after");
    }
    if (doc.contains("editor") && doc["editor"].contains("positions")) doc["editor"]["positions"].erase(name);
    // Resources only this pass named go with it.
    std::set<std::string> named;
    for_each_resource_reference(doc, [&](ordered_json& r) { named.insert(resource_of_binding(r.get<std::string>())); });
    for (const char* section : {"inputs", "outputs"}) {
      if (!removed.contains(section)) continue;
      for (const auto& [port, resource] : removed[section].items()) {
        if (!named.count(resource.get<std::string>())) doc["resources"].erase(resource.get<std::string>());
      }
    }
  });
}

void GraphModel::rename_pass(const std::string& name, const std::string& new_name) {
  const auto taken = pass_names(doc_);
  if (new_name != name && std::find(taken.begin(), taken.end(), new_name) != taken.end())
    throw InputError(path_ + ": a pass named '" + new_name + "' already exists");
  apply("rename pass " + name + " to " + new_name, [&](ordered_json& doc) {
    pass_json(doc, name)["name"] = new_name;
    for (auto& p : doc["passes"]) {
      if (!p.contains("after")) continue;
      for (auto& a : p["after"]) {
        if (a == name) a = new_name;
      }
    }
    if (doc.contains("editor") && doc["editor"].contains("positions") && doc["editor"]["positions"].contains(name))
      rename_key(doc["editor"]["positions"], name, new_name);
  });
}

// A read_write port reads what another pass wrote, and the compiler wants that order stated: the
// pass goes "after" the last other pass in the file that writes `resource` ("after" right after
// "type", where the bundled graphs have it).
void GraphModel::order_after_last_writer(ordered_json& doc, ordered_json& pass, const std::string& resource) const {
  std::string writer;
  for (const auto& other : doc["passes"]) {
    if (&other == &pass || !other.contains("outputs")) continue;
    for (const auto& [port, bound] : other["outputs"].items()) {
      if (bound == resource) writer = other.value("name", "");
    }
  }
  if (writer.empty()) return;
  if (pass.contains("after")) {
    if (!pass["after"].is_array()) return;  // the compiler names what is wrong with it
    for (const auto& name : pass["after"]) {
      if (name == writer) return;
    }
    pass["after"].push_back(writer);
    return;
  }
  ordered_json ordered = ordered_json::object();
  for (auto& [key, value] : pass.items()) {
    ordered[key] = std::move(value);
    if (key == "type") ordered["after"] = ordered_json::array({writer});
  }
  if (!ordered.contains("after")) ordered["after"] = ordered_json::array({writer});
  pass = std::move(ordered);
}

void GraphModel::connect(const std::string& pass, const std::string& port_name, const std::string& resource) {
  apply("connect " + pass + "." + port_name + " to " + resource, [&](ordered_json& doc) {
    ordered_json& p = pass_json(doc, pass);
    const graph::PassTypeDecl type = pass_type(p);
    const graph::PortDecl* port = type.find_port(port_name);
    if (!port) throw InputError(path_ + ": pass type '" + p.value("type", "") + "' has no port '" + port_name + "'");
    p[writes(*port) ? "outputs" : "inputs"][port_name] = resource;
    if (port->access == graph::PortAccess::read_write) order_after_last_writer(doc, p, resource);
    // The pass's outputs of the same extent group that only it names follow the input's size, as
    // they did when add_pass made them.
    if (writes(*port) || port->extent_group.empty() || !doc["resources"].contains(resource) || !p.contains("outputs")) return;
    std::map<std::string, int> references;
    for_each_resource_reference(doc, [&](ordered_json& r) { ++references[r.get<std::string>()]; });
    const ordered_json source = doc["resources"][resource];
    for (const auto& [out_port, out_resource] : p["outputs"].items()) {
      const graph::PortDecl* out = type.find_port(out_port);
      const std::string name = out_resource.get<std::string>();
      if (!out || out->extent_group != port->extent_group || references[name] != 1 || !doc["resources"].contains(name)) continue;
      ordered_json& target = doc["resources"][name];
      for (const char* axis : {"width", "height"}) {
        if (source.contains(axis))
          target[axis] = source[axis];
        else
          target.erase(axis);
      }
    }
  });
}

void GraphModel::disconnect(const std::string& pass, const std::string& port_name) {
  apply("disconnect " + pass + "." + port_name, [&](ordered_json& doc) {
    ordered_json& p = pass_json(doc, pass);
    for (const char* section : {"inputs", "outputs"}) {
      if (!p.contains(section) || !p[section].contains(port_name)) continue;
      p[section].erase(port_name);
      if (p[section].empty()) p.erase(section);
      return;
    }
    throw InputError(path_ + ": port '" + port_name + "' of pass '" + pass + "' is not connected");
  });
}

void GraphModel::set_param(const std::string& pass, const std::string& param, const nlohmann::json& value) {
  apply("set " + pass + "." + param + " = " + value.dump(), [&](ordered_json& doc) {
    ordered_json& p = pass_json(doc, pass);
    p["params"][param] = ordered_json::parse(value.dump());
  });
}

void GraphModel::reset_param(const std::string& pass, const std::string& param) {
  apply("reset " + pass + "." + param, [&](ordered_json& doc) {
    ordered_json& p = pass_json(doc, pass);
    if (!p.contains("params")) return;
    p["params"].erase(param);
    if (p["params"].empty()) p.erase("params");
  });
}

void GraphModel::set_enabled(const std::string& pass, const nlohmann::json& value) {
  apply("set " + pass + " enabled = " + value.dump(),
        [&](ordered_json& doc) { pass_json(doc, pass)["enabled"] = ordered_json::parse(value.dump()); });
}

void GraphModel::set_for_each(const std::string& pass, const std::string& kind) {
  if (!kind.empty() && kind != graph::kForEachLight && kind != graph::kForEachCausticView) {
    throw InputError(path_ + ": unknown \"for_each\" '" + kind + "': a pass is made once per light (\"light\"), once per caustic view " +
                     "(\"caustic_view\") or once (\"\")");
  }
  apply((kind.empty() ? "make " + pass + " once" : "make " + pass + " once per " + kind), [&](ordered_json& doc) {
    ordered_json& p = pass_json(doc, pass);
    wire_for_each(doc, p, registry_->find(p.value("type", "")), kind);
  });
}

void GraphModel::add_resource(const std::string& name, const ordered_json& description) {
  if (doc_["resources"].contains(name)) throw InputError(path_ + ": a resource named '" + name + "' already exists");
  apply("add resource " + name, [&](ordered_json& doc) { doc["resources"][name] = description; });
}

void GraphModel::remove_resource(const std::string& name) {
  apply("remove resource " + name, [&](ordered_json& doc) {
    member(doc, "resources", name, "resource");
    doc["resources"].erase(name);
  });
}

void GraphModel::rename_resource(const std::string& name, const std::string& new_name) {
  if (new_name != name && doc_["resources"].contains(new_name))
    throw InputError(path_ + ": a resource named '" + new_name + "' already exists");
  apply("rename resource " + name + " to " + new_name, [&](ordered_json& doc) {
    member(doc, "resources", name, "resource");
    rename_key(doc["resources"], name, new_name);
    for_each_resource_reference(doc, [&](ordered_json& r) {
      if (r == name) r = new_name;
      if (r == graph::history_of(name)) r = graph::history_of(new_name);
    });
  });
}

void GraphModel::set_resource_field(const std::string& name, const std::string& field, const nlohmann::json& value) {
  apply("set " + name + "." + field + " = " + value.dump(),
        [&](ordered_json& doc) { member(doc, "resources", name, "resource")[field] = ordered_json::parse(value.dump()); });
}

void GraphModel::add_parameter(const std::string& name, const ordered_json& declaration) {
  if (doc_.contains("parameters") && doc_["parameters"].contains(name))
    throw InputError(path_ + ": a parameter named '" + name + "' already exists");
  apply("add parameter " + name, [&](ordered_json& doc) { doc["parameters"][name] = declaration; });
}

void GraphModel::remove_parameter(const std::string& name) {
  apply("remove parameter " + name, [&](ordered_json& doc) {
    member(doc, "parameters", name, "parameter");
    doc["parameters"].erase(name);
  });
}

void GraphModel::set_parameter_field(const std::string& name, const std::string& field, const nlohmann::json& value) {
  apply("set parameter " + name + "." + field + " = " + value.dump(),
        [&](ordered_json& doc) { member(doc, "parameters", name, "parameter")[field] = ordered_json::parse(value.dump()); });
}

void GraphModel::set_graph_field(const std::string& field, const nlohmann::json& value) {
  if (field != "name" && field != "description" && field != "linear_output")
    throw InputError(path_ + ": the graph's \"" + field + "\" is not a field the editor sets");
  apply("set graph " + field, [&](ordered_json& doc) { doc[field] = ordered_json::parse(value.dump()); });
}

void GraphModel::set_outputs(const std::vector<std::string>& outputs) {
  apply("set outputs", [&](ordered_json& doc) { doc["outputs"] = outputs; });
}

void GraphModel::set_position(const std::string& pass, float x, float y) {
  apply("move " + pass, [&](ordered_json& doc) {
    pass_json(doc, pass);
    doc["editor"]["positions"][pass] = {std::lround(x), std::lround(y)};
  });
}

// Moves the newest step of `from` onto `to`, swapping it with the current document.
bool GraphModel::step(std::vector<Step>& from, std::vector<Step>& to) {
  if (from.empty()) return false;
  to.push_back({std::move(doc_), std::move(text_), from.back().label, std::move(refusal_)});
  doc_ = std::move(from.back().doc);
  text_ = std::move(from.back().text);
  refusal_ = std::move(from.back().refusal);
  from.pop_back();
  return true;
}

bool GraphModel::undo() {
  return step(undo_, redo_);
}
bool GraphModel::redo() {
  return step(redo_, undo_);
}

bool GraphModel::changed_on_disk() const {
  try {
    return read_text_file(path_, JsonDocument::kMaxBytes) != base_.original();
  } catch (const InputError&) {
    return true;  // deleted or unreadable
  }
}

void GraphModel::save(bool overwrite) {
  if (!overwrite && changed_on_disk()) throw InputError(path_ + ": changed on disk since it was opened or last saved; not overwritten");
  io::write_text_atomically(path_, text_);
  base_ = PreservingWriter(text_);
  saved_ = doc_;
}

void GraphModel::save_as(const std::string& path) {
  io::write_text_atomically(path, text_);
  path_ = path;
  base_ = PreservingWriter(text_);
  saved_ = doc_;
}

std::vector<Wire> wires(const ordered_json& graph) {
  std::vector<Wire> found;
  if (!graph.contains("passes")) return found;
  for (const auto& reader : graph["passes"]) {
    if (!reader.contains("inputs")) continue;
    for (const auto& [input, binding] : reader["inputs"].items()) {
      const std::string resource = resource_of_binding(binding.get<std::string>());
      const bool history = resource != binding.get<std::string>();
      for (const auto& writer : graph["passes"]) {
        // A read_write port's own binding is no wire; a pass reading its own last result is one.
        if (&writer == &reader && !history) continue;
        if (!writer.contains("outputs")) continue;
        for (const auto& [output, written] : writer["outputs"].items()) {
          if (written == resource) found.push_back({writer["name"], output, reader["name"], input, resource, history});
        }
      }
    }
  }
  return found;
}

std::string stand_in_graph(const std::string& name) {
  const ordered_json graph = {{"name", name},
                              {"description", "the editor's stand-in while " + name + " does not compile"},
                              {"resources",
                               {{"hdr", {{"type", "image"}, {"format", "rgba16f"}, {"width", "output.width"}, {"height", "output.height"}}},
                                {"ldr", {{"type", "image"}, {"format", "rgba8"}}}}},
                              {"passes",
                               {{{"name", "pattern"}, {"type", "pattern"}, {"outputs", {{"color", "hdr"}}}},
                                {{"name", "black"},
                                 {"type", "tonemap"},
                                 {"params", {{"exposure", 0.0}}},
                                 {"inputs", {{"source", "hdr"}}},
                                 {"outputs", {{"target", "ldr"}}}}}},
                              {"outputs", {"ldr"}}};
  return graph.dump(2);
}

}  // namespace caustica::editor
