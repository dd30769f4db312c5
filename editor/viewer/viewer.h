#pragma once
// caustica view: the graph running in a window (GLFW, a Vulkan swapchain, Dear ImGui), with its
// passes' times, counters and memory, editable parameters, an orbit camera, a movable light, and
// hot reload of the graph, scene and shader files. Each frame the executor renders the graph
// headless as `render` does; its first output goes into the swapchain image (a blit on the device,
// or through the host), and the UI is drawn over it. Nothing is rendered while nothing changes.
// caustica edit (editor/edit/) adds its canvas through the hooks below.
#include <functional>
#include <memory>
#include <string>

#include "graph/executor.h"
#include "graph/graph_desc.h"
#include "viewer/window.h"

namespace caustica::editor {

struct ViewerOptions {
  std::string graph_file, scene_file;
  uint32_t width = 1280, height = 720;
  vk::ContextOptions device;  // window-system extensions are added
  uint32_t frames = 0;        // quit after this many frames; 0: when the window closes
  std::string screenshot, window_shot, inspect;
  bool continuous = false;  // render every frame (for timing) instead of only when something changed
  double max_fps = 60.0;
  bool watch_graph_file = true;  // reload the graph when its file changes (the editor owns it instead)
  bool parameter_panel = true;   // the graph parameters' panel with its save button
  bool stage = true;             // a model file as the scene gets a floor
  std::string stats;             // --stats: every frame's times and passes, written at exit (frame_log.h)
  float orbit_degrees = 0.0f;    // --orbit: turn the camera about its target by this much each frame
  float move_light = 0.0f;       // --move-light: move the chosen light along x by this much each frame
  uint32_t moved_light = 0;      // --light: the light that the arrows and --move-light move (L picks the next)
  // --move-frames FIRST:END: the scripted motion (--orbit, --move-light) on frames FIRST to END-1
  // only, counted from 0, so that a run can rest, move and rest again.
  uint32_t move_first = 0, move_end = UINT32_MAX;
  bool reuse = true;  // skip passes whose dependencies are unchanged (--every-pass: off)
  // --budget: while the camera or a light moves, a frame that took longer than this halves the
  // rendered size (down to a quarter of the window's each way) for the next, and then takes the
  // graph parameters' "while_moving" values; whole again once at rest (--still-after). 0: off.
  double budget_ms = 100.0;
  // --still-after: once nothing has moved for this long, the graph parameters' "while_still" values
  // (where the user has not set them): the progressive graph's exact photons.
  double still_after_ms = 300.0;
  // --frame-timeout: a frame that has not finished after this long (a shader that never ends) ends
  // the viewer with a message naming the pass and exit code 3 (the editor first keeps the unsaved
  // graph: editor/model/recovery_copy.h). A plan's first frame, whose pipelines lavapipe compiles
  // as they first run, gets first_frame_timeout_s (the flag sets both).
  double frame_timeout_s = 5.0, first_frame_timeout_s = 60.0;
  // --set NAME=VALUE: graph parameters as if set in the panel (the while_moving and while_still
  // values leave them alone).
  std::vector<std::string> sets;
};

// What the help and the on-screen help say about the keys.
extern const char* const kViewerKeys;

class Viewer {
 public:
  explicit Viewer(const ViewerOptions& options);
  ~Viewer();
  Viewer(const Viewer&) = delete;
  Viewer& operator=(const Viewer&) = delete;

  // Runs until the window closes, Esc, a termination signal or the frame count; returns the exit
  // code (3 after validation messages).
  int run();

  // ---- for the editor ----
  // Drawn each frame after the viewer's own panels, with the frame's timings and counters.
  std::function<void(const graph::FrameResult&)> extra_ui;
  // Each key press before the viewer sees it; returns true when it was taken.
  std::function<bool(const WindowEvents::Key&)> on_key;
  // Runs `graph` from now on; when it does not compile or set up, keeps the last good one and
  // returns the message (empty on success).
  std::string use_graph(graph::GraphDesc graph);
  const graph::Plan& plan() const;
  void set_status(std::string message, bool error);
  // Draw again soon even without input (an edit, a reload).
  void request_redraw();
  // Writes the graph's output of the next frame drawn to `path` (.png or .exr).
  void screenshot_next(std::string path);
  // Closes the window at the end of this frame, as Esc does.
  void close();
  // Called after each frame is drawn (the editor's script steps on it).
  std::function<void()> after_frame;
  // Called when a frame fails on the device (a DeviceError: the device lost, a frame that does not
  // finish), before the error ends run() (exit 3): the editor keeps the unsaved graph then.
  std::function<void()> on_device_failure;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace caustica::editor
