// The editor's window: the canvas of the graph (ImGui draw lists: nodes, ports, wires, gestures)
// and the side panel of the selected pass. Every change goes through GraphEditor's actions.
#include <imgui.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <vector>

#include "edit/graph_editor.h"

namespace caustica::editor {
namespace {

using nlohmann::ordered_json;

ImVec2 operator+(ImVec2 a, ImVec2 b) {
  return {a.x + b.x, a.y + b.y};
}

}  // namespace

void GraphEditor::draw(const graph::FrameResult& frame) {
  const ImVec2 display = ImGui::GetIO().DisplaySize;
  ImGui::SetNextWindowPos(ImVec2(390, display.y * 0.45f), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(display.x - 400, display.y * 0.55f - 10), ImGuiCond_FirstUseEver);
  ImGui::Begin("graph editor", nullptr, ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoScrollWithMouse);
  ImGui::TextColored(status_is_error_ ? ImVec4(1, 0.4f, 0.3f, 1) : ImVec4(0.6f, 0.9f, 0.6f, 1), "%s", status_.c_str());
  ImGui::TextDisabled("right click: add a pass   drag port to port: connect   Del: remove   middle drag: pan   wheel: zoom");
  const float side = 260.0f;
  ImGui::BeginChild("canvas", ImVec2(ImGui::GetContentRegionAvail().x - side, 0), true,
                    ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoScrollWithMouse);
  draw_canvas(frame);
  ImGui::EndChild();
  ImGui::SameLine();
  ImGui::BeginChild("selected pass", ImVec2(0, 0), true);
  draw_side_panel();
  ImGui::EndChild();
  ImGui::End();
}

// Where the canvas lies on screen this frame, and drawing in canvas units: screen = origin +
// (canvas + pan) * zoom. Text scales with the canvas, so that a zoomed-out graph does not overlap itself.
struct GraphEditor::CanvasView {
  ImDrawList* draw;
  ImVec2 origin;
  float pan_x, pan_y, zoom;
  float font_size = ImGui::GetFontSize() * zoom;

  ImVec2 to_screen(float x, float y) const { return ImVec2(origin.x + (x + pan_x) * zoom, origin.y + (y + pan_y) * zoom); }
  ImVec2 to_canvas(ImVec2 p) const { return ImVec2((p.x - origin.x) / zoom - pan_x, (p.y - origin.y) / zoom - pan_y); }
  void text_at(ImVec2 p, ImU32 colour, const std::string& t, float wrap = 0.0f) const {
    draw->AddText(ImGui::GetFont(), font_size, p, colour, t.c_str(), nullptr, wrap);
  }
  ImVec2 text_size(const std::string& t) const { return ImGui::GetFont()->CalcTextSizeA(font_size, FLT_MAX, 0.0f, t.c_str()); }
  ImVec2 port_pos(const Node& n, const std::string& port, bool output) const {
    const auto& list = output ? n.outputs : n.inputs;
    const auto i = static_cast<float>(std::find(list.begin(), list.end(), port) - list.begin());
    return to_screen(n.x + (output ? kNodeWidth : 0.0f), n.y + kHeader + (i + 0.5f) * kRow);
  }
};

void GraphEditor::draw_canvas(const graph::FrameResult& frame) {
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  const ImVec2 size = ImGui::GetContentRegionAvail();
  ImGui::InvisibleButton("canvas", size,
                         ImGuiButtonFlags_MouseButtonLeft | ImGuiButtonFlags_MouseButtonMiddle | ImGuiButtonFlags_MouseButtonRight);
  canvas_hovered_ = ImGui::IsItemHovered();
  pan_and_zoom(origin);
  if (!fitted_ && !nodes_.empty() && size.x > 1 && size.y > 1) fit_view(size);
  const CanvasView view{ImGui::GetWindowDrawList(), origin, pan_x_, pan_y_, zoom_};
  view.draw->PushClipRect(origin, origin + size, true);
  port_positions_.clear();
  draw_wires(view);
  const Hovered hovered = draw_nodes(view, frame);
  canvas_gestures(view, hovered);
  view.draw->PopClipRect();
  if (canvas_hovered_ && ImGui::IsMouseClicked(ImGuiMouseButton_Right)) {
    const ImVec2 m = view.to_canvas(ImGui::GetIO().MousePos);
    menu_x_ = m.x;
    menu_y_ = m.y;
    filter_[0] = '\0';
    menu_has_keyboard_ = false;
    ImGui::OpenPopup("add pass");
  }
  draw_add_menu();
}

// Middle drag pans, the wheel zooms about the mouse.
void GraphEditor::pan_and_zoom(ImVec2 origin) {
  ImGuiIO& io = ImGui::GetIO();
  if (canvas_hovered_ && ImGui::IsMouseDragging(ImGuiMouseButton_Middle)) {
    pan_x_ += io.MouseDelta.x / zoom_;
    pan_y_ += io.MouseDelta.y / zoom_;
  }
  if (canvas_hovered_ && io.MouseWheel != 0.0f) {
    const ImVec2 before = CanvasView{nullptr, origin, pan_x_, pan_y_, zoom_}.to_canvas(io.MousePos);
    zoom_ = std::clamp(zoom_ * std::pow(1.1f, io.MouseWheel), 0.3f, 3.0f);
    const ImVec2 after = CanvasView{nullptr, origin, pan_x_, pan_y_, zoom_}.to_canvas(io.MousePos);
    pan_x_ += after.x - before.x;
    pan_y_ += after.y - before.y;
  }
}

// The whole graph in view, no larger than life.
void GraphEditor::fit_view(ImVec2 size) {
  float x0 = 1e9f, y0 = 1e9f, x1 = -1e9f, y1 = -1e9f;
  for (const auto& n : nodes_) {
    x0 = std::min(x0, n.x);
    y0 = std::min(y0, n.y);
    x1 = std::max(x1, n.x + kNodeWidth);
    y1 = std::max(y1, n.y + kHeader + static_cast<float>(std::max(n.inputs.size(), n.outputs.size()) + 2) * kRow);
  }
  zoom_ = std::clamp(std::min(size.x / (x1 - x0 + 40.0f), size.y / (y1 - y0 + 40.0f)), 0.6f, 1.0f);
  pan_x_ = 20.0f / zoom_ - x0;
  pan_y_ = 20.0f / zoom_ - y0;
  fitted_ = true;
}

// Wires: from the writer's output port to each reader's input port, labelled with the resource's
// format and extent as compiled; a history input's wire (the last frame's resource) in blue, looping
// below the node when a pass reads its own last result.
void GraphEditor::draw_wires(const CanvasView& view) const {
  const graph::Plan& plan = viewer_.plan();
  for (const Wire& wire : wires(model_.json())) {
    const Node* writer = node(wire.writer);
    const Node* reader = node(wire.reader);
    if (!writer || !reader) continue;
    const ImVec2 a = view.port_pos(*writer, wire.output, true), b = view.port_pos(*reader, wire.input, false);
    const float bend = std::max(40.0f, std::abs(b.x - a.x) * 0.5f) * view.zoom;
    const float drop = writer == reader ? 60.0f * view.zoom : 0.0f;
    view.draw->AddBezierCubic(a, ImVec2(a.x + bend, a.y + drop), ImVec2(b.x - bend, b.y + drop), b,
                              wire.history ? IM_COL32(140, 170, 255, 220) : IM_COL32(200, 200, 120, 200), 2.0f);
    std::string label = wire.history ? "last frame's " + wire.resource : wire.resource;
    if (const int r = plan.find_resource(wire.resource); r >= 0) {
      const auto& pr = plan.resources[static_cast<size_t>(r)];
      label += " " + std::string(graph::format_info(pr.format).name) + " " + std::to_string(pr.width) + "x" + std::to_string(pr.height);
    }
    const ImVec2 middle((a.x + b.x) * 0.5f - view.text_size(label).x * 0.5f, (a.y + b.y) * 0.5f + drop * 0.75f - view.font_size);
    view.draw->AddRectFilled(middle, middle + view.text_size(label), IM_COL32(20, 20, 20, 170));
    view.text_at(middle, IM_COL32(220, 220, 170, 255), label);
  }
}

// Each node: its box (grey when culled, outlined when selected or refused), its ports, its last
// GPU time and first counters, its error. Returns what the mouse is over.
GraphEditor::Hovered GraphEditor::draw_nodes(const CanvasView& view, const graph::FrameResult& frame) {
  const graph::Plan& plan = viewer_.plan();
  const ImGuiIO& io = ImGui::GetIO();
  Hovered hovered;
  for (const auto& n : nodes_) {
    const bool culled = std::find(plan.culled.begin(), plan.culled.end(), n.name) != plan.culled.end() ||
                        std::none_of(plan.passes.begin(), plan.passes.end(), [&](const auto& p) { return p.name == n.name; });
    const auto timing = std::find_if(frame.passes.begin(), frame.passes.end(), [&](const auto& p) { return p.name == n.name; });
    std::vector<std::string> lines;
    if (timing != frame.passes.end() && !timing->ran) {
      lines.emplace_back("reused (unchanged)");
    } else if (timing != frame.passes.end()) {
      char text[64];
      std::snprintf(text, sizeof text, "GPU %.2f ms", timing->gpu_ms);
      lines.emplace_back(text);
    }
    for (const auto& [counter, value] : frame.counters) {
      const auto owner = frame.counter_passes.find(counter);
      if (owner == frame.counter_passes.end() || owner->second != n.name || lines.size() >= kCounterLines) continue;
      char text[128];
      std::snprintf(text, sizeof text, "%s %.4g", counter.c_str(), value);
      lines.emplace_back(text);
    }
    const auto error = node_errors_.find(n.name);
    const float rows =
        static_cast<float>(std::max(n.inputs.size(), n.outputs.size()) + lines.size()) + (error != node_errors_.end() ? 2.0f : 0.0f);
    const ImVec2 top = view.to_screen(n.x, n.y), bottom = view.to_screen(n.x + kNodeWidth, n.y + kHeader + rows * kRow + 4.0f);
    const bool selected = selected_.count(n.name) > 0;
    view.draw->AddRectFilled(top, bottom, culled ? IM_COL32(45, 45, 45, 230) : IM_COL32(35, 45, 70, 235), 4.0f);
    view.draw->AddRectFilled(top, ImVec2(bottom.x, top.y + kHeader * view.zoom),
                             culled ? IM_COL32(70, 70, 70, 255) : IM_COL32(60, 90, 150, 255), 4.0f);
    view.draw->AddRect(top, bottom,
                       selected                      ? IM_COL32(255, 220, 90, 255)
                       : error != node_errors_.end() ? IM_COL32(240, 80, 60, 255)
                                                     : IM_COL32(90, 90, 90, 255),
                       4.0f, 0, selected ? 2.5f : 1.0f);
    const ImU32 text = culled ? IM_COL32(140, 140, 140, 255) : IM_COL32(235, 235, 235, 255);
    view.text_at(ImVec2(top.x + 5 * view.zoom, top.y + 3 * view.zoom), text, n.name + (culled ? " (culled)" : "") + ": " + n.type);
    for (int side = 0; side < 2; ++side) {
      const auto& ports = side ? n.outputs : n.inputs;
      for (const auto& port : ports) {
        const ImVec2 p = view.port_pos(n, port, side == 1);
        const bool bound = !resource_of(n.name, port).empty();
        view.draw->AddCircleFilled(p, kPortRadius * view.zoom, bound ? IM_COL32(200, 200, 120, 255) : IM_COL32(110, 110, 110, 255));
        const ImVec2 label_size = view.text_size(port);
        view.text_at(ImVec2(side ? p.x - label_size.x - 8 * view.zoom : p.x + 8 * view.zoom, p.y - label_size.y * 0.5f), text, port);
        const float dx = io.MousePos.x - p.x, dy = io.MousePos.y - p.y;
        if (dx * dx + dy * dy < 64.0f) hovered.port = PortHit{n.name, port, side == 1};
        port_positions_[n.name + "." + port] = {p.x, p.y};
      }
    }
    float y = n.y + kHeader + static_cast<float>(std::max(n.inputs.size(), n.outputs.size())) * kRow;
    for (const auto& line : lines) {
      view.text_at(view.to_screen(n.x + 5, y), IM_COL32(150, 200, 255, 255), line);
      y += kRow;
    }
    if (error != node_errors_.end()) {
      view.text_at(view.to_screen(n.x + 5, y), IM_COL32(255, 110, 90, 255), error->second, (kNodeWidth - 10) * view.zoom);
    }
    if (io.MousePos.x >= top.x && io.MousePos.x <= bottom.x && io.MousePos.y >= top.y && io.MousePos.y <= bottom.y) hovered.node = n.name;
  }
  return hovered;
}

// Gestures: drag port to port connects, drag a node moves it, drag the background box-selects.
void GraphEditor::canvas_gestures(const CanvasView& view, const Hovered& hovered) {
  const ImGuiIO& io = ImGui::GetIO();
  if (canvas_hovered_ && ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
    if (hovered.port) {
      wire_from_ = hovered.port;
    } else if (!hovered.node.empty()) {
      if (!io.KeyShift && !selected_.count(hovered.node)) selected_.clear();
      selected_.insert(hovered.node);
      if (const Node* n = node(hovered.node)) {
        dragging_node_ = hovered.node;
        const ImVec2 m = view.to_canvas(io.MousePos);
        drag_dx_ = m.x - n->x;
        drag_dy_ = m.y - n->y;
      }
    } else {
      box_selecting_ = true;
      const ImVec2 m = view.to_canvas(io.MousePos);
      box_x0_ = m.x;
      box_y0_ = m.y;
    }
  }
  if (!dragging_node_.empty()) {
    const ImVec2 m = view.to_canvas(io.MousePos);
    for (auto& n : nodes_) {
      if (n.name == dragging_node_) {
        n.x = m.x - drag_dx_;
        n.y = m.y - drag_dy_;
      }
    }
    if (ImGui::IsMouseReleased(ImGuiMouseButton_Left)) {
      const std::string name = std::move(dragging_node_);
      dragging_node_.clear();
      if (const Node* n = node(name)) {
        const float x = n->x, y = n->y;
        move(name, x, y);
      }
    }
  }
  if (wire_from_) {
    const Node* from = node(wire_from_->pass);
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
    const ImVec2 m = view.to_canvas(io.MousePos);
    view.draw->AddRect(view.to_screen(box_x0_, box_y0_), io.MousePos, IM_COL32(255, 220, 90, 200));
    if (ImGui::IsMouseReleased(ImGuiMouseButton_Left)) {
      box_selecting_ = false;
      if (!io.KeyShift) selected_.clear();
      const float x0 = std::min(box_x0_, m.x), x1 = std::max(box_x0_, m.x), y0 = std::min(box_y0_, m.y), y1 = std::max(box_y0_, m.y);
      for (const auto& n : nodes_) {
        if (n.x + kNodeWidth >= x0 && n.x <= x1 && n.y + kHeader >= y0 && n.y <= y1) selected_.insert(n.name);
      }
    }
  }
}

void GraphEditor::draw_add_menu() {
  if (!ImGui::BeginPopup("add pass")) return;
  if (ImGui::IsWindowAppearing()) ImGui::SetKeyboardFocusHere();
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
    if (ImGui::Selectable(decl->type.c_str())) chosen = decl->type;
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", decl->description.c_str());
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
  if (selected_.size() != 1) {
    ImGui::TextDisabled(selected_.empty() ? "select a pass to edit it" : "%zu passes selected (Del removes them)", selected_.size());
    return;
  }
  const std::string name = *selected_.begin();
  ordered_json pass;
  for (const auto& p : model_.json()["passes"]) {
    if (p["name"] == name) pass = p;
  }
  const graph::PassTypeDecl* decl = model_.registry().find(pass.value("type", ""));
  if (!decl) return;
  ImGui::Text("%s (%s)", name.c_str(), decl->type.c_str());
  ImGui::InputTextWithHint("##rename", "new name", rename_, sizeof rename_);
  ImGui::SameLine();
  if (ImGui::Button("rename") && rename_[0]) rename(name, rename_);
  if (ImGui::Button("remove pass")) remove_selected();
  ImGui::Separator();
  for (const auto& d : decl->params) {
    const ordered_json current =
        pass.contains("params") && pass["params"].contains(d.name) ? pass["params"][d.name] : ordered_json(d.default_value);
    ImGui::PushID(d.name.c_str());
    // A graph parameter ("$name") or, for a number, an expression: shown as written.
    if (current.is_string() && (d.type != graph::ParamType::choice || current.get<std::string>().starts_with('$'))) {
      ImGui::Text("%s = %s", d.name.c_str(), current.get<std::string>().c_str());
      ImGui::SameLine();
      if (ImGui::SmallButton("own value")) set_param(name, d.name, d.default_value);
    } else if (d.type == graph::ParamType::bool_) {
      bool v = current.get<bool>();
      if (ImGui::Checkbox(d.name.c_str(), &v)) set_param(name, d.name, v);
    } else if (d.type == graph::ParamType::int_) {
      int v = current.get<int>();
      if (ImGui::InputInt(d.name.c_str(), &v, 1, 16, ImGuiInputTextFlags_EnterReturnsTrue)) set_param(name, d.name, v);
    } else if (d.type == graph::ParamType::float_) {
      float v = current.get<float>();
      if (ImGui::InputFloat(d.name.c_str(), &v, 0.0f, 0.0f, "%.4g", ImGuiInputTextFlags_EnterReturnsTrue)) set_param(name, d.name, v);
    } else if (d.type == graph::ParamType::choice) {
      const std::string value = current.get<std::string>();
      if (ImGui::BeginCombo(d.name.c_str(), value.c_str())) {
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

}  // namespace caustica::editor
