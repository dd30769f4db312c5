#include "edit/graph_editor.h"

#include <imgui.h>

#include <algorithm>
#include <cfloat>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "model/recovery_copy.h"

namespace caustica::editor {

const char* const kEditScriptHelp = R"(An edit script (--script FILE) runs one action per frame drawn, each as the canvas or the keys
would do it, and logs "edit: LINE: ok" or "edit: LINE: refused: MESSAGE":
  add TYPE [X Y]                 add a pass of a registered type at a canvas position
  connect PASS PORT RESOURCE     bind a port to a resource
  disconnect PASS PORT           unbind a port
  set PASS PARAM JSON            set a parameter of a pass
  for-each PASS light|caustic_view|once
                                 make a pass (and what it writes) once per light, per caustic view, or once
  param NAME JSON                set a graph parameter (its default in the file)
  select PASS...                 select passes;  remove  removes the selected ones
  rename PASS NEW_NAME           rename a pass
  undo | redo | save | save!     save! overwrites a file that changed on disk
  where PASS.PORT                log where the port is drawn in the window (to drive the mouse)
  layout                         log where the canvas, each node and each wire label are drawn
  screenshot FILE                write the next frame's output
  quit                           close the editor
)";

namespace {

using nlohmann::ordered_json;

// Which pass an editor error concerns: the "(at /passes/N..." of the validator's message.
std::string pass_named_in(const std::string& message, const ordered_json& doc) {
  const size_t at = message.rfind("(at /passes/");
  if (at == std::string::npos) return "";
  const size_t index = std::strtoul(message.c_str() + at + 12, nullptr, 10);
  if (index >= doc["passes"].size()) return "";
  return doc["passes"][index].value("name", "");
}

// The panels' font, as the canvas measures its text at zoom 1. The font atlas is built with the
// viewer, before the first frame sets ImGui's current font.
TextMeasure panel_text() {
  const ImFont* font = ImGui::GetIO().Fonts->Fonts[0];
  return {font->FontSize, [font](const std::string& text) { return font->CalcTextSizeA(font->FontSize, FLT_MAX, 0.0f, text.c_str()).x; }};
}

}  // namespace

GraphEditor::GraphEditor(Viewer& viewer, GraphModel& model, std::string script) : viewer_(viewer), model_(model), text_(panel_text()) {
  if (!script.empty()) {
    std::istringstream lines(read_text_file(script, 1 << 20));
    for (std::string line; std::getline(lines, line);) {
      if (!line.empty() && line[0] != '#') script_.push_back(line);
    }
  }
  viewer_.extra_ui = [this](const graph::FrameResult& frame) { draw(frame); };
  viewer_.on_key = [this](const WindowEvents::Key& key) { return on_key(key); };
  viewer_.after_frame = [this] { step_script(); };
  // A device failure (a frame that does not finish) ends the session: the unsaved graph is kept.
  viewer_.on_device_failure = [this] {
    const std::string kept = write_recovery_copy(model_);
    if (!kept.empty()) std::fprintf(stderr, "edit: the unsaved graph is kept in %s\n", kept.c_str());
  };
  status_ = "editing " + model_.path();
  refresh();
  if (const std::string offer = recovery_offer(model_.path()); !offer.empty()) {
    std::fprintf(stderr, "edit: %s\n", offer.c_str());
    status_ = offer;
    status_is_error_ = true;
  }
}

template <class Edit>
bool GraphEditor::act(const std::string& label, Edit&& edit) {
  try {
    edit();
  } catch (const InputError& e) {
    const std::string where = pass_named_in(e.what(), model_.json());
    if (!where.empty()) node_errors_[where] = e.what();
    status_ = label + " refused: " + e.what();
    status_is_error_ = true;
    std::fprintf(stderr, "edit: %s refused: %s\n", label.c_str(), e.what());
    viewer_.request_redraw();
    return false;
  }
  node_errors_.clear();
  status_ = label + (model_.modified() ? " (unsaved)" : "");
  status_is_error_ = false;
  refresh();  // a graph still refused, or one this device cannot run, says so instead
  std::fprintf(stderr, "edit: %s%s\n", label.c_str(), model_.refusal().empty() ? "" : " (the graph is still refused)");
  return true;
}

void GraphEditor::refresh() {
  const graph::GraphDesc desc = model_.desc();
  parameters_ = desc.parameters;
  if (!model_.refusal().empty()) {
    // A graph that does not compile does not run: the window keeps the last good frame (the
    // stand-in, black, when the graph was refused from the start).
    status_ = "refused (the picture is the last good graph's): " + model_.refusal();
    status_is_error_ = true;
    const std::string where = pass_named_in(model_.refusal(), model_.json());
    if (!where.empty()) node_errors_[where] = model_.refusal();
  } else {
    // The running frame follows every accepted edit; a graph that compiles but does not set up on
    // this device (a shader, a device limit) keeps the last good frame on screen.
    try {
      if (const std::string error = viewer_.use_graph(desc); !error.empty()) {
        status_ = error;
        status_is_error_ = true;
        const std::string where = pass_named_in(error, model_.json());
        if (!where.empty()) node_errors_[where] = error;
      }
    } catch (const InputError& e) {
      status_ = e.what();
      status_is_error_ = true;
    }
  }
  bindings_.clear();
  for (const auto& pass : model_.json()["passes"]) {
    for (const char* section : {"inputs", "outputs"}) {
      if (!pass.contains(section)) continue;
      for (const auto& [port, resource] : pass[section].items()) bindings_[pass["name"].get<std::string>() + "." + port] = resource;
    }
  }
  nodes_ = layout_nodes(model_.json(), model_.registry(), text_);
  for (auto it = selected_.begin(); it != selected_.end();) it = node(*it) ? std::next(it) : selected_.erase(it);
  viewer_.request_redraw();
}

const CanvasNode* GraphEditor::node(const std::string& name) const {
  for (const auto& n : nodes_) {
    if (n.name == name) return &n;
  }
  return nullptr;
}

std::string GraphEditor::resource_of(const std::string& pass, const std::string& port) const {
  const auto found = bindings_.find(pass + "." + port);
  return found == bindings_.end() ? "" : found->second;
}

bool GraphEditor::add_pass(const std::string& type, float x, float y, const std::string& shader) {
  std::string name;
  const bool user = !shader.empty();
  if (!act("add " + type, [&] { name = user ? model_.add_user_pass(type, shader) : model_.add_pass(type); })) return false;
  // The position is part of the same gesture, but its own step in the history.
  return act("place " + name, [&] { model_.set_position(name, x, y); });
}

bool GraphEditor::remove_selected() {
  bool all = true;
  for (const auto& name : std::vector<std::string>(selected_.begin(), selected_.end())) {
    all = act("remove " + name, [&] { model_.remove_pass(name); }) && all;
  }
  return all;
}

bool GraphEditor::connect(const std::string& pass, const std::string& port, const std::string& resource) {
  return act("connect " + pass + "." + port + " to " + resource, [&] { model_.connect(pass, port, resource); });
}

bool GraphEditor::disconnect(const std::string& pass, const std::string& port) {
  return act("disconnect " + pass + "." + port, [&] { model_.disconnect(pass, port); });
}

bool GraphEditor::set_for_each(const std::string& pass, const std::string& kind) {
  return act(kind.empty() ? "make " + pass + " once" : "make " + pass + " once per " + kind, [&] { model_.set_for_each(pass, kind); });
}

bool GraphEditor::set_param(const std::string& pass, const std::string& param, const nlohmann::json& value) {
  return act("set " + pass + "." + param, [&] { model_.set_param(pass, param, value); });
}

bool GraphEditor::set_graph_parameter(const std::string& parameter, const nlohmann::json& value) {
  return act("set parameter " + parameter, [&] { model_.set_parameter_field(parameter, "default", value); });
}

bool GraphEditor::rename(const std::string& pass, const std::string& new_name) {
  if (!act("rename " + pass, [&] { model_.rename_pass(pass, new_name); })) return false;
  if (selected_.erase(pass)) selected_.insert(new_name);
  return true;
}

bool GraphEditor::move(const std::string& pass, float x, float y) {
  return act("move " + pass, [&] { model_.set_position(pass, x, y); });
}

bool GraphEditor::undo() {
  const std::string label = model_.undo_label();
  return act("undo " + label, [&] {
    if (!model_.undo()) throw InputError("nothing to undo");
  });
}

bool GraphEditor::redo() {
  const std::string label = model_.redo_label();
  return act("redo " + label, [&] {
    if (!model_.redo()) throw InputError("nothing to redo");
  });
}

bool GraphEditor::save(bool overwrite) {
  if (!overwrite && model_.changed_on_disk()) {
    confirm_overwrite_ = true;  // the side panel asks
    status_ = model_.path() + " changed on disk since it was opened: overwrite it?";
    status_is_error_ = true;
    std::fprintf(stderr, "edit: %s\n", status_.c_str());
    viewer_.request_redraw();
    return false;
  }
  confirm_overwrite_ = false;
  if (!act("save", [&] { model_.save(overwrite); })) return false;
  status_ = "saved " + model_.path();
  std::fprintf(stderr, "edit: saved %s\n", model_.path().c_str());
  return true;
}

bool GraphEditor::on_key(const WindowEvents::Key& key) {
  const bool ctrl = (key.mods & GLFW_MOD_CONTROL) != 0, shift = (key.mods & GLFW_MOD_SHIFT) != 0;
  if (ctrl && key.key == GLFW_KEY_S) return save(), true;
  if (ctrl && (key.key == GLFW_KEY_Y || (key.key == GLFW_KEY_Z && shift))) return redo(), true;
  if (ctrl && key.key == GLFW_KEY_Z) return undo(), true;
  if ((key.key == GLFW_KEY_DELETE || key.key == GLFW_KEY_BACKSPACE) && canvas_hovered_ && !ImGui::GetIO().WantTextInput) {
    remove_selected();
    return true;
  }
  return false;
}

void GraphEditor::step_script() {
  if (script_line_ >= script_.size()) return;
  const std::string line = script_[script_line_++];
  std::istringstream in(line);
  std::string verb;
  in >> verb;
  std::vector<std::string> args;
  for (std::string a; in >> a;) args.push_back(a);
  bool ok = false;
  auto need = [&](size_t n) {
    if (args.size() < n) throw UsageError("edit script line " + std::to_string(script_line_) + " '" + line + "': too few arguments");
  };
  if (verb == "add") {
    need(1);
    ok = add_pass(args[0], args.size() > 2 ? std::stof(args[1]) : 40.0f, args.size() > 2 ? std::stof(args[2]) : 40.0f);
  } else if (verb == "add-shader") {  // add-shader compute|fullscreen FILE [X Y]
    need(2);
    ok = add_pass(args[0], args.size() > 3 ? std::stof(args[2]) : 40.0f, args.size() > 3 ? std::stof(args[3]) : 40.0f, args[1]);
  } else if (verb == "connect") {
    need(3);
    ok = connect(args[0], args[1], args[2]);
  } else if (verb == "disconnect") {
    need(2);
    ok = disconnect(args[0], args[1]);
  } else if (verb == "set") {
    need(3);
    const auto value = nlohmann::json::parse(args[2], nullptr, false);
    ok = set_param(args[0], args[1], value.is_discarded() ? nlohmann::json(args[2]) : value);
  } else if (verb == "for-each") {  // for-each PASS light|caustic_view|once
    need(2);
    ok = set_for_each(args[0], args[1] == "once" ? "" : args[1]);
  } else if (verb == "param") {
    need(2);
    const auto value = nlohmann::json::parse(args[1], nullptr, false);
    ok = set_graph_parameter(args[0], value.is_discarded() ? nlohmann::json(args[1]) : value);
  } else if (verb == "select") {
    selected_ = std::set<std::string>(args.begin(), args.end());
    ok = true;
  } else if (verb == "remove") {
    ok = remove_selected();
  } else if (verb == "rename") {
    need(2);
    ok = rename(args[0], args[1]);
  } else if (verb == "undo") {
    ok = undo();
  } else if (verb == "redo") {
    ok = redo();
  } else if (verb == "save" || verb == "save!") {
    ok = save(verb == "save!");
  } else if (verb == "screenshot") {
    need(1);
    viewer_.screenshot_next(args[0]);
    ok = true;
  } else if (verb == "where") {
    // Where a port was drawn, in window pixels: scripts drive the mouse with it (edit_test).
    need(1);
    const auto found = port_positions_.find(args[0]);
    ok = found != port_positions_.end();
    if (ok) std::fprintf(stderr, "edit: port %s at %.0f,%.0f\n", args[0].c_str(), double(found->second[0]), double(found->second[1]));
  } else if (verb == "layout") {
    log_layout();
    ok = true;
  } else if (verb == "quit") {
    viewer_.close();
    ok = true;
  } else {
    throw UsageError("edit script line " + std::to_string(script_line_) + ": unknown action '" + verb + "'");
  }
  std::fprintf(stderr, "edit: %s: %s\n", line.c_str(), ok ? "ok" : ("refused: " + status_).c_str());
  viewer_.request_redraw();
}

void GraphEditor::log_layout() const {
  auto log = [](const char* what, const std::string& name, const Box& b) {
    std::fprintf(stderr, "edit: %s %s at %.0f,%.0f size %.0fx%.0f\n", what, name.c_str(), double(b.x), double(b.y), double(b.w),
                 double(b.h));
  };
  const ImVec2 display = ImGui::GetIO().DisplaySize;
  log("dock", "window", Box{0, display.y - dock_height_, display.x, dock_height_});
  log("canvas", "view", canvas_rect_);
  std::fprintf(stderr, "edit: canvas text %.0f px, panel text %.0f px\n", double(text_.line_height * view_.zoom),
               double(ImGui::GetFontSize()));
  for (const auto& n : nodes_) {
    const Point top = view_.to_screen({canvas_rect_.x, canvas_rect_.y}, {n.box.x, n.box.y});
    log("node", n.name, Box{top.x, top.y, n.box.w * view_.zoom, n.box.h * view_.zoom});
  }
  for (const auto& [label, box] : drawn_labels_) log("label", label, box);
}

}  // namespace caustica::editor
