// caustica view and caustica edit: the flags; the viewer and the editor live in editor/.
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <vector>

#include <unistd.h>

#include "builtin_passes.h"
#include "cli.h"
#include "core/paths.h"
#include "edit/graph_editor.h"
#include "flags.h"
#include "io/files.h"
#include "io/image_io.h"
#include "io/json_document.h"
#include "model/graph_model.h"
#include "viewer/viewer.h"

namespace caustica::cli {
namespace {

// The editor's window: the canvas docked below the picture shows every bundled graph whole at the
// panels' text size (tests/editor_model_test.cpp checks it).
constexpr uint32_t kEditWidth = 1600, kEditHeight = 900;

const char* kViewHelp = R"(usage: caustica view [--graph FILE] [--scene FILE] [--size WxH] [--frames N] [--screenshot F.png]
                     [--window-shot F.png] [--inspect IMAGE] [--set NAME=VALUE]... [--continuous] [--max-fps N]
                     [--validate] [--device NAME]

Opens a window that runs the graph on the scene (defaults as for render): the compiled passes in
order with their GPU and CPU times over the last frames, the counters, transient memory with and
without aliasing, passes switched off and on where the graph stays valid, the graph's parameters,
editable within their ranges and saved back into the graph
file (only the values change), and a resource inspector: any image of the graph (G-buffer normals,
light-view buffers, the caustic map, the caustic map's levels side by side) in its own panel, or
in place of the output, with an exposure. Saving the graph or the
scene file, or a shader, in an editor reloads it within a second; a file that fails to load or
compile leaves the last good one running and shows the error on screen. Nothing is rendered while
nothing changes (no input, no reload), unless --continuous or the C key.

)";

const char* kEditHelp = R"(usage: caustica edit GRAPH [--scene FILE] [--size WxH] [--frames N] [--screenshot F.png]
                     [--window-shot F.png] [--script FILE] [--continuous] [--max-fps N] [--validate] [--device NAME]

The graph editor: the viewer (caustica view --help) with a canvas of the graph, docked at the
bottom of the window (drag its top edge to give the picture or the canvas more room; the viewer's
panel starts folded). Passes are nodes with their input and output ports and last GPU time (hover
for the counters), resources are wires labelled with their name where the label covers nothing
(hover a wire for its format and extent), culled passes are grey. The canvas opens at the panels'
text size. Drag from an output port to an input port to connect; right click for a searchable menu
of pass types; Del removes the selected passes; drag the background to select a box; middle drag
pans, the wheel zooms in. The side panel edits the selected pass's parameters, and the graph's
parameters (the viewer's sliders) as the file's defaults. Every edit is checked by the compiler
and swaps the running frame; an edit the compiler refuses keeps the last good frame and shows its
message on the node. A GRAPH that does not compile opens refused, its message shown, and a black
picture until an edit makes it compile. Ctrl+Z and Ctrl+Y undo and redo, Ctrl+S saves: only what
was edited changes in the file (node positions go into its "editor" block, which the engine
ignores), and a file changed on disk meanwhile is overwritten only after a confirmation. A new
GRAPH file does not need to exist: it starts as a copy of the default graph.

options (as caustica view's, but --size defaults to 1600x900: the canvas of every bundled graph at
the panels' text size, and --script):
)";

// The flags view and edit share; returns false for any other.
// --move-frames FIRST:END, FIRST < END.
void parse_move_frames(const std::string& text, editor::ViewerOptions& v) {
  const std::string usage = "--move-frames " + text + ": expected FIRST:END, e.g. 20:50";
  const size_t colon = text.find(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == text.size()) throw UsageError(usage + " (the frames FIRST to END-1 move)");
  const auto frame = [&](const std::string& part) {
    try {
      return static_cast<uint32_t>(parse_uint("--move-frames", part, 0, 1000000));
    } catch (const UsageError&) {
      throw UsageError(usage + " ('" + part + "' is not a whole number from 0 to 1000000)");
    }
  };
  v.move_first = frame(text.substr(0, colon));
  v.move_end = frame(text.substr(colon + 1));
  if (v.move_end <= v.move_first) throw UsageError(usage + " (END must come after FIRST)");
}

// The flags view and edit share, in the order --help lists them.
FlagTable window_flags(RenderOptions& o, editor::ViewerOptions& v, std::string size_help) {
  return {size_flag(v.width, v.height, std::move(size_help)),
          uint32_flag("--frames", "N", "quit after N frames (default: run until the window is closed); every frame is rendered", v.frames,
                      1, 1000000),
          text_flag("--screenshot", "F.png",
                    "with --frames: write the last frame's image and quit: the graph's output, or\n"
                    "with --inspect the inspected image at full size (.exr: its values as they are)",
                    v.screenshot),
          text_flag("--window-shot", "F.png", "with --frames: write the whole window as shown, panels included, and quit", v.window_shot),
          scene_flag(o.scene),
          {"--no-stage", "", "with a model file: no floor", [&v](const std::string&) { v.stage = false; }},
          {"--continuous", "", "render every frame even when nothing changes (for timing; key C toggles it)",
           [&v](const std::string&) { v.continuous = true; }},
          {"--max-fps", "N", "frame-rate cap (default 60; 0: none)",
           [&v](const std::string& text) { v.max_fps = parse_number("--max-fps", text, 0, 1000); }},
          stats_flag(v.stats,
                     "at exit, every frame's wall time (input to present, or to the frame's end where\n"
                     "it was not presented), GPU and recording time, whether it was presented, the\n"
                     "passes that ran and those reused (unchanged since they last ran), and the\n"
                     "median and 95th percentile of the wall time, over all frames and while moving"),
          {"--every-pass", "",
           "run every pass every frame; by default a pass whose inputs, parameters and\n"
           "scene parts (camera, lights, geometry) did not change keeps its last result",
           [&v](const std::string&) { v.reuse = false; }},
          number_flag("--budget", "MS",
                      "frame-time target while the camera or a light moves (default 100; 0: off): a\n"
                      "moving frame over it halves the rendered size for the next, down to a\n"
                      "quarter each way, scaled up into the window, and then uses the graph\n"
                      "parameters' \"while_moving\" values (the default graph: a coarser photon\n"
                      "grid, smaller light maps); a frame well under it goes back a step when\n"
                      "that step is predicted within the budget; a still frame is whole again",
                      v.budget_ms, 0, 10000),
          number_flag("--still-after", "MS",
                      "once nothing has moved for MS (default 300), the graph parameters'\n"
                      "\"while_still\" values, except where set in the panel (caustics_progressive:\n"
                      "exact ray-query photons accumulating, on a device with VK_KHR_ray_query);\n"
                      "while a pass converges (an accumulating mean) frames go on at rest; where\n"
                      "it lists several values (slice_side: 2, 3, 4), refining frames too slow\n"
                      "for the budget (a median over 0.9 of it) take the next, cheaper one, and\n"
                      "a quieter machine's the richer one back; the picture shows the mean\n"
                      "every 0.5 to 2 s, and frames that leave it go to the window only after\n"
                      "input or every 0.25 s",
                      v.still_after_ms, 0, 60000),
          orbit_flag(v.orbit_degrees, "turn the camera about its target by DEG each frame (scripted motion, for --stats)"),
          frame_timeout_flag(v.frame_timeout_s, &v.first_frame_timeout_s,
                             "default 5, a plan's first frame 60; the editor first writes\nunsaved edits to FILE.recovered.json"),
          {"--move-light", "D", "move the chosen light (--light) by D along x each frame (scripted motion, for --stats)",
           [&v](const std::string& text) { v.move_light = static_cast<float>(parse_number("--move-light", text, -10, 10)); }},
          {"--light", "I", "the light that the arrows and --move-light move (default 0, the first; L picks the next)",
           [&v](const std::string& text) { v.moved_light = static_cast<uint32_t>(parse_uint("--light", text, 0, 7)); }},
          {"--move-frames", "A:B",
           "the scripted motion on frames A to B-1 only (from 0), e.g. --frames 90\n"
           "--orbit 2 --move-frames 20:50 rests, orbits and rests again",
           [&v](const std::string& text) { parse_move_frames(text, v); }},
          validate_flag(o.validate, "Khronos validation; any message makes the command exit 3"),
          device_flag(o.device),
          tracer_flag()};
}

// Checks what can be checked before the window opens, and fills in the defaults.
void finish_window_options(const RenderOptions& o, editor::ViewerOptions& v) {
  if (!v.screenshot.empty() && v.frames == 0) throw UsageError("--screenshot needs --frames N: the frame it captures");
  if (!v.window_shot.empty() && v.frames == 0) throw UsageError("--window-shot needs --frames N: the frame it captures");
  if (!v.screenshot.empty()) io::check_image_output(v.screenshot);
  if (!v.window_shot.empty()) io::check_image_output(v.window_shot);
  if (!v.stats.empty() && !v.stats.ends_with(".json")) throw UsageError("--stats " + v.stats + ": a .json file");
  if (v.move_end != UINT32_MAX && v.orbit_degrees == 0.0f && v.move_light == 0.0f) {
    throw UsageError("--move-frames says when the scripted motion runs: give --orbit DEG or --move-light D too");
  }
  v.scene_file = o.scene.empty() ? (data_dir() / kDefaultScene).string() : o.scene;
  v.device = device_options(o.device, o.validate);
}

}  // namespace

int cmd_edit(Args& args) {
  RenderOptions o;
  editor::ViewerOptions v;
  v.width = kEditWidth;
  v.height = kEditHeight;
  std::string script;
  FlagTable flags = window_flags(o, v, "window size (default 1600x900)");
  flags.add(text_flag("--script", "FILE", "run an edit script, one action per frame drawn (for tests):", script));
  if (args.wants_help()) {
    std::cout << kEditHelp << flags.help() << "\n" << editor::kEditScriptHelp;
    return 0;
  }
  flags.parse(args, [&o](const std::string& graph) {
    if (!o.graph.empty()) unknown_option(graph, {});
    o.graph = graph;
  });
  if (o.graph.empty()) throw UsageError("caustica edit needs a GRAPH file (see caustica edit --help)");
  finish_window_options(o, v);
  if (!script.empty()) read_text_file(script, 1 << 20);  // a missing script is an error before the window opens
  if (!std::filesystem::exists(o.graph)) {
    io::check_output_file(o.graph);
    io::write_text_atomically(o.graph, read_text_file((data_dir() / kDefaultGraph).string(), JsonDocument::kMaxBytes));
    std::fprintf(stderr, "edit: %s is new: it starts as a copy of %s\n", o.graph.c_str(), kDefaultGraph);
  }
  editor::GraphModel model = editor::GraphModel::open(o.graph, passes::builtin_registry());
  v.graph_file = o.graph;
  v.watch_graph_file = false;  // the editor owns the file; a change on disk is met at save
  v.parameter_panel = false;   // parameters are edited in the graph, through the editor
  // A graph that does not compile opens refused: the window starts on a stand-in (the viewer needs
  // a graph that runs), which the first edit that makes the graph compile replaces.
  std::filesystem::path stand_in;
  if (!model.refusal().empty()) {
    std::fprintf(stderr, "edit: %s opens refused, to be repaired: %s\n", o.graph.c_str(), model.refusal().c_str());
    stand_in = std::filesystem::temp_directory_path() / ("caustica_edit_stand_in_" + std::to_string(getpid()) + ".json");
    io::write_text_atomically(stand_in.string(), editor::stand_in_graph(model.json().value("name", "graph")));
    v.graph_file = stand_in.string();
  }
  std::optional<editor::Viewer> viewer;
  try {
    viewer.emplace(v);
  } catch (...) {
    if (!stand_in.empty()) std::filesystem::remove(stand_in);
    throw;
  }
  if (!stand_in.empty()) std::filesystem::remove(stand_in);  // read once: the editor owns the graph from here
  editor::GraphEditor graph_editor(*viewer, model, script);
  return viewer->run();
}

int cmd_view(Args& args) {
  RenderOptions o;
  editor::ViewerOptions v;
  FlagTable flags{graph_flag(o.graph, "the graph (default as for render), or a bundled one by its name"),
                  text_flag("--inspect", "IMAGE", "open the resource inspector on one of the graph's images", v.inspect),
                  set_flag(v.sets,
                           "a graph parameter, as if set in the panel (repeatable; the while_moving and\n"
                           "while_still values leave it alone)")};
  const FlagTable window = window_flags(o, v, "window size (default 1280x720)");
  for (const Flag& f : window.flags()) flags.add(f);
  if (args.wants_help()) {
    std::cout << kViewHelp << editor::kViewerKeys << "\noptions:\n" << flags.help();
    return 0;
  }
  flags.parse(args);
  finish_window_options(o, v);
  v.graph_file = o.graph.empty() ? (data_dir() / kDefaultGraph).string() : o.graph;
  editor::Viewer viewer(v);
  return viewer.run();
}

}  // namespace caustica::cli
