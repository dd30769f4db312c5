// The editor's window: the canvas of the graph (ImGui draw lists: nodes, ports, wires, gestures)
// and the side panel of the selected pass. Every change goes through GraphEditor's actions.
#include <imgui.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <vector>

#include <imgui_internal.h>

#include "edit/graph_editor.h"
#include "graph/per_light.h"
#include "viewer/parameter_panel.h"

namespace caustica::editor {
namespace {

using nlohmann::ordered_json;

ImVec2 operator+(ImVec2 a, ImVec2 b) {
  return {a.x + b.x, a.y + b.y};
}

constexpr float kMinDockHeight = 120.0f;  // the status line and a few rows of canvas
constexpr float kSidePanelEms = 22.0f;    // the side panel's width in the panels' text size
constexpr float kMaxZoom = 3.0f;
constexpr float kWireHoverPixels = 6.0f;

}  // namespace

void GraphEditor::draw(const graph::FrameResult& frame) {
  const ImVec2 display = ImGui::GetIO().DisplaySize;
  if (dock_height_ <= 0.0f) dock_height_ = std::round(display.y * kDockFraction);
  dock_height_ = std::clamp(dock_height_, std::min(kMinDockHeight, display.y), display.y);
  if (!viewer_panel_arranged_) {
    arrange_viewer_panel(display);
    viewer_panel_arranged_ = true;
  }
  // Docked at the bottom, the window's full width; its top edge, dragged, is the splitter between
  // the picture and the canvas (ImGui resizes the window, the next frame keeps it at the bottom).
  ImGui::SetNextWindowPos(ImVec2(0, display.y - dock_height_), ImGuiCond_Always);
  ImGui::SetNextWindowSize(ImVec2(display.x, dock_height_), ImGuiCond_Always);
  ImGui::Begin("graph editor", nullptr,
               ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoScrollWithMouse | ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoMove);
  dock_height_ = ImGui::GetWindowHeight();
  ImGui::TextDisabled("(?)");
  if (ImGui::IsItemHovered()) {
    ImGui::SetTooltip(
        "right click: add a pass   drag port to port: connect   Del: remove   middle drag: pan   wheel: zoom in\n"
        "hover a node for its counters, a wire for its resource   drag this window's top edge: more picture or more canvas");
  }
  ImGui::SameLine();
  ImGui::PushTextWrapPos(0.0f);
  ImGui::TextColored(status_is_error_ ? ImVec4(1, 0.4f, 0.3f, 1) : ImVec4(0.6f, 0.9f, 0.6f, 1), "%s", status_.c_str());
  ImGui::PopTextWrapPos();
  // A small window keeps most of its width for the canvas.
  const float side = std::min(ImGui::GetFontSize() * kSidePanelEms, ImGui::GetContentRegionAvail().x * 0.4f);
  ImGui::BeginChild("canvas", ImVec2(ImGui::GetContentRegionAvail().x - side, 0), true,
                    ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoScrollWithMouse);
  draw_canvas(frame);
  ImGui::EndChild();
  ImGui::SameLine();
  ImGui::BeginChild("side panel", ImVec2(0, 0), true);
  draw_side_panel();
  ImGui::EndChild();
  ImGui::End();
}

// The viewer draws its panel (id "###caustica", viewer.cpp) before the editor each frame. Folded,
// it leaves the picture in view (the nodes show the pass times); unfolded, it ends above the dock.
void GraphEditor::arrange_viewer_panel(ImVec2 display) const {
  const ImGuiWindow* panel = ImGui::FindWindowByName("###caustica");
  if (!panel) return;
  ImGui::SetWindowSize("###caustica", ImVec2(panel->SizeFull.x, std::max(kMinDockHeight, display.y - dock_height_ - 20.0f)),
                       ImGuiCond_Always);
  ImGui::SetWindowCollapsed("###caustica", true, ImGuiCond_Always);
}

// Where the canvas lies on screen this frame, and drawing in canvas units (model/canvas_layout.h).
// Text scales with the canvas, never below the panels' size (kReadableZoom).
struct GraphEditor::ScreenView {
  ImDrawList* draw;
  ImVec2 origin;
  CanvasView view;
  const TextMeasure& text;

  float font_size() const { return text.line_height * view.zoom; }
  ImVec2 to_screen(Point p) const {
    const Point s = view.to_screen({origin.x, origin.y}, p);
    return {s.x, s.y};
  }
  ImVec2 to_screen(float x, float y) const { return to_screen(Point{x, y}); }
  Point to_canvas(ImVec2 p) const { return view.to_canvas({origin.x, origin.y}, {p.x, p.y}); }
  void text_at(ImVec2 p, ImU32 colour, const std::string& t) const { draw->AddText(ImGui::GetFont(), font_size(), p, colour, t.c_str()); }
  ImVec2 port_pos(const CanvasNode& n, const std::string& port, bool output) const {
    return to_screen(port_position(n, port, output, text));
  }
};

void GraphEditor::draw_canvas(const graph::FrameResult& frame) {
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  const ImVec2 size = ImGui::GetContentRegionAvail();
  if (size.x < 1.0f || size.y < 1.0f) return;  // a window too small for any canvas
  ImGui::InvisibleButton("canvas", size,
                         ImGuiButtonFlags_MouseButtonLeft | ImGuiButtonFlags_MouseButtonMiddle | ImGuiButtonFlags_MouseButtonRight);
  canvas_hovered_ = ImGui::IsItemHovered();
  canvas_rect_ = {origin.x, origin.y, size.x, size.y};
  pan_and_zoom(origin);
  if (!fitted_ && !nodes_.empty() && size.x > 1 && size.y > 1) {
    view_ = fit_view(nodes_, size.x, size.y);
    fitted_ = true;
  }
  const ScreenView view{ImGui::GetWindowDrawList(), origin, view_, text_};
  view.draw->PushClipRect(origin, origin + size, true);
  port_positions_.clear();
  draw_wires(view);
  const Hovered hovered = draw_nodes(view, frame);
  canvas_gestures(view, hovered);
  view.draw->PopClipRect();
  if (canvas_hovered_ && ImGui::IsMouseClicked(ImGuiMouseButton_Right)) {
    const Point m = view.to_canvas(ImGui::GetIO().MousePos);
    menu_x_ = m.x;
    menu_y_ = m.y;
    filter_[0] = '\0';
    menu_has_keyboard_ = false;
    ImGui::OpenPopup("add pass");
  }
  draw_add_menu();
}

// Middle drag pans, the wheel zooms about the mouse: in from the readable size, not below it.
void GraphEditor::pan_and_zoom(ImVec2 origin) {
  ImGuiIO& io = ImGui::GetIO();
  if (canvas_hovered_ && ImGui::IsMouseDragging(ImGuiMouseButton_Middle)) {
    view_.pan_x += io.MouseDelta.x / view_.zoom;
    view_.pan_y += io.MouseDelta.y / view_.zoom;
  }
  if (canvas_hovered_ && io.MouseWheel != 0.0f) {
    const Point o{origin.x, origin.y}, mouse{io.MousePos.x, io.MousePos.y};
    const Point before = view_.to_canvas(o, mouse);
    view_.zoom = std::clamp(view_.zoom * std::pow(1.1f, io.MouseWheel), kReadableZoom, kMaxZoom);
    const Point after = view_.to_canvas(o, mouse);
    view_.pan_x += after.x - before.x;
    view_.pan_y += after.y - before.y;
  }
}

// Wires: from the writer's output port to each reader's input port, a history input's wire (the
// last frame's resource) in blue, looping below the node when a pass reads its own last result.
// Each is labelled with its resource where the label lies over no node and no other label; the
// hovered wire shows its resource's format and extent as compiled.
void GraphEditor::draw_wires(const ScreenView& view) {
  const graph::Plan& plan = viewer_.plan();
  const ImVec2 mouse = ImGui::GetIO().MousePos;
  const Point m = view.to_canvas(mouse);
  const bool over_node = std::any_of(nodes_.begin(), nodes_.end(), [&](const CanvasNode& n) { return n.box.contains(m); });
  const std::vector<Wire> all = wires(model_.json());
  std::vector<std::string> names;
  for (const Wire& wire : all) names.push_back(wire.history ? "last frame's " + wire.resource : wire.resource);
  const std::vector<std::optional<Box>> labels = place_wire_labels(nodes_, all, names, text_);
  std::optional<size_t> hovered;
  float nearest = kWireHoverPixels / view.view.zoom;
  std::vector<std::array<Point, 4>> curves(all.size());
  for (size_t i = 0; i < all.size(); ++i) {
    const CanvasNode* writer = node(all[i].writer);
    const CanvasNode* reader = node(all[i].reader);
    if (!writer || !reader) continue;
    curves[i] = wire_curve(port_position(*writer, all[i].output, true, text_), port_position(*reader, all[i].input, false, text_),
                           writer == reader);
    if (canvas_hovered_ && !over_node) {
      if (const float d = distance_to_curve(curves[i], m); d < nearest) {
        nearest = d;
        hovered = i;
      }
    }
  }
  for (size_t i = 0; i < all.size(); ++i) {
    if (!node(all[i].writer) || !node(all[i].reader)) continue;
    const auto& c = curves[i];
    const ImU32 colour = hovered == i     ? IM_COL32(255, 255, 190, 255)
                         : all[i].history ? IM_COL32(140, 170, 255, 220)
                                          : IM_COL32(200, 200, 120, 200);
    view.draw->AddBezierCubic(view.to_screen(c[0]), view.to_screen(c[1]), view.to_screen(c[2]), view.to_screen(c[3]), colour,
                              hovered == i ? 3.0f : 2.0f);
  }
  drawn_labels_.clear();
  for (size_t i = 0; i < all.size(); ++i) {
    if (!labels[i]) continue;
    const ImVec2 top = view.to_screen(labels[i]->x, labels[i]->y), bottom = view.to_screen(labels[i]->right(), labels[i]->bottom());
    view.draw->AddRectFilled(top, bottom, IM_COL32(20, 20, 20, 200), 3.0f);
    view.text_at(ImVec2(top.x + 3.0f * view.view.zoom, top.y + view.view.zoom), IM_COL32(220, 220, 170, 255), names[i]);
    drawn_labels_.emplace_back(names[i], Box{top.x, top.y, bottom.x - top.x, bottom.y - top.y});
  }
  if (hovered) {
    const Wire& wire = all[*hovered];
    std::string label = names[*hovered];
    if (const int r = plan.find_resource(wire.resource); r >= 0) {
      const auto& pr = plan.resources[static_cast<size_t>(r)];
      label += ": " + std::string(graph::format_info(pr.format).name) + " " + std::to_string(pr.width) + "x" + std::to_string(pr.height);
    }
    ImGui::SetTooltip("%s\n%s.%s -> %s.%s", label.c_str(), wire.writer.c_str(), wire.output.c_str(), wire.reader.c_str(),
                      wire.input.c_str());
  }
}

// Each node: its box (grey when culled, outlined when selected or refused), its ports, its last
// GPU time; hovered, its counters and its error. Returns what the mouse is over.
GraphEditor::Hovered GraphEditor::draw_nodes(const ScreenView& view, const graph::FrameResult& frame) {
  const graph::Plan& plan = viewer_.plan();
  const ImGuiIO& io = ImGui::GetIO();
  const NodeMetrics metrics(text_);
  const float zoom = view.view.zoom;
  Hovered hovered;
  for (const auto& n : nodes_) {
    // A per-light pass is its instances (graph/per_light.h): shown with their time together.
    const auto is_node = [&](const std::string& pass) { return pass == n.name || graph::instance_of(pass) == n.name; };
    const bool culled = std::find(plan.culled.begin(), plan.culled.end(), n.name) != plan.culled.end() ||
                        std::none_of(plan.passes.begin(), plan.passes.end(), [&](const auto& p) { return is_node(p.name); });
    double gpu_ms = 0;
    bool timed = false, ran = false;
    for (const auto& p : frame.passes) {
      if (!is_node(p.name)) continue;
      timed = true;
      ran = ran || p.ran();
      gpu_ms += p.gpu_ms;
    }
    std::string stats;
    if (timed && !ran) {
      stats = "reused (unchanged)";
    } else if (timed) {
      char text[64];
      std::snprintf(text, sizeof text, "GPU %.2f ms", gpu_ms);
      stats = text;
    }
    const auto error = node_errors_.find(n.name);
    const ImVec2 top = view.to_screen(n.box.x, n.box.y), bottom = view.to_screen(n.box.right(), n.box.bottom());
    const bool selected = selected_.count(n.name) > 0;
    view.draw->AddRectFilled(top, bottom, culled ? IM_COL32(45, 45, 45, 235) : IM_COL32(35, 45, 70, 240), 4.0f);
    view.draw->AddRectFilled(top, ImVec2(bottom.x, top.y + metrics.header * zoom),
                             culled ? IM_COL32(70, 70, 70, 255) : IM_COL32(60, 90, 150, 255), 4.0f);
    view.draw->AddRect(top, bottom,
                       selected                      ? IM_COL32(255, 220, 90, 255)
                       : error != node_errors_.end() ? IM_COL32(240, 80, 60, 255)
                                                     : IM_COL32(90, 90, 90, 255),
                       4.0f, 0, selected || error != node_errors_.end() ? 2.5f : 1.0f);
    const ImU32 text = culled ? IM_COL32(150, 150, 150, 255) : IM_COL32(235, 235, 235, 255);
    view.text_at(ImVec2(top.x + metrics.padding * zoom, top.y + (metrics.header - text_.line_height) * 0.5f * zoom), text, n.title);
    for (int side = 0; side < 2; ++side) {
      const auto& ports = side ? n.outputs : n.inputs;
      for (const auto& port : ports) {
        const ImVec2 p = view.port_pos(n, port, side == 1);
        const bool bound = !resource_of(n.name, port).empty();
        view.draw->AddCircleFilled(p, metrics.port_radius * zoom, bound ? IM_COL32(200, 200, 120, 255) : IM_COL32(110, 110, 110, 255));
        const float label_width = text_.width(port) * zoom;
        const float inset = metrics.port_inset * zoom;
        view.text_at(ImVec2(side ? p.x - label_width - inset : p.x + inset, p.y - view.font_size() * 0.5f), text, port);
        const float dx = io.MousePos.x - p.x, dy = io.MousePos.y - p.y;
        const float reach = std::max(8.0f, metrics.port_radius * zoom * 1.6f);
        if (dx * dx + dy * dy < reach * reach) hovered.port = PortHit{n.name, port, side == 1};
        port_positions_[n.name + "." + port] = {p.x, p.y};
      }
    }
    const Box line = stats_line(n, text_);
    view.text_at(view.to_screen(line.x, line.y + 2.0f), IM_COL32(150, 200, 255, 255), stats);
    if (io.MousePos.x >= top.x && io.MousePos.x <= bottom.x && io.MousePos.y >= top.y && io.MousePos.y <= bottom.y) hovered.node = n.name;
    if (hovered.node == n.name && !hovered.port && canvas_hovered_) {
      ImGui::BeginTooltip();
      ImGui::PushTextWrapPos(ImGui::GetFontSize() * 45.0f);
      ImGui::TextUnformatted((n.title + (culled ? " (culled)" : "")).c_str());
      for (const auto& [counter, value] : frame.counters) {
        const auto owner = frame.counter_passes.find(counter);
        if (owner != frame.counter_passes.end() && owner->second == n.name) ImGui::Text("%s %.6g", counter.c_str(), value);
      }
      if (error != node_errors_.end()) ImGui::TextColored(ImVec4(1, 0.45f, 0.35f, 1), "%s", error->second.c_str());
      ImGui::PopTextWrapPos();
      ImGui::EndTooltip();
    }
  }
  return hovered;
}

// Gestures: drag port to port connects, drag a node moves it, drag the background box-selects.
void GraphEditor::canvas_gestures(const ScreenView& view, const Hovered& hovered) {
  const ImGuiIO& io = ImGui::GetIO();
  if (canvas_hovered_ && ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
    if (hovered.port) {
      wire_from_ = hovered.port;
    } else if (!hovered.node.empty()) {
      if (!io.KeyShift && !selected_.count(hovered.node)) selected_.clear();
      selected_.insert(hovered.node);
      if (const CanvasNode* n = node(hovered.node)) {
        dragging_node_ = hovered.node;
        const Point m = view.to_canvas(io.MousePos);
        drag_dx_ = m.x - n->box.x;
        drag_dy_ = m.y - n->box.y;
      }
    } else {
      box_selecting_ = true;
      const Point m = view.to_canvas(io.MousePos);
      box_x0_ = m.x;
      box_y0_ = m.y;
    }
  }
  if (!dragging_node_.empty()) {
    const Point m = view.to_canvas(io.MousePos);
    for (auto& n : nodes_) {
      if (n.name == dragging_node_) {
        n.box.x = m.x - drag_dx_;
        n.box.y = m.y - drag_dy_;
      }
    }
    if (ImGui::IsMouseReleased(ImGuiMouseButton_Left)) {
      const std::string name = std::move(dragging_node_);
      dragging_node_.clear();
      if (const CanvasNode* n = node(name)) {
        const float x = n->box.x, y = n->box.y;
        move(name, x, y);
      }
    }
  }
  if (wire_from_) {
    const CanvasNode* from = node(wire_from_->pass);
    if (from)
      view.draw->AddLine(view.port_pos(*from, wire_from_->port, wire_from_->output), io.MousePos, IM_COL32(255, 255, 160, 255), 2.0f);
    if (ImGui::IsMouseReleased(ImGuiMouseButton_Left)) {
      const PortHit a = *wire_from_;
      wire_from_.reset();
      if (hovered.port && hovered.port->output != a.output) {
        const PortHit& out = a.output ? a : *hovered.port;
        const PortHit& in = a.output ? *hovered.port : a;
        const std::string resource = resource_of(out.pass, out.port);
        if (resource.empty()) {
          status_ = "output " + out.pass + "." + out.port + " is not bound to a resource";
          status_is_error_ = true;
        } else {
          connect(in.pass, in.port, resource);
        }
      }
    }
  }
  if (box_selecting_) {
    const Point m = view.to_canvas(io.MousePos);
    view.draw->AddRect(view.to_screen(box_x0_, box_y0_), io.MousePos, IM_COL32(255, 220, 90, 200));
    if (ImGui::IsMouseReleased(ImGuiMouseButton_Left)) {
      box_selecting_ = false;
      if (!io.KeyShift) selected_.clear();
      const Box area{std::min(box_x0_, m.x), std::min(box_y0_, m.y), std::abs(m.x - box_x0_), std::abs(m.y - box_y0_)};
      for (const auto& n : nodes_) {
        if (n.box.overlaps(area)) selected_.insert(n.name);
      }
    }
  }
}

void GraphEditor::draw_add_menu() {
  if (!ImGui::BeginPopup("add pass")) return;
  if (ImGui::IsWindowAppearing()) {
    ImGui::SetKeyboardFocusHere();
    shader_kind_.clear();
  }
  const bool enter = ImGui::InputTextWithHint("##filter", "search pass types (Enter: the first)", filter_, sizeof filter_,
                                              ImGuiInputTextFlags_EnterReturnsTrue);
  if (ImGui::IsItemActive() && !menu_has_keyboard_) {
    menu_has_keyboard_ = true;  // said once per opening, for scripts that type into it
    std::fprintf(stderr, "edit: the pass-type menu has the keyboard\n");
  }
  // Types whose name matches first, then those whose description does.
  std::vector<const graph::PassTypeDecl*> matches;
  for (int by_description = 0; by_description < 2; ++by_description) {
    for (const auto& [type, decl] : model_.registry().types()) {
      const bool name = type.find(filter_) != std::string::npos;
      if (by_description ? !name && decl.description.find(filter_) != std::string::npos : name) matches.push_back(&decl);
    }
  }
  std::string chosen = enter && !matches.empty() ? matches.front()->type : "";
  for (const auto* decl : matches) {
    const bool user = decl->user_kind != graph::UserShaderKind::none;
    const std::string label =
        user ? decl->type + (decl->user_kind == graph::UserShaderKind::compute ? ": compute shader..." : ": full-screen shader...")
             : decl->type;
    if (ImGui::Selectable(label.c_str(), false, user ? ImGuiSelectableFlags_DontClosePopups : 0)) chosen = decl->type;
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", decl->description.c_str());
  }
  const graph::PassTypeDecl* chosen_decl = chosen.empty() ? nullptr : model_.registry().find(chosen);
  bool focus_shader = false;
  if (chosen_decl && chosen_decl->user_kind != graph::UserShaderKind::none) {
    shader_kind_ = chosen;  // its shader file first: the shader declares its ports
    chosen.clear();
    focus_shader = true;
  }
  if (!shader_kind_.empty()) {
    ImGui::Separator();
    if (focus_shader) ImGui::SetKeyboardFocusHere(1);
    ImGui::TextUnformatted((shader_kind_ + " pass: its shader file, beside the graph (Enter adds it)").c_str());
    if (ImGui::InputTextWithHint("##shader", shader_kind_ == "compute" ? "my_pass.comp" : "my_pass.frag", shader_file_, sizeof shader_file_,
                                 ImGuiInputTextFlags_EnterReturnsTrue) &&
        shader_file_[0]) {
      if (add_pass(shader_kind_, menu_x_, menu_y_, shader_file_)) {
        shader_kind_.clear();
        shader_file_[0] = 0;
        ImGui::CloseCurrentPopup();
      }
    }
  }
  if (!chosen.empty()) {
    add_pass(chosen, menu_x_, menu_y_);
    ImGui::CloseCurrentPopup();
  }
  ImGui::EndPopup();
}

void GraphEditor::draw_side_panel() {
  if (confirm_overwrite_) {
    ImGui::TextColored(ImVec4(1, 0.6f, 0.3f, 1), "The file changed on disk.");
    if (ImGui::Button("overwrite it")) save(true);
    ImGui::SameLine();
    if (ImGui::Button("cancel")) confirm_overwrite_ = false;
    ImGui::Separator();
  }
  if (ImGui::Button("undo")) undo();
  ImGui::SameLine();
  if (ImGui::Button("redo")) redo();
  ImGui::SameLine();
  if (ImGui::Button(model_.modified() ? "save *" : "save")) save();
  ImGui::SameLine();
  if (ImGui::Button("fit")) fitted_ = false;
  if (!ImGui::BeginTabBar("side")) return;
  if (ImGui::BeginTabItem("pass")) {
    draw_pass_panel();
    ImGui::EndTabItem();
  }
  if (ImGui::BeginTabItem("graph parameters")) {
    draw_graph_parameters();
    ImGui::EndTabItem();
  }
  ImGui::EndTabBar();
}

// The selected pass: its name, its parameters (each name whole, on its own line) and its ports.
void GraphEditor::draw_pass_panel() {
  if (selected_.size() != 1) {
    ImGui::TextDisabled(selected_.empty() ? "select a pass to edit it" : "%zu passes selected (Del removes them)", selected_.size());
    return;
  }
  const std::string name = *selected_.begin();
  ordered_json pass;
  for (const auto& p : model_.json()["passes"]) {
    if (p["name"] == name) pass = p;
  }
  if (!model_.registry().find(pass.value("type", ""))) return;
  const graph::PassTypeDecl type = model_.pass_type(pass);
  const graph::PassTypeDecl* decl = &type;
  ImGui::TextWrapped("%s (%s)", name.c_str(), decl->type.c_str());
  ImGui::InputTextWithHint("##rename", "new name", rename_, sizeof rename_);
  ImGui::SameLine();
  if (ImGui::Button("rename") && rename_[0]) rename(name, rename_);
  if (ImGui::Button("remove pass")) remove_selected();
  // Once, once per light, or once per caustic view (a point light's cube faces each their own).
  static const char* const kForEach[] = {"", "light", "caustic_view"};
  static const char* const kMadeOnce[] = {"once", "once per light", "once per caustic view"};
  int made = 0;
  for (int k = 1; k < 3; ++k) made = pass.value("for_each", "") == kForEach[k] ? k : made;
  if (ImGui::Combo("made", &made, kMadeOnce, 3)) set_for_each(name, kForEach[made]);
  ImGui::Separator();
  for (const auto& d : decl->params) {
    const ordered_json current =
        pass.contains("params") && pass["params"].contains(d.name) ? pass["params"][d.name] : ordered_json(d.default_value);
    ImGui::PushID(d.name.c_str());
    parameter_name(d);
    ImGui::SetNextItemWidth(-FLT_MIN);
    // A graph parameter ("$name") or, for a number, an expression: shown as written.
    if (current.is_string() && (d.type != graph::ParamType::choice || current.get<std::string>().starts_with('$'))) {
      ImGui::TextDisabled("= %s", current.get<std::string>().c_str());
      ImGui::SameLine();
      if (ImGui::SmallButton("own value")) set_param(name, d.name, d.default_value);
    } else if (d.type == graph::ParamType::bool_) {
      bool v = current.get<bool>();
      if (ImGui::Checkbox("##value", &v)) set_param(name, d.name, v);
    } else if (d.type == graph::ParamType::int_) {
      int v = current.get<int>();
      if (ImGui::InputInt("##value", &v, 1, 16, ImGuiInputTextFlags_EnterReturnsTrue)) set_param(name, d.name, v);
    } else if (d.type == graph::ParamType::float_) {
      float v = current.get<float>();
      if (ImGui::InputFloat("##value", &v, 0.0f, 0.0f, "%.4g", ImGuiInputTextFlags_EnterReturnsTrue)) set_param(name, d.name, v);
    } else if (d.type == graph::ParamType::choice) {
      const std::string value = current.get<std::string>();
      if (ImGui::BeginCombo("##value", value.c_str())) {
        for (const auto& c : d.choices) {
          if (ImGui::Selectable(c.c_str(), c == value)) set_param(name, d.name, c);
        }
        ImGui::EndCombo();
      }
    }
    if (ImGui::IsItemHovered() && !d.description.empty()) ImGui::SetTooltip("%s", d.description.c_str());
    ImGui::PopID();
  }
  ImGui::Separator();
  for (const auto& port : decl->ports) {
    const std::string resource = resource_of(name, port.name);
    ImGui::PushID(port.name.c_str());
    ImGui::Text("%s %s: %s", port.access == graph::PortAccess::read ? "in " : "out", port.name.c_str(),
                resource.empty() ? "-" : resource.c_str());
    if (!resource.empty()) {
      ImGui::SameLine();
      if (ImGui::SmallButton("disconnect")) disconnect(name, port.name);
    }
    ImGui::PopID();
  }
}

// The viewer's sliders for the graph's parameters; here a value set is the file's default, an
// edit of the graph like any other (undone with Ctrl+Z, written by Ctrl+S).
void GraphEditor::draw_graph_parameters() {
  if (parameters_.empty()) ImGui::TextDisabled("this graph declares no parameters");
  for (const auto& parameter : parameters_) {
    if (const auto value = parameter_input(parameter.decl, parameter.value)) set_graph_parameter(parameter.decl.name, *value);
  }
}

}  // namespace caustica::editor
