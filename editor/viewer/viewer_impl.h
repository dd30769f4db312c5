#pragma once
// The viewer's inside (editor/viewer/viewer.h), its member functions in files by job: viewer.cpp
// (set-up and the frame loop), viewer_reload.cpp (the files on disk and the plan),
// viewer_budget.cpp (what the frame budget asks of the plan, editor/model/view_budget.h),
// viewer_panels.cpp (input and the panels), viewer_present.cpp (a frame into the window).
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_vulkan.h>
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "builtin_passes.h"
#include "core/paths.h"
#include "io/image_io.h"
#include "model/view_budget.h"
#include "scene/acceleration.h"
#include "scene/gpu_scene.h"
#include "scene/scene.h"
#include "scene_draw.h"
#include "viewer/frame_log.h"
#include "viewer/frame_panel.h"
#include "viewer/hot_reload.h"
#include "viewer/inspector.h"
#include "viewer/parameter_panel.h"
#include "viewer/screenshot.h"
#include "viewer/viewer.h"
#include "vk/buffer.h"

namespace caustica::editor {

class Viewer::Impl {
 public:
  Impl(Viewer& owner, const ViewerOptions& o);

  ~Impl();

  int run();

  std::string use_graph(graph::GraphDesc graph);
  const graph::Plan& plan() const { return executor_.plan(); }
  void set_status(std::string message, bool error);
  void request_redraw() { redraw_frames_ = std::max(redraw_frames_, kFramesAfterInput); }
  void close() { quit_ = true; }
  void screenshot_next(std::string path);

 private:
  static double now_s() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

  static vk::ContextOptions context_options(vk::ContextOptions options);

  // A saved shader file or include (the engine's or a user pass's) sets up the plan again: the passes
  // set up with it run again with those that read what they write, and the others keep their results.
  // A shader that fails to compile leaves the last good plan running, its error on screen.
  bool reload_shaders();

  // Watches the shader files of the plan now running: new ones from their present time, the others
  // from when they were last seen, so that a save between two plans still counts.
  void watch_shaders();

  // "GRAPH on SCENE": the window's title and the panel's.
  std::string shown_name() const;

  // Loads what changed on disk (everything when `first`); a failure keeps the last good version.
  // Returns whether anything changed on disk.
  bool reload(bool first);

  // `showing_passes_kept`: the new plan differs in what refines only (a still level), so the last
  // whole frame's time still says whether a whole frame fits the budget. `picture_may_stand`: a
  // change of quality values at rest (HandOverOptions::picture_may_stand).
  void configure(bool showing_passes_kept = false, bool picture_may_stand = false);

  // The graph renders at the window's size divided by the frame budget's divider.
  VkExtent2D render_size() const;

  // Asks the budget (editor/model/view_budget.h) what the frame renders at, after input that
  // `moved` the view or not, and makes the plan it asks for. The size goes down only where the output
  // goes to the window by a blit (an 8-bit output, no image inspected in its place), which scales
  // it; the host path copies pixels one to one.
  void fit_frame_budget(bool moved);

  // What the frame just drawn took, for the budget: its times, whether it rendered, and where the
  // plan refines apart, the showing passes' times as they ran (what a display's steps are cut from).
  ViewBudget::Measured measured(double wall_ms) const;

  // At rest, refining frames too slow for the budget take the graph's next while_still values, where it
  // lists cheaper ones (editor::StillLevels). Where the values are sampling-only the mean goes on,
  // and the new plan's showing passes carry over what the plan before's last showed
  // (PlannedPass::showing_key): its first frame refines at once, the picture standing.
  void take_still_level(size_t level_before);

  // A new graph starts with its values as set, and may try its while_still values again, from the
  // first level.
  void forget_still_values();

  void init_imgui();

  // Keys come as events (a tap shorter than a frame still counts); held arrows move the light by
  // the keyboard's own repeat, so the speed does not depend on the frame rate.
  // Returns whether the camera or a light moved.
  bool handle_input(const WindowEvents& events);

  void draw_ui(const graph::FrameResult& frame, const io::ImageData& inspected);

  // Writes the edited values into the graph file (only those values change), or into a new file.
  void save(const std::string& path);

  void select_inspected(const std::string& name);

  void draw_frame(bool last);

  // The screenshots the frame was asked for: --screenshot on the last, the editor's, and P's.
  void write_screenshots(bool last, const io::ImageData& image, const io::ImageData& inspected);

  // Into the window: the graph's output by a blit on the device (`blitted`), or else `main` through
  // the host, the inspector's image in its panel, and the panels drawn over them.
  void present(const graph::FrameImage* blitted, const io::ImageData& main, bool main_inspected, const io::ImageData& inspected, bool last);

  bool size_changed() const;

  void rebuild();

  // The main view, then the inspector panel's image, as BGRA bytes in a host-visible buffer, for
  // the copies into the swapchain image.
  void upload(const io::ImageData& image, float scale, const io::ImageData& panel, float panel_scale);

  void write_window_shot();

  // After input, a few frames more: ImGui settles hover and active states over the next frames.
  static constexpr int kFramesAfterInput = 3;

  Viewer& owner_;
  ViewerOptions options_;
  Window window_;
  vk::Context vk_;
  shader::ShaderCompiler& shaders_;
  graph::Executor executor_;
  VkSurfaceKHR surface_ = VK_NULL_HANDLE;
  Swapchain swapchain_;
  Session session_;
  Inspector inspector_;
  WindowShot window_shot_;
  scene::View home_camera_;
  std::vector<glm::vec3> home_lights_;  // where R puts the lights back
  uint32_t moved_light_ = 0;            // the light the arrows move (L: the next)
  vk::OwnedDescriptorPool imgui_pool_;
  vk::FrameCommands commands_;
  VkCommandBuffer cmd_ = VK_NULL_HANDLE;  // commands_.cmd
  vk::OwnedSemaphore acquired_, rendered_;
  vk::Buffer staging_;
  std::map<std::string, std::vector<float>> gpu_history_;
  std::map<std::filesystem::path, std::filesystem::file_time_type> shader_times_;  // watch_shaders()
  // Shader files saved since the last plan that set its passes up (a reload that failed keeps them).
  std::set<std::filesystem::path> shaders_saved_;
  bool blit_supported_ = false;  // the output can go into the window on the device
  uint32_t uploaded_width_ = 0, uploaded_height_ = 0;
  char save_as_[512] = {};
  bool imgui_ready_ = false, show_help_ = false, quit_ = false;
  int screenshot_keys_ = 0;  // P presses not yet written
  bool panels_hidden_ = false, continuous_ = false;
  int redraw_frames_ = 0;
  uint64_t frames_drawn_ = 0;
  FrameLog log_;
  graph::FrameResult last_result_;
  ViewBudget budget_{options_.budget_ms, options_.still_after_ms, now_s()};  // what each frame renders at
  bool was_converging_ = false;                                              // the last frame had a pass converging
  uint32_t screenshots_ = 0;
  std::string pending_screenshot_;
};

}  // namespace caustica::editor
