#include "viewer/viewer.h"

#include <cstdlib>
#include <thread>

#include "core/interrupt.h"
#include "viewer/viewer_impl.h"

namespace caustica::editor {

const char* const kViewerKeys = R"(keys and mouse:
  left drag   orbit the camera around its target       wheel      move the camera closer or farther
  arrows      move the chosen light (x, z)             PgUp/PgDn  move the light up or down
  L           choose the next light (light 0 first)    P          screenshot (caustica_view_N.png)
  R           reset the camera and the lights
  Tab         hide or show the panels                  C          continuous rendering on or off
  F1          this help on screen                      Esc        quit (as do Ctrl-C and SIGTERM, exit code 0)
)";

Viewer::Impl::Impl(Viewer& owner, const ViewerOptions& o)
    : owner_(owner),
      options_(o),
      window_(o.width, o.height),
      vk_(context_options(o.device)),
      shaders_(shader::process_shader_compiler()),
      executor_(vk_, shaders_, passes::builtin_registry()) {
  inspector_.inspected = o.inspect;
  inspector_.open = inspector_.fit_exposure = !o.inspect.empty();
  executor_.set_frame_timeout(o.frame_timeout_s, o.first_frame_timeout_s);
  VkSurfaceKHR surface = VK_NULL_HANDLE;
  vk::check(glfwCreateWindowSurface(vk_.instance(), window_.handle, nullptr, &surface), "glfwCreateWindowSurface");
  vk_.adopt_surface(surface);
  surface_ = surface;
  VkBool32 supported = VK_FALSE;
  vkGetPhysicalDeviceSurfaceSupportKHR(vk_.physical_device(), vk_.queue_family(), surface, &supported);
  if (!supported) throw DeviceError(vk_.device_name() + " cannot present to this window from its queue");
  build_swapchain(vk_, surface_, window_.handle, swapchain_);
  blit_supported_ = can_blit_to_window(vk_.physical_device(), swapchain_.format);
  std::fprintf(stderr, "view: an 8-bit output at the window's size goes to the window %s\n",
               blit_supported_ ? "by a blit on the device" : "through the host (this device cannot blit it)");
  if (!o.window_shot.empty() && !swapchain_.readable)
    throw DeviceError(vk_.device_name() + ": this window's images cannot be copied out (--window-shot)");
  session_.graph_file = o.graph_file;
  session_.scene_file = o.scene_file;
  set_from_command_line(session_, o.sets);
  reload(true);
  if (!session_.graph) throw InputError(session_.status);
  if (inspector_.inspected != o.inspect)
    throw InputError("--inspect " + o.inspect + ": not an image of " + session_.graph_file + " that a running pass writes");
  home_camera_ = session_.scene->camera;
  for (const scene::Light& light : session_.scene->lights) home_lights_.push_back(light.view.position);
  if (o.moved_light >= home_lights_.size())
    throw InputError(session_.scene_file + ": --light " + std::to_string(o.moved_light) + ": the scene has " +
                     std::to_string(home_lights_.size()) + (home_lights_.size() == 1 ? " light" : " lights") + " (from 0)");
  moved_light_ = o.moved_light;
  window_.capture_events();  // before ImGui's backend, which chains to these callbacks
  init_imgui();
}

Viewer::Impl::~Impl() {
  vk_.wait_idle();
  if (imgui_ready_) {
    ImGui_ImplVulkan_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
  }
}

int Viewer::Impl::run() {
  // Ctrl-C and SIGTERM close the window as its close button does (seen between frames, or by the
  // executor's wait for a frame, which then ends the viewer with 128 + the signal).
  const InterruptPolling polling;
  using clock = std::chrono::steady_clock;
  auto last_check = clock::now(), last_frame = clock::now() - std::chrono::hours(1);
  continuous_ = options_.continuous;
  for (uint32_t frame = 0; !glfwWindowShouldClose(window_.handle) && (options_.frames == 0 || frame < options_.frames);) {
    // Asleep until an event, a file check or the end of a redraw request; the frame cap keeps a
    // continuous or busy viewer from taking every core.
    const bool every_frame = continuous_ || options_.frames != 0;
    if (every_frame || redraw_frames_ > 0) {
      glfwPollEvents();
    } else {
      // Awake when the view comes to rest too: that frame takes the rest setting (ViewBudget).
      glfwWaitEventsTimeout(budget_.rest_pending() ? std::clamp(budget_.rest_in_s(now_s()), 0.001, 0.25) : 0.25);
    }
    if (interrupt_signal() != 0) break;
    if (window_.events.any) redraw_frames_ = std::max(redraw_frames_, kFramesAfterInput);
    if (budget_.rest_pending() && budget_.rest_in_s(now_s()) == 0) redraw_frames_ = std::max(redraw_frames_, 1);
    if (clock::now() - last_check > std::chrono::milliseconds(250)) {
      const bool graph_reloaded = reload(false), shaders_reloaded = reload_shaders();  // both checked every time
      if (graph_reloaded || shaders_reloaded) request_redraw();
      last_check = clock::now();
    }
    if (!every_frame && redraw_frames_ == 0) continue;
    if (options_.max_fps > 0 && options_.frames == 0) {
      const auto next = last_frame + std::chrono::duration_cast<clock::duration>(std::chrono::duration<double>(1.0 / options_.max_fps));
      if (clock::now() < next) std::this_thread::sleep_until(next);
    }
    last_frame = clock::now();
    redraw_frames_ = redraw_frames_ > 0 ? redraw_frames_ - 1 : 0;
    draw_frame(options_.frames != 0 && frame + 1 == options_.frames);
    const double wall_ms = std::chrono::duration<double, std::milli>(clock::now() - last_frame).count();
    const ViewBudget::Setting drawn = budget_.setting();  // end_frame may choose the next frame's level
    if (!options_.stats.empty()) {
      log_.add(wall_ms, last_result_,
               {budget_.moved(), drawn.step.divider, drawn.step.lowered, drawn.still_values, drawn.still_level, budget_.presented()});
    }
    if (budget_.end_frame(measured(wall_ms))) take_still_level(drawn.still_level);
    // A view at rest refines: frames go on while a pass converges (an accumulating mean); between
    // input events they wait for the next, or for the rest.
    if (last_result_.converging && !budget_.rest_pending()) redraw_frames_ = std::max(redraw_frames_, 1);
    if (was_converging_ && !last_result_.converging) {
      std::fprintf(stderr, "view: converged after %llu frames at rest\n",
                   static_cast<unsigned long long>(last_result_.frame.since_reset + 1));
    }
    was_converging_ = last_result_.converging;
    if (owner_.after_frame) owner_.after_frame();
    ++frame;
    ++frames_drawn_;
    if (quit_) break;
  }
  vk_.wait_idle();
  std::fprintf(stderr, "view: %llu frames drawn\n", static_cast<unsigned long long>(frames_drawn_));
  if (!options_.stats.empty()) {
    log_.write(options_.stats);
    std::fprintf(stderr, "view: frame log %s\n", options_.stats.c_str());
  }
  if (vk_.validation_messages() > 0) {
    std::fprintf(stderr, "caustica: %u validation messages (see above)\n", vk_.validation_messages());
    return 3;
  }
  return 0;
}

std::string Viewer::Impl::use_graph(graph::GraphDesc graph) {
  std::optional<graph::GraphDesc> previous = std::move(session_.graph);
  session_.graph = std::move(graph);
  forget_still_values();
  try {
    configure();
  } catch (const std::exception& e) {
    session_.graph = std::move(previous);
    if (session_.graph) configure();
    return e.what();
  }
  request_redraw();
  return "";
}

void Viewer::Impl::set_status(std::string message, bool error) {
  session_.report(std::move(message), error);
  request_redraw();
}

void Viewer::Impl::screenshot_next(std::string path) {
  io::check_image_output(path);
  pending_screenshot_ = std::move(path);
  request_redraw();
}

vk::ContextOptions Viewer::Impl::context_options(vk::ContextOptions options) {
  uint32_t count = 0;
  const char** names = glfwGetRequiredInstanceExtensions(&count);
  if (!names) throw DeviceError("GLFW finds no Vulkan window-system support (is libvulkan's WSI available?)");
  for (uint32_t i = 0; i < count; ++i) options.instance_extensions.emplace_back(names[i]);
  options.presentation = true;
  return options;
}

Viewer::Viewer(const ViewerOptions& options) : impl_(std::make_unique<Impl>(*this, options)) {}
Viewer::~Viewer() = default;
int Viewer::run() {
  try {
    return impl_->run();
  } catch (const FrameTimeout& e) {
    if (on_device_failure) on_device_failure();
    // The device still runs the frame and nothing can stop it: the teardown's waits for it (the
    // window's, the executor's, the device's) would never return, so the viewer ends here, as the
    // command line ends on a device error.
    std::fprintf(stderr, "caustica: device error: %s\n", e.what());
    std::fflush(nullptr);
    std::_Exit(3);
  } catch (const DeviceError&) {
    if (on_device_failure) on_device_failure();
    throw;
  } catch (const Interrupted& e) {
    // A signal while the device ran a frame that has not finished: as above, nothing can wait for it.
    if (on_device_failure) on_device_failure();
    std::fprintf(stderr, "caustica: interrupted (signal %d)\n", e.signal());
    std::fflush(nullptr);
    std::_Exit(128 + e.signal());
  }
}
std::string Viewer::use_graph(graph::GraphDesc graph) {
  return impl_->use_graph(std::move(graph));
}
const graph::Plan& Viewer::plan() const {
  return impl_->plan();
}
void Viewer::set_status(std::string message, bool error) {
  impl_->set_status(std::move(message), error);
}
void Viewer::request_redraw() {
  impl_->request_redraw();
}
void Viewer::close() {
  impl_->close();
}
void Viewer::screenshot_next(std::string path) {
  impl_->screenshot_next(std::move(path));
}

}  // namespace caustica::editor
