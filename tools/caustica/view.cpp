// caustica view and caustica edit: the flags; the viewer and the editor live in editor/.
#include <iostream>

#include "cli.h"
#include "core/paths.h"
#include "io/image_io.h"
#include "viewer/viewer.h"

namespace caustica::cli {
namespace {

const char* kViewHelp = R"(usage: caustica view [--graph FILE] [--scene FILE] [--size WxH] [--frames N] [--screenshot F.png]
                     [--window-shot F.png] [--inspect IMAGE] [--continuous] [--max-fps N]
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

const char* kViewOptions = R"(
options:
  --size WxH            window size (default 1280x720)
  --frames N            quit after N frames (default: run until the window is closed); every frame is rendered
  --screenshot F.png    with --frames: write the last frame's image and quit: the graph's output, or
                        with --inspect the inspected image at full size (.exr: its values as they are)
  --window-shot F.png   with --frames: write the whole window as shown, panels included, and quit
  --inspect IMAGE       open the resource inspector on one of the graph's images
  --continuous          render every frame even when nothing changes (for timing; key C toggles it)
  --max-fps N           frame-rate cap (default 60; 0: none)
  --validate            Khronos validation; any message makes the command exit 3
)";

}  // namespace

int cmd_view(Args& args) {
  if (args.wants_help()) {
    std::cout << kViewHelp << editor::kViewerKeys << kViewOptions;
    return 0;
  }
  RenderOptions o;
  editor::ViewerOptions v;
  while (!args.done()) {
    std::string a = args.take();
    if (a == "--graph")
      o.graph = args.value(a);
    else if (a == "--scene")
      o.scene = args.value(a);
    else if (a == "--size")
      parse_size(args.value(a), v.width, v.height);
    else if (a == "--frames")
      v.frames = static_cast<uint32_t>(parse_uint(a, args.value(a), 1, 1000000));
    else if (a == "--screenshot")
      v.screenshot = args.value(a);
    else if (a == "--window-shot")
      v.window_shot = args.value(a);
    else if (a == "--inspect")
      v.inspect = args.value(a);
    else if (a == "--continuous")
      v.continuous = true;
    else if (a == "--max-fps")
      v.max_fps = parse_number(a, args.value(a), 0, 1000);
    else if (a == "--validate")
      o.validate = true;
    else if (a == "--device")
      o.device = args.value(a);
    else
      unknown_option(a, {"--graph", "--scene", "--size", "--frames", "--screenshot", "--window-shot", "--inspect", "--continuous",
                         "--max-fps", "--validate", "--device"});
  }
  if (!v.screenshot.empty() && v.frames == 0) throw UsageError("--screenshot needs --frames N: the frame it captures");
  if (!v.window_shot.empty() && v.frames == 0) throw UsageError("--window-shot needs --frames N: the frame it captures");
  if (!v.screenshot.empty()) io::check_image_output(v.screenshot);
  if (!v.window_shot.empty()) io::check_image_output(v.window_shot);
  v.graph_file = o.graph.empty() ? (data_dir() / kDefaultGraph).string() : o.graph;
  v.scene_file = o.scene.empty() ? (data_dir() / kDefaultScene).string() : o.scene;
  v.device = device_options(o.device, o.validate);
  editor::Viewer viewer(v);
  editor::close_viewers_on_signals();
  return viewer.run();
}

}  // namespace caustica::cli
