#pragma once
// The graph as the editor changes it: no window, no device. Every edit is an operation on the
// graph file's JSON (key order kept) that is checked as a whole graph, loaded and compiled as
// `caustica validate` does; an edit that would make the graph invalid is refused with the
// validator's message and changes nothing. A file that loads as a graph but does not compile opens
// refused (refusal() says why) so that it can be repaired: while refused, every edit that leaves a
// loadable graph is taken, and the one that makes it compile ends the refusal. Every edit can be
// undone and redone. Saving writes the
// author's text back with only the edited parts changed (json_text.h), through a temporary file.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "graph/graph_desc.h"
#include "graph/pass_type.h"
#include "model/json_text.h"

namespace caustica::editor {

class GraphModel {
 public:
  // Throws InputError (file, line, JSON pointer) when the file cannot be read or is not a graph
  // (its JSON or its structure); one that does not compile opens refused.
  static GraphModel open(const std::string& path, const graph::PassRegistry& registry);
  GraphModel(std::string text, std::string path, const graph::PassRegistry& registry);

  const nlohmann::ordered_json& json() const { return doc_; }
  const std::string& path() const { return path_; }
  const graph::PassRegistry& registry() const { return *registry_; }
  // The current graph as the engine loads it.
  graph::GraphDesc desc() const;
  // A pass's type: the registry's, or for a user pass its own ports and parameters as declared.
  graph::PassTypeDecl pass_type(const nlohmann::ordered_json& pass) const;
  // What save() writes: the text as loaded with the edits applied.
  const std::string& text() const { return text_; }
  // Whether the graph differs from the file as opened or last saved.
  bool modified() const { return doc_ != saved_; }
  // Why the graph as it stands does not compile (the validator's message); empty when it does.
  const std::string& refusal() const { return refusal_; }

  // ---- edits: each throws InputError and changes nothing when refused ----
  // Adds a pass of a registered type with every parameter at its default, a new resource for each
  // required output (named pass_port, format and extent from the port) and each required input
  // bound to a resource of an accepted format that a pass writes. Returns the pass's name (`name`,
  // or the type made unique).
  std::string add_pass(const std::string& type, const std::string& name = "");
  // Adds a user pass ("compute" or "fullscreen") whose ports and parameters are those its shader
  // declares (a file relative to the graph's, or absolute), bound as add_pass binds them.
  std::string add_user_pass(const std::string& kind, const std::string& shader, const std::string& name = "");
  // Removes a pass, its place in other passes' "after" and its position, and every resource that
  // nothing else names any more.
  void remove_pass(const std::string& pass);
  void rename_pass(const std::string& pass, const std::string& new_name);
  // Binds a port (an input or an output, as the pass type declares it) to an existing resource.
  // An input's new size carries over to the pass's outputs of its extent group that nothing else
  // names (the resources add_pass made), so that re-wiring a new pass keeps it valid. A read_write
  // port bound to a resource another pass writes orders its pass "after" the last such writer.
  void connect(const std::string& pass, const std::string& port, const std::string& resource);
  void disconnect(const std::string& pass, const std::string& port);
  // A literal within the parameter's declared range, or "$name" of a graph parameter.
  void set_param(const std::string& pass, const std::string& param, const nlohmann::json& value);
  void reset_param(const std::string& pass, const std::string& param);     // back to the type's default
  void set_enabled(const std::string& pass, const nlohmann::json& value);  // true, false or an expression
  // The pass made once per light or caustic view (`kind`: "light" or "caustic_view", its
  // "for_each"), or once again (""): the resources it writes with it, and its "light" parameter,
  // where its type has one, following its instance's light or view ("$light").
  void set_for_each(const std::string& pass, const std::string& kind);

  void add_resource(const std::string& name, const nlohmann::ordered_json& description);
  void remove_resource(const std::string& name);
  // Renames the resource and every binding, output and fallback that names it.
  void rename_resource(const std::string& name, const std::string& new_name);
  void set_resource_field(const std::string& name, const std::string& field, const nlohmann::json& value);

  void add_parameter(const std::string& name, const nlohmann::ordered_json& declaration);
  void remove_parameter(const std::string& name);
  void set_parameter_field(const std::string& name, const std::string& field, const nlohmann::json& value);

  void set_graph_field(const std::string& field, const nlohmann::json& value);  // "name", "description" or "linear_output"
  void set_outputs(const std::vector<std::string>& outputs);
  // The pass's place on the editor's canvas, kept in the file's "editor" block (the engine ignores it).
  void set_position(const std::string& pass, float x, float y);

  // ---- history ----
  bool can_undo() const { return !undo_.empty(); }
  bool can_redo() const { return !redo_.empty(); }
  // What the next undo or redo would change ("add pass tonemap"); empty when there is none.
  std::string undo_label() const { return undo_.empty() ? "" : undo_.back().label; }
  std::string redo_label() const { return redo_.empty() ? "" : redo_.back().label; }
  bool undo();
  bool redo();

  // ---- files ----
  // Whether the file on disk is no longer what was opened or last saved (another editor wrote it).
  bool changed_on_disk() const;
  // Writes text() to path() through a temporary file and a rename. Refuses (InputError) when the
  // file changed on disk meanwhile, unless `overwrite` (after the user confirmed).
  void save(bool overwrite = false);
  // Writes to another file, which becomes path().
  void save_as(const std::string& path);

 private:
  struct Step {
    nlohmann::ordered_json doc;
    std::string text;  // as text() was then, so that an undo after a save restores those bytes
    std::string label;
    std::string refusal;
  };
  struct Checked {
    std::string text, refusal;
  };
  template <class Change>
  void apply(const std::string& label, Change&& change);
  // `doc`'s text and, when it does not compile, the compiler's message; throws the loader's
  // InputError when it is not a graph.
  Checked check(const nlohmann::ordered_json& doc) const;
  // Makes `doc` the current graph, the one before it an undo step. Refuses (the compiler's
  // InputError) a graph that does not compile unless the current one does not either.
  void commit(const std::string& label, nlohmann::ordered_json doc, Checked checked);
  nlohmann::ordered_json& pass_json(nlohmann::ordered_json& doc, const std::string& pass) const;
  // doc[section][name]; throws InputError naming the missing `what` (with a suggestion).
  nlohmann::ordered_json& member(nlohmann::ordered_json& doc, const char* section, const std::string& name, const char* what) const;
  bool step(std::vector<Step>& from, std::vector<Step>& to);
  std::string add_pass_of(const graph::PassTypeDecl& decl, const nlohmann::ordered_json& declared, const std::string& name);
  // `decl` (a user pass kind) given the ports and parameters its shader declares; returns them as
  // the graph file writes them.
  nlohmann::ordered_json declare_user_pass(graph::PassTypeDecl& decl, const std::string& shader) const;
  void order_after_last_writer(nlohmann::ordered_json& doc, nlohmann::ordered_json& pass, const std::string& resource) const;

  const graph::PassRegistry* registry_;
  std::string path_;
  PreservingWriter base_;  // the file as opened or last saved: what text() preserves
  nlohmann::ordered_json doc_, saved_;
  std::string text_;
  std::string refusal_;
  std::vector<Step> undo_, redo_;
};

// A wire of the canvas: from a pass's output to an input that reads what it writes, in this frame
// or (a history input, "NAME@previous") as the last frame left it.
struct Wire {
  std::string writer, output, reader, input, resource;
  bool history = false;
  bool operator==(const Wire&) const = default;
};
std::vector<Wire> wires(const nlohmann::ordered_json& graph);

// What the editor's window runs while a graph refused from the start is repaired (there is no last
// good frame to keep): a black picture, under the graph's name.
std::string stand_in_graph(const std::string& name);

}  // namespace caustica::editor
