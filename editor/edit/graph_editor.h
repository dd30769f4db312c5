#pragma once
// caustica edit: the viewer with a node canvas over the graph, docked below the picture. Passes are
// boxes with their ports and last GPU time (counters on hover), resources are wires labelled with
// name, format and extent, culled passes are grey. Every edit goes through the graph model
// (editor/model), is compiled, and swaps the running frame; a refused edit keeps the last good frame
// and shows the message on the node it concerns. The canvas's geometry is model/canvas_layout.h.
#include <imgui.h>

#include <array>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "model/canvas_layout.h"
#include "model/graph_model.h"
#include "viewer/viewer.h"

namespace caustica::editor {

class GraphEditor {
 public:
  // `script`: a file of editor actions, one per frame (for tests; see kEditScriptHelp).
  GraphEditor(Viewer& viewer, GraphModel& model, std::string script = "");

  // The actions the canvas, the side panel, the keys and the script share. Each returns whether
  // it was applied; a refusal is shown on its node (or the status line) and changes nothing.
  // A user pass kind ("compute", "fullscreen") takes its shader file, which declares its ports.
  bool add_pass(const std::string& type, float x, float y, const std::string& shader = "");
  bool remove_selected();
  bool connect(const std::string& pass, const std::string& port, const std::string& resource);
  bool disconnect(const std::string& pass, const std::string& port);
  bool set_for_each(const std::string& pass, const std::string& kind);
  bool set_param(const std::string& pass, const std::string& param, const nlohmann::json& value);
  bool rename(const std::string& pass, const std::string& new_name);
  // A graph parameter's value, as the file's default.
  bool set_graph_parameter(const std::string& parameter, const nlohmann::json& value);
  bool move(const std::string& pass, float x, float y);
  bool undo();
  bool redo();
  // Ctrl+S: a file changed on disk meanwhile asks first (confirm_overwrite_).
  bool save(bool overwrite = false);

 private:
  struct PortHit {
    std::string pass, port;
    bool output = false;
  };

  template <class Edit>
  bool act(const std::string& label, Edit&& edit);
  void refresh();  // after any change of the model: nodes, layout, the running graph
  // edit/canvas.cpp: the editor's window, its canvas and side panel.
  void draw(const graph::FrameResult& frame);
  void draw_canvas(const graph::FrameResult& frame);
  // The canvas's parts (edit/canvas.cpp): its view, wires, nodes and the mouse's gestures.
  struct ScreenView;
  struct Hovered {
    std::optional<PortHit> port;
    std::string node;
  };
  void pan_and_zoom(ImVec2 origin);
  void draw_wires(const ScreenView& view);
  Hovered draw_nodes(const ScreenView& view, const graph::FrameResult& frame);
  void canvas_gestures(const ScreenView& view, const Hovered& hovered);
  // The viewer's panel folded above the dock, once: the nodes show the pass times, and the picture stays in view.
  void arrange_viewer_panel(ImVec2 display) const;
  void draw_side_panel();
  void draw_pass_panel();
  void draw_graph_parameters();
  void draw_add_menu();
  bool on_key(const WindowEvents::Key& key);
  void step_script();
  const CanvasNode* node(const std::string& name) const;
  // The canvas's geometry as last drawn, in window pixels, for scripts (the "layout" action).
  void log_layout() const;
  std::string resource_of(const std::string& pass, const std::string& port) const;

  Viewer& viewer_;
  GraphModel& model_;
  TextMeasure text_;  // the panels' font, at the canvas's zoom 1
  std::vector<CanvasNode> nodes_;
  std::vector<graph::GraphParameter> parameters_;  // the graph's, as of the last refresh
  std::map<std::string, std::string> bindings_;    // "pass.port" -> resource, as of the last refresh
  std::set<std::string> selected_;
  std::map<std::string, std::string> node_errors_;  // pass -> the message of the edit it refused
  std::string status_;
  bool status_is_error_ = false;
  CanvasView view_;
  bool fitted_ = false;    // the view was fitted to the graph once
  float dock_height_ = 0;  // the editor's window at the bottom; its top edge is the splitter
  bool viewer_panel_arranged_ = false;
  // Where the canvas and its wire labels were drawn last, in window pixels.
  Box canvas_rect_;
  std::vector<std::pair<std::string, Box>> drawn_labels_;
  // Interaction in progress.
  std::string dragging_node_;
  float drag_dx_ = 0, drag_dy_ = 0;
  std::optional<PortHit> wire_from_;
  bool box_selecting_ = false;
  float box_x0_ = 0, box_y0_ = 0;
  float menu_x_ = 0, menu_y_ = 0;  // where an added pass goes, canvas units
  char filter_[64] = {};
  std::string shader_kind_;  // a user pass kind chosen in the menu, waiting for its shader file
  char shader_file_[256] = {};
  bool menu_has_keyboard_ = false;
  char rename_[128] = {};
  bool confirm_overwrite_ = false;
  bool canvas_hovered_ = false;
  std::map<std::string, std::array<float, 2>> port_positions_;  // "pass.port" -> where it was drawn last
  std::vector<std::string> script_;
  size_t script_line_ = 0;
};

extern const char* const kEditScriptHelp;

}  // namespace caustica::editor
