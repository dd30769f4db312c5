#pragma once
// The editor canvas's geometry, without a window: node boxes sized for their text, the layout of
// the passes that the file gives no position, the wires' curves and their labels, and the view that
// shows the graph. All of it is in canvas units, which are window pixels at zoom 1; text is measured
// by the caller (ImGui's font in the editor, a fixed-width stand-in in tests), so that the rules the
// canvas keeps (every node inside it, no label over a node or another label, text no smaller than
// the panels') can be checked on the CPU.
#include <array>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "graph/pass_type.h"
#include "model/graph_model.h"

namespace caustica::editor {

struct Point {
  float x = 0, y = 0;
};

struct Box {
  float x = 0, y = 0, w = 0, h = 0;
  float right() const { return x + w; }
  float bottom() const { return y + h; }
  bool overlaps(const Box& o) const { return x < o.right() && o.x < right() && y < o.bottom() && o.y < bottom(); }
  bool contains(const Box& o) const { return o.x >= x && o.y >= y && o.right() <= right() && o.bottom() <= bottom(); }
  bool contains(Point p) const { return p.x >= x && p.y >= y && p.x <= right() && p.y <= bottom(); }
};

// The font the canvas draws with, at zoom 1: the height of a line and the width of a text.
struct TextMeasure {
  float line_height = 13.0f;
  std::function<float(const std::string&)> width;
};

struct CanvasNode {
  std::string name, type;
  std::string title;  // "name: type", or the name alone when the pass is named after its type
  // A read_write port is on both sides: the wire in from the pass it reads after, and out.
  std::vector<std::string> inputs, outputs;
  Box box;
};

// A node's rows at a font: the title, a row per port pair, and one line of statistics (the GPU
// time); counters and messages are shown on hover, so that a node's size never changes while it runs.
struct NodeMetrics {
  float header, row, padding, port_radius, port_inset;  // port_inset: from the node's edge to a port's label
  explicit NodeMetrics(const TextMeasure& text)
      : header(text.line_height + 8.0f),
        row(text.line_height + 4.0f),
        padding(6.0f),
        port_radius(text.line_height * 0.38f),
        port_inset(text.line_height * 0.7f) {}
};

// Every pass of `graph` as a node sized for its text: placed where the file's "editor" block says,
// or else in columns by dependency depth (a pass right of every pass it reads from), each column
// stacked top down.
std::vector<CanvasNode> layout_nodes(const nlohmann::ordered_json& graph, const graph::PassRegistry& registry, const TextMeasure& text);

// Where a port's dot is: on the left edge for an input, the right edge for an output, at its row.
Point port_position(const CanvasNode& node, const std::string& port, bool output, const TextMeasure& text);
// The box of a node's statistics line (below its ports).
Box stats_line(const CanvasNode& node, const TextMeasure& text);

// A wire's cubic Bezier from an output port to an input port; one from a pass to itself (a history
// input reading its own last result) loops below the node.
std::array<Point, 4> wire_curve(Point from, Point to, bool self_loop);
Point curve_point(const std::array<Point, 4>& curve, float t);
// The distance from `p` to the curve (sampled), for hovering.
float distance_to_curve(const std::array<Point, 4>& curve, Point p);

// Labels along the wires (`labels[i]` for `wires[i]`): each centred on a point of its wire, the
// first of several along it where it lies over no node and no label placed before; none when no
// point is free (the canvas shows that label when the wire is hovered).
std::vector<std::optional<Box>> place_wire_labels(const std::vector<CanvasNode>& nodes, const std::vector<Wire>& wires,
                                                  const std::vector<std::string>& labels, const TextMeasure& text);

// The smallest zoom the canvas draws text at: its font's own size, the panels' text size. The font
// is a bitmap font; drawn smaller, rows of its glyphs are dropped ("g" reads "c", "_" vanishes).
inline constexpr float kReadableZoom = 1.0f;

// Screen = origin + (canvas + pan) * zoom.
struct CanvasView {
  float pan_x = 0, pan_y = 0, zoom = kReadableZoom;
  Point to_screen(Point origin, Point canvas) const { return {origin.x + (canvas.x + pan_x) * zoom, origin.y + (canvas.y + pan_y) * zoom}; }
  Point to_canvas(Point origin, Point screen) const { return {(screen.x - origin.x) / zoom - pan_x, (screen.y - origin.y) / zoom - pan_y}; }
};
// The view that shows the whole graph in a canvas of `width` x `height` at the readable zoom,
// centred where it is smaller than the canvas, its top left corner in view where it is larger.
CanvasView fit_view(const std::vector<CanvasNode>& nodes, float width, float height);

// Where the editor docks at the bottom of a window of `height`, unless the user drags its top edge:
// below half of the window, so that most of the picture stays in view.
inline constexpr float kDockFraction = 0.48f;
// The canvas that the dock leaves beside its side panel in the editor's default window (1600x900),
// as ImGui lays it out; tests/view/edit_test.sh checks the window's, tests/editor_model_test.cpp
// every bundled graph in it.
inline constexpr float kDefaultCanvasWidth = 1282.0f, kDefaultCanvasHeight = 364.0f;

}  // namespace caustica::editor
