#include "model/canvas_layout.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

namespace caustica::editor {
namespace {

using nlohmann::ordered_json;

constexpr float kMargin = 12.0f;     // between the canvas's edge and the graph, in the fitted view
constexpr float kColumnGap = 40.0f;  // room for the wires between columns
constexpr float kStackGap = 4.0f;    // between the nodes of a column: the tallest columns (the G-buffer and light passes)
                                     // of the bundled graphs fit the default canvas with 1 px to spare
constexpr float kBend = 40.0f;       // the least horizontal pull of a wire's control points
constexpr float kLoopDrop = 60.0f;   // how far below its node a pass's wire to itself loops

// Each pass's column: one right of the deepest pass it reads from or is ordered after, and, for a
// pass that others read, pulled right to just before its first reader, so that the sources of a late
// pass (a shadow map the lighting reads) do not pile up in the first column.
std::map<std::string, int> columns_of(const ordered_json& graph) {
  std::map<std::string, std::string> writer;  // resource -> pass
  for (const auto& pass : graph["passes"]) {
    if (!pass.contains("outputs")) continue;
    for (const auto& [port, resource] : pass["outputs"].items()) writer[resource.get<std::string>()] = pass["name"];
  }
  std::map<std::string, std::set<std::string>> before;  // pass -> the passes it reads from or runs after
  for (const auto& pass : graph["passes"]) {
    const std::string name = pass["name"];
    before[name];
    if (pass.contains("inputs")) {
      for (const auto& [port, resource] : pass["inputs"].items()) {
        const auto w = writer.find(resource.get<std::string>());
        if (w != writer.end() && w->second != name) before[name].insert(w->second);
      }
    }
    if (pass.contains("after") && pass["after"].is_array()) {
      for (const auto& other : pass["after"]) {
        if (other.is_string() && other != name && before.count(other.get<std::string>())) before[name].insert(other.get<std::string>());
      }
    }
  }
  // One round per pass settles any order of the file; a cycle (refused by the compiler) is cut off.
  const int passes = static_cast<int>(before.size());
  std::map<std::string, int> column;
  for (int round = 0; round < passes; ++round) {
    for (const auto& [name, sources] : before) {
      int c = 0;
      for (const auto& source : sources) c = std::max(c, column[source] + 1);
      column[name] = std::min(c, passes);
    }
  }
  for (int round = 0; round < passes; ++round) {
    for (const auto& [name, sources] : before) {
      for (const auto& source : sources) {
        int first_reader = passes + 1;
        for (const auto& [reader, read] : before) {
          if (read.count(source)) first_reader = std::min(first_reader, column[reader]);
        }
        column[source] = std::max(column[source], first_reader - 1);
      }
    }
  }
  return column;
}

// The node's size for its text: the widest of its title, its rows of input and output labels and
// the longest statistics line.
void size_node(CanvasNode& n, const TextMeasure& text) {
  const NodeMetrics m(text);
  float width = std::max(text.width(n.title), text.width("reused (unchanged)"));
  const size_t rows = std::max(n.inputs.size(), n.outputs.size());
  for (size_t i = 0; i < rows; ++i) {
    const float in = i < n.inputs.size() ? text.width(n.inputs[i]) : 0.0f;
    const float out = i < n.outputs.size() ? text.width(n.outputs[i]) : 0.0f;
    width = std::max(width, in + out + 2.0f * m.port_inset + text.line_height - 2.0f * m.padding);
  }
  n.box.w = std::ceil(width + 2.0f * m.padding);
  n.box.h = std::ceil(m.header + static_cast<float>(rows + 1) * m.row + m.padding * 0.5f);
}

}  // namespace

std::vector<CanvasNode> layout_nodes(const ordered_json& graph, const graph::PassRegistry& registry, const TextMeasure& text) {
  const std::map<std::string, int> column_of = columns_of(graph);
  const ordered_json positions =
      graph.contains("editor") ? graph["editor"].value("positions", ordered_json::object()) : ordered_json::object();
  std::vector<CanvasNode> nodes;
  std::map<int, std::vector<size_t>> columns;
  for (const auto& pass : graph["passes"]) {
    CanvasNode n;
    n.name = pass["name"];
    n.type = pass["type"];
    n.title = n.name == n.type ? n.name : n.name + ": " + n.type;
    const auto* decl = registry.find(n.type);
    if (decl && decl->user_kind != graph::UserShaderKind::none && pass.contains("ports") && pass["ports"].is_object()) {
      // A user pass's ports are its own, as the file declares them (from its shader's bindings).
      for (const auto& [port, declared] : pass["ports"].items()) {
        const std::string access = declared.is_object() ? declared.value("access", "read") : "read";
        if (access != "write") n.inputs.push_back(port);
        if (access != "read") n.outputs.push_back(port);
      }
    } else if (decl) {
      for (const auto& port : decl->ports) {
        if (port.access != graph::PortAccess::write) n.inputs.push_back(port.name);
        if (port.access != graph::PortAccess::read) n.outputs.push_back(port.name);
      }
    }
    size_node(n, text);
    if (positions.contains(n.name) && positions[n.name].is_array() && positions[n.name].size() == 2) {
      n.box.x = positions[n.name][0].get<float>();
      n.box.y = positions[n.name][1].get<float>();
    } else {
      columns[column_of.at(n.name)].push_back(nodes.size());
    }
    nodes.push_back(std::move(n));
  }
  // Columns as wide as their widest node, so that no node reaches into the next column's.
  float x = 0.0f;
  for (const auto& [column, members] : columns) {
    float width = 0.0f, y = 0.0f;
    for (size_t i : members) {
      nodes[i].box.x = x;
      nodes[i].box.y = y;
      y += nodes[i].box.h + kStackGap;
      width = std::max(width, nodes[i].box.w);
    }
    x += width + kColumnGap;
  }
  return nodes;
}

Point port_position(const CanvasNode& node, const std::string& port, bool output, const TextMeasure& text) {
  const NodeMetrics m(text);
  const auto& list = output ? node.outputs : node.inputs;
  const auto row = static_cast<float>(std::find(list.begin(), list.end(), port) - list.begin());
  return {output ? node.box.right() : node.box.x, node.box.y + m.header + (row + 0.5f) * m.row};
}

Box stats_line(const CanvasNode& node, const TextMeasure& text) {
  const NodeMetrics m(text);
  const auto rows = static_cast<float>(std::max(node.inputs.size(), node.outputs.size()));
  return {node.box.x + m.padding, node.box.y + m.header + rows * m.row, node.box.w - 2.0f * m.padding, m.row};
}

std::array<Point, 4> wire_curve(Point from, Point to, bool self_loop) {
  const float bend = std::max(kBend, std::abs(to.x - from.x) * 0.5f);
  const float drop = self_loop ? kLoopDrop : 0.0f;
  return {from, Point{from.x + bend, from.y + drop}, Point{to.x - bend, to.y + drop}, to};
}

Point curve_point(const std::array<Point, 4>& c, float t) {
  const float u = 1.0f - t;
  const float a = u * u * u, b = 3.0f * u * u * t, d = 3.0f * u * t * t, e = t * t * t;
  return {a * c[0].x + b * c[1].x + d * c[2].x + e * c[3].x, a * c[0].y + b * c[1].y + d * c[2].y + e * c[3].y};
}

float distance_to_curve(const std::array<Point, 4>& curve, Point p) {
  constexpr int kSamples = 32;
  float nearest = INFINITY;
  Point previous = curve[0];
  for (int i = 1; i <= kSamples; ++i) {
    const Point next = curve_point(curve, static_cast<float>(i) / kSamples);
    // The distance to the segment from previous to next.
    const float dx = next.x - previous.x, dy = next.y - previous.y;
    const float length2 = dx * dx + dy * dy;
    const float t = length2 > 0.0f ? std::clamp(((p.x - previous.x) * dx + (p.y - previous.y) * dy) / length2, 0.0f, 1.0f) : 0.0f;
    const float ex = previous.x + t * dx - p.x, ey = previous.y + t * dy - p.y;
    nearest = std::min(nearest, std::sqrt(ex * ex + ey * ey));
    previous = next;
  }
  return nearest;
}

std::vector<std::optional<Box>> place_wire_labels(const std::vector<CanvasNode>& nodes, const std::vector<Wire>& wires,
                                                  const std::vector<std::string>& labels, const TextMeasure& text) {
  auto find = [&](const std::string& name) -> const CanvasNode* {
    for (const auto& n : nodes) {
      if (n.name == name) return &n;
    }
    return nullptr;
  };
  std::vector<std::optional<Box>> placed(wires.size());
  std::vector<Box> taken;
  for (size_t i = 0; i < wires.size() && i < labels.size(); ++i) {
    const CanvasNode* writer = find(wires[i].writer);
    const CanvasNode* reader = find(wires[i].reader);
    if (!writer || !reader) continue;
    const auto curve = wire_curve(port_position(*writer, wires[i].output, true, text), port_position(*reader, wires[i].input, false, text),
                                  writer == reader);
    const float w = text.width(labels[i]) + 6.0f, h = text.line_height + 2.0f;
    // On the wire, or just above or below it where a node or a label is in the way.
    for (float t : {0.5f, 0.4f, 0.6f, 0.3f, 0.7f, 0.2f, 0.8f}) {
      const Point p = curve_point(curve, t);
      for (float shift : {0.0f, -h * 0.5f, h * 0.5f}) {
        const Box box{p.x - w * 0.5f, p.y - h * 0.5f + shift, w, h};
        const auto hits = [&](const Box& other) { return box.overlaps(other); };
        if (std::any_of(nodes.begin(), nodes.end(), [&](const CanvasNode& n) { return hits(n.box); }) ||
            std::any_of(taken.begin(), taken.end(), hits))
          continue;
        placed[i] = box;
        taken.push_back(box);
        break;
      }
      if (placed[i]) break;
    }
  }
  return placed;
}

CanvasView fit_view(const std::vector<CanvasNode>& nodes, float width, float height) {
  CanvasView view;
  if (nodes.empty()) return view;
  float x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
  for (const auto& n : nodes) {
    x0 = std::min(x0, n.box.x);
    y0 = std::min(y0, n.box.y);
    x1 = std::max(x1, n.box.right());
    y1 = std::max(y1, n.box.bottom());
  }
  const float room_x = width / view.zoom, room_y = height / view.zoom;
  view.pan_x = x1 - x0 + 2.0f * kMargin <= room_x ? (room_x - (x1 - x0)) * 0.5f - x0 : kMargin - x0;
  view.pan_y = y1 - y0 + 2.0f * kMargin <= room_y ? (room_y - (y1 - y0)) * 0.5f - y0 : kMargin - y0;
  return view;
}

}  // namespace caustica::editor
