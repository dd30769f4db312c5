#include "viewer/viewer.h"

#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_vulkan.h>
#include <imgui.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <thread>

#include "builtin_passes.h"
#include "core/paths.h"
#include "io/image_io.h"
#include "model/frame_budget.h"
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
#include "vk/buffer.h"

namespace caustica::editor {

const char* const kViewerKeys = R"(keys and mouse:
  left drag   orbit the camera around its target       wheel      move the camera closer or farther
  arrows      move the first light (x, z)              PgUp/PgDn  move the light up or down
  R           reset camera and light                   P          screenshot (caustica_view_N.png)
  Tab         hide or show the panels                  C          continuous rendering on or off
  F1          this help on screen                      Esc        quit (as do Ctrl-C and SIGTERM, exit code 0)
)";

namespace {

std::atomic<bool> g_close_requested{false};
void request_close(int) {
  g_close_requested = true;
}

}  // namespace

void close_viewers_on_signals() {
  std::signal(SIGINT, request_close);
  std::signal(SIGTERM, request_close);
}

class Viewer::Impl {
 public:
  Impl(Viewer& owner, const ViewerOptions& o)
      : owner_(owner),
        options_(o),
        window_(o.width, o.height),
        vk_(context_options(o.device)),
        shaders_(shader::process_shader_compiler()),
        executor_(vk_, shaders_, passes::builtin_registry()) {
    inspector_.inspected = o.inspect;
    inspector_.open = inspector_.fit_exposure = !o.inspect.empty();
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
    home_light_ = session_.scene->lights.empty() ? glm::vec3(0.0f) : session_.scene->lights.front().view.position;
    window_.capture_events();  // before ImGui's backend, which chains to these callbacks
    init_imgui();
  }

  ~Impl() {
    vk_.wait_idle();
    if (imgui_ready_) {
      ImGui_ImplVulkan_Shutdown();
      ImGui_ImplGlfw_Shutdown();
      ImGui::DestroyContext();
    }
  }

  int run() {
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
        glfwWaitEventsTimeout(0.25);
      }
      if (g_close_requested) break;
      if (window_.events.any) redraw_frames_ = std::max(redraw_frames_, kFramesAfterInput);
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
      last_wall_ms_ = std::chrono::duration<double, std::milli>(clock::now() - last_frame).count();
      frame_measured_ = true;
      // A plan's first frame runs every pass and its wall time holds the plan's set-up (pipelines):
      // its GPU time and a frame's usual overhead stand for a whole frame until one is measured, so
      // that a still plan over the budget refines from its second frame, not after another whole one.
      if (last_result_.part == graph::FramePart::whole) {
        last_whole_ms_ = last_result_.frame.index > 0 ? last_wall_ms_ : last_result_.gpu_ms + frame_overhead_ms_;
      }
      if (shows_the_result(last_result_)) {
        last_shown_ = clock::now();
        accumulated_shown_ = last_result_.accumulated;
      }
      // A frame the executor ran whole though asked for a part (a new plan's first) showed
      // everything: a display it began starts again from its first step next time.
      if (last_result_.part == graph::FramePart::whole) display_step_ = 0;
      measure_showing_passes();
      if (!options_.stats.empty()) {
        log_.add(last_wall_ms_, last_result_, {moved_, step_.divider, step_.lowered, still_values_, still_levels_.level(), presented_});
      }
      fit_refining_frames();
      // A still view refines: frames go on while a pass converges (an accumulating mean) or the
      // graph's while_still values wait for the view to rest.
      if (last_result_.converging || still_values_due()) redraw_frames_ = std::max(redraw_frames_, 1);
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

  std::string use_graph(graph::GraphDesc graph) {
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
  const graph::Plan& plan() const { return executor_.plan(); }
  void set_status(std::string message, bool error) {
    session_.report(std::move(message), error);
    request_redraw();
  }
  void request_redraw() { redraw_frames_ = std::max(redraw_frames_, kFramesAfterInput); }
  void close() { quit_ = true; }
  void screenshot_next(std::string path) {
    io::check_image_output(path);
    pending_screenshot_ = std::move(path);
    request_redraw();
  }

 private:
  static vk::ContextOptions context_options(vk::ContextOptions options) {
    uint32_t count = 0;
    const char** names = glfwGetRequiredInstanceExtensions(&count);
    if (!names) throw DeviceError("GLFW finds no Vulkan window-system support (is libvulkan's WSI available?)");
    for (uint32_t i = 0; i < count; ++i) options.instance_extensions.emplace_back(names[i]);
    options.presentation = true;
    return options;
  }

  // A saved shader file or include (the engine's or a user pass's) sets up the plan again: the passes
  // set up with it run again with those that read what they write, and the others keep their results.
  // A shader that fails to compile leaves the last good plan running, its error on screen.
  bool reload_shaders() {
    std::set<std::filesystem::path> edited;
    std::string names;
    for (auto& [file, time] : shader_times_) {
      const auto now = modified(file.string());
      if (now == time) continue;
      time = now;
      edited.insert(file);
      names += (names.empty() ? "" : ", ") + file.filename().string();
    }
    if (edited.empty()) return false;
    try {
      shaders_saved_.insert(edited.begin(), edited.end());
      configure();
      session_.report("reloaded " + names, false);
    } catch (const std::exception& e) {
      session_.report(e.what(), true);
    }
    std::fprintf(stderr, "view: %s%s\n", session_.status_is_error ? "kept the last good shaders: " : "", session_.status.c_str());
    return true;
  }

  // Watches the shader files of the plan now running: new ones from their present time, the others
  // from when they were last seen, so that a save between two plans still counts.
  void watch_shaders() {
    std::map<std::filesystem::path, std::filesystem::file_time_type> watched;
    for (const auto& file : executor_.shader_files()) {
      const auto seen = shader_times_.find(file);
      watched[file] = seen != shader_times_.end() ? seen->second : modified(file.string());
    }
    shader_times_ = std::move(watched);
  }

  // "GRAPH on SCENE": the window's title and the panel's.
  std::string shown_name() const {
    const std::string scene_name =
        session_.scene && !session_.scene->name.empty() ? session_.scene->name : std::filesystem::path(session_.scene_file).stem().string();
    return executor_.plan().graph_name + " on " + scene_name;
  }

  // Loads what changed on disk (everything when `first`); a failure keeps the last good version.
  // Returns whether anything changed on disk.
  bool reload(bool first) {
    const auto graph_time = first || options_.watch_graph_file ? modified(session_.graph_file) : session_.graph_time;
    const auto scene_time = modified(session_.scene_file);
    if (!first && graph_time == session_.graph_time && scene_time == session_.scene_time) return false;
    try {
      graph::GraphDesc g = first || graph_time != session_.graph_time ? graph::load_graph_file(session_.graph_file) : *session_.graph;
      auto scene = std::make_shared<const scene::Scene>(scene::load_scene_file(session_.scene_file, options_.stage));
      std::optional<graph::GraphDesc> previous = std::move(session_.graph);
      session_.graph = std::move(g);
      forget_still_values();
      try {
        executor_.set_scene(scene);
        configure();
      } catch (...) {
        session_.graph = std::move(previous);
        if (session_.scene) executor_.set_scene(session_.scene);
        if (session_.graph) configure();
        throw;
      }
      session_.scene = scene;
      window_.set_title("caustica: " + shown_name());
      session_.status = first ? "loaded " + session_.graph_file : "reloaded " + session_.graph_file + " and " + session_.scene_file;
      session_.status_is_error = false;
      std::fprintf(stderr, "view: %s\n", session_.status.c_str());
      for (const auto& warning : executor_.plan().warnings) {
        session_.report("warning: " + warning, true);
        std::fprintf(stderr, "view: warning: %s\n", warning.c_str());
      }
    } catch (const std::exception& e) {
      session_.status = e.what();
      session_.status_is_error = true;
      // On the first load there is nothing to keep: the caller reports the error and exits.
      if (!first) std::fprintf(stderr, "view: kept the last good files: %s\n", e.what());
    }
    session_.graph_time = graph_time;
    session_.scene_time = scene_time;
    return true;
  }

  // `showing_passes_kept`: the new plan differs in what refines only (a still level), so the last
  // whole frame's time still says whether a whole frame fits the budget. `picture_may_stand`: a
  // change of quality values at rest (HandOverOptions::picture_may_stand).
  void configure(bool showing_passes_kept = false, bool picture_may_stand = false) {
    budget_.new_plan();
    std::set<std::string> retained;
    if (!inspector_.inspected.empty()) retained.insert(inspector_.inspected);
    const VkExtent2D size = render_size();
    graph::GraphDesc graph = edited(session_);
    for (auto& p : graph.parameters) {
      if (step_.lowered && p.while_moving) p.value = *p.while_moving;
      if (still_values_ && !p.while_still.empty() && !session_.edits.count(p.decl.name))
        p.value = p.while_still[std::min(still_levels_.level(), p.while_still.size() - 1)];
    }
    graph::ConfigureOptions configure;
    configure.retained = retained;
    // While only the camera moves, the light's passes keep their last results.
    configure.reuse_unchanged_passes = options_.reuse;
    configure.hand_over.edited_shaders = shaders_saved_;
    configure.hand_over.picture_may_stand = picture_may_stand;
    try {
      executor_.configure(graph, size.width, size.height, configure);
    } catch (const InputError&) {
      if (inspector_.inspected.empty()) throw;
      inspector_.inspected.clear();  // the inspected image left the graph: back to its output
      configure.retained.clear();
      executor_.configure(graph, size.width, size.height, configure);
    }
    shaders_saved_.clear();  // the plan that set them up anew runs
    if (executor_.picture_standing()) {
      // The plan before's picture stands (let_picture_stand): its whole frame stands for this one's
      // (over the budget, frames refine at once; within it, as on a GPU, the next frame shows the
      // new plan whole), a new mean shows once display_due says so, and a display starts from its
      // first step.
      accumulated_shown_ = 0;
      display_step_ = 0;
    } else if (!showing_passes_kept) {
      last_whole_ms_ = 0;
    }
    watch_shaders();
  }

  // The graph renders at the window's size divided by the frame budget's divider.
  VkExtent2D render_size() const {
    return {std::max(1u, swapchain_.extent.width / step_.divider), std::max(1u, swapchain_.extent.height / step_.divider)};
  }

  // Cycles-style (editor/model/frame_budget.h): while something moves, a frame over the budget
  // halves the rendered size for the next (to a quarter each way), blitted up to the window, then
  // takes the graph's while_moving values; a frame well under it goes back a step; the first still
  // frame is whole again. Only where the output goes to the window by a blit (an 8-bit output, no
  // image inspected in its place), which scales it; the host path copies pixels one to one. Once
  // nothing has moved for --still-after, the graph's while_still values. Each change of these is a
  // new plan.
  void fit_frame_budget() {
    const graph::PlannedResource& out = executor_.plan().resources[executor_.plan().outputs.front()];
    const bool can_scale =
        blit_supported_ && out.format == graph::Format::rgba8 && !(inspector_.in_main_view && !inspector_.inspected.empty());
    const bool can_lower = std::any_of(session_.graph->parameters.begin(), session_.graph->parameters.end(),
                                       [](const auto& p) { return p.while_moving.has_value(); });
    // Judged on frames drawn since the last call only (none before the first).
    const editor::FrameBudget::Step step = frame_measured_ ? budget_.next(last_wall_ms_, moved_, can_scale, can_lower) : step_;
    frame_measured_ = false;
    const bool still_values =
        still_values_wanted() && !moved_ &&
        std::chrono::steady_clock::now() - last_move_ >= std::chrono::duration<double, std::milli>(options_.still_after_ms);
    if (step == step_ && still_values == still_values_) return;
    step_ = step;
    still_values_ = still_values;
    // At rest the change is one of quality (the while_still values), not of what the picture shows:
    // the picture stands while the new plan refines, where the sizes let it.
    try {
      configure(false, !moved_);
    } catch (const std::exception& e) {
      if (!still_values_) throw;
      // The device cannot run the graph with them (exact photons without VK_KHR_ray_query): the
      // values as set, until the graph changes.
      still_values_refused_ = true;
      still_values_ = false;
      configure();
      session_.report(std::string("not using the while_still values: ") + e.what(), true);
      std::fprintf(stderr, "view: not using the while_still values: %s\n", e.what());
    }
  }

  // At rest, with a plan that refines apart (an accumulating mean) whose whole frame is over the
  // budget, frames refine the mean and now and then one shows it (editor::display_due), as Cycles' viewport
  // refreshes its picture between samples: the window answers input within a refining frame, and
  // most of the time goes into the mean. A refining frame leaves the window's picture as it was.
  // A display frame shows in steps when its showing passes together would go over the budget
  // (editor::display_steps): step k of n runs the passes of that step, and the picture changes with
  // the last one.
  std::pair<graph::FramePart, graph::DisplayStep> frame_part(bool must_show) {
    if (moved_ || must_show || !executor_.plan().refines_apart || !last_result_.converging || options_.budget_ms <= 0 ||
        last_whole_ms_ <= options_.budget_ms) {
      display_step_ = 0;
      return {graph::FramePart::whole, {}};
    }
    const double since_shown_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - last_shown_).count();
    if (display_step_ == 0 && !editor::display_due(since_shown_s, last_result_.accumulated, accumulated_shown_)) {
      return {graph::FramePart::refine, {}};
    }
    if (display_step_ == 0) display_ends_ = display_steps(showing_ms_, frame_overhead_ms_, options_.budget_ms);
    graph::DisplayStep step{display_step_ == 0 ? 0 : display_ends_[display_step_ - 1], display_ends_[display_step_]};
    display_step_ = display_step_ + 1 == display_ends_.size() ? 0 : display_step_ + 1;
    if (display_step_ == 0) step.last = SIZE_MAX;  // the last step runs whatever is left
    return {graph::FramePart::display, step};
  }

  // The showing passes' GPU times as they last ran, by number among them (graph::DisplayStep), and
  // what the frame cost besides its passes: what the next display frame's steps are cut from.
  void measure_showing_passes() {
    if (!executor_.plan().refines_apart) return;  // PlannedPass::showing numbers nothing else
    const auto& planned = executor_.plan().passes;
    const size_t showing = static_cast<size_t>(std::count_if(planned.begin(), planned.end(), [](const auto& p) { return !p.refines; }));
    if (showing_ms_.size() != showing) showing_ms_.assign(showing, 0.0);
    if (last_result_.passes.size() != planned.size()) return;
    for (size_t i = 0; i < planned.size(); ++i) {
      if (planned[i].refines) continue;
      // A pass that keeps its result while nothing changes (the G-buffer, the shadow map) is skipped
      // by a display, which runs at rest: it costs its barriers alone, whatever it took when it ran.
      if (planned[i].reusable(executor_.plan().reuses_unchanged_passes)) {
        showing_ms_[planned[i].showing] = 0.0;
      } else if (last_result_.passes[i].ran) {
        showing_ms_[planned[i].showing] = last_result_.passes[i].gpu_ms;
      }
    }
    frame_overhead_ms_ = editor::display_overhead(frame_overhead_ms_, last_wall_ms_, last_result_.gpu_ms, presented_);
  }

  // At rest, refining frames too slow for the budget take the graph's next while_still values, where it
  // lists cheaper ones (editor::StillLevels). Where the values are sampling-only the mean goes on,
  // and the new plan's showing passes carry over what the plan before's last showed
  // (PlannedPass::showing_key): its first frame refines at once, the picture standing.
  void fit_refining_frames() {
    const size_t before = still_levels_.level();
    if (!still_values_ || last_result_.part != graph::FramePart::refine ||
        !still_levels_.refined(editor::refining_frame_ms(last_wall_ms_, last_result_.gpu_ms, presented_, frame_overhead_ms_))) {
      return;
    }
    if (still_levels_.level() > before) {
      std::fprintf(stderr,
                   "view: refining frames too slow for the %.0f ms budget (median %.0f ms): the while_still values of level %zu of %zu\n",
                   options_.budget_ms, still_levels_.judged(), still_levels_.level() + 1, still_levels_.levels());
    } else {
      std::fprintf(stderr,
                   "view: refining frames well within the %.0f ms budget again (median %.0f ms, about %.0f ms predicted a level up): "
                   "the while_still values of level %zu of %zu\n",
                   options_.budget_ms, still_levels_.judged(), still_levels_.predicted(), still_levels_.level() + 1, still_levels_.levels());
    }
    configure(true, true);  // a plan whose picture stands still (its showing passes have not run) hands it on
  }

  // The graph declares while_still values that this device has not refused.
  bool still_values_wanted() const {
    return session_.graph && !still_values_refused_ &&
           std::any_of(session_.graph->parameters.begin(), session_.graph->parameters.end(),
                       [](const auto& p) { return !p.while_still.empty(); });
  }
  bool still_values_due() const { return still_values_wanted() && !still_values_; }
  // A new graph starts with its values as set, and may try its while_still values again, from the
  // first level.
  void forget_still_values() {
    still_values_ = false;
    still_values_refused_ = false;
    size_t levels = 1;
    if (session_.graph) {
      for (const auto& p : session_.graph->parameters) levels = std::max(levels, p.while_still.size());
    }
    still_levels_ = editor::StillLevels(options_.budget_ms, levels);
  }

  void init_imgui() {
    VkDescriptorPoolSize sizes[] = {{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 16}};
    VkDescriptorPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    pool_info.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
    pool_info.maxSets = 16;
    pool_info.poolSizeCount = 1;
    pool_info.pPoolSizes = sizes;
    VkDescriptorPool pool = VK_NULL_HANDLE;
    vk::check(vkCreateDescriptorPool(vk_.device(), &pool_info, nullptr, &pool), "vkCreateDescriptorPool");
    imgui_pool_ = vk::OwnedDescriptorPool(vk_, pool);
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini in the user's folder
    ImGui_ImplGlfw_InitForVulkan(window_.handle, true);
    window_.hold_short_key_taps();
    ImGui_ImplVulkan_InitInfo info{};
    info.Instance = vk_.instance();
    info.PhysicalDevice = vk_.physical_device();
    info.Device = vk_.device();
    info.QueueFamily = vk_.queue_family();
    info.Queue = vk_.queue();
    info.DescriptorPool = pool;
    info.MinImageCount = 2;
    info.ImageCount = static_cast<uint32_t>(swapchain_.images.size());
    info.MSAASamples = VK_SAMPLE_COUNT_1_BIT;
    info.CheckVkResultFn = [](VkResult r) { vk::check(r, "ImGui Vulkan backend"); };
    ImGui_ImplVulkan_Init(&info, swapchain_.render_pass.get());
    vk_.submit_and_wait([](VkCommandBuffer cmd) { ImGui_ImplVulkan_CreateFontsTexture(cmd); });
    ImGui_ImplVulkan_DestroyFontUploadObjects();
    imgui_ready_ = true;

    commands_ = vk::make_frame_commands(vk_);
    cmd_ = commands_.cmd;
    acquired_ = vk::make_semaphore(vk_);
    rendered_ = vk::make_semaphore(vk_);
  }

  // Keys come as events (a tap shorter than a frame still counts); held arrows move the light by
  // the keyboard's own repeat, so the speed does not depend on the frame rate.
  void handle_input(const WindowEvents& events) {
    ImGuiIO& io = ImGui::GetIO();
    // What input can move: the camera and the lights, as the executor's scene has them now (a
    // reloaded scene file starts from its own).
    struct {
      scene::View camera;
      std::vector<scene::Light> lights;
    } moved{executor_.scene()->camera(), executor_.scene()->lights()};
    bool changed = false;
    const bool scripted = frames_drawn_ >= options_.move_first && frames_drawn_ < options_.move_end;
    if (scripted && options_.orbit_degrees != 0.0f) {
      moved.camera.orbit(options_.orbit_degrees);
      changed = true;
    }
    if (scripted && options_.move_light != 0.0f && !moved.lights.empty()) {
      moved.lights.front().view.position.x += options_.move_light;
      changed = true;
    }
    if (!io.WantCaptureMouse && (ImGui::IsMouseDragging(ImGuiMouseButton_Left) || io.MouseWheel != 0.0f)) {
      // Orbit: yaw and pitch of the camera's offset from its target, distance by the wheel.
      glm::vec3 offset = moved.camera.position - moved.camera.target;
      const float distance = glm::length(offset) * std::pow(0.9f, io.MouseWheel);
      float yaw = std::atan2(offset.x, offset.z) - io.MouseDelta.x * 0.01f;
      float pitch = std::clamp(std::asin(offset.y / glm::length(offset)) + io.MouseDelta.y * 0.01f, -1.5f, 1.5f);
      moved.camera.position =
          moved.camera.target + distance * glm::vec3(std::cos(pitch) * std::sin(yaw), std::sin(pitch), std::cos(pitch) * std::cos(yaw));
      changed = true;
    }
    for (const auto& key : events.pressed) {
      if (owner_.on_key && owner_.on_key(key)) continue;
      if (key.key == GLFW_KEY_ESCAPE) quit_ = true;
      if (key.key == GLFW_KEY_F1) show_help_ = !show_help_;
      if (io.WantCaptureKeyboard) continue;  // typing into a field
      constexpr float kStep = 0.05f;
      glm::vec3 light_step(0.0f);
      switch (key.key) {
        case GLFW_KEY_TAB: panels_hidden_ = !panels_hidden_; break;
        case GLFW_KEY_C: continuous_ = !continuous_; break;
        case GLFW_KEY_P: ++screenshot_keys_; break;
        case GLFW_KEY_R:
          moved.camera = home_camera_;
          if (!moved.lights.empty()) moved.lights.front().view.position = home_light_;
          changed = true;
          break;
        case GLFW_KEY_LEFT: light_step.x = -kStep; break;
        case GLFW_KEY_RIGHT: light_step.x = kStep; break;
        case GLFW_KEY_UP: light_step.z = -kStep; break;
        case GLFW_KEY_DOWN: light_step.z = kStep; break;
        case GLFW_KEY_PAGE_UP: light_step.y = kStep; break;
        case GLFW_KEY_PAGE_DOWN: light_step.y = -kStep; break;
        default: break;
      }
      if (light_step != glm::vec3(0.0f) && !moved.lights.empty()) {
        moved.lights.front().view.position += light_step;
        changed = true;
      }
    }
    if (changed) {
      last_move_ = std::chrono::steady_clock::now();
      executor_.set_view(moved.camera, std::move(moved.lights));
    }
    moved_ = changed;
  }

  void draw_ui(const graph::FrameResult& frame, const io::ImageData& inspected) {
    inspector_.panel = {};
    if (panels_hidden_) return;
    // Fits 1280x720 beside the picture: the graph's panel on the left, the inspector on the right.
    const float height = std::min(700.0f, static_cast<float>(swapchain_.extent.height) - 20.0f);
    ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(370, height), ImGuiCond_FirstUseEver);
    // The label shows the graph and the scene; the id after ### keeps the panel's place when they change.
    ImGui::Begin((shown_name() + "###caustica").c_str());
    ImGui::PushTextWrapPos(0.0f);
    ImGui::TextColored(session_.status_is_error ? ImVec4(1, 0.4f, 0.3f, 1) : ImVec4(0.6f, 0.9f, 0.6f, 1), "%s", session_.status.c_str());
    ImGui::PopTextWrapPos();
    ImGui::Text("frame: GPU %.2f ms, CPU %.2f ms, %.0f ms in all", frame.gpu_ms, frame.cpu_ms, last_wall_ms_);
    if (step_.divider > 1) {
      ImGui::TextColored(ImVec4(1, 0.8f, 0.4f, 1), "moving: 1/%u of the window's size each way%s (budget %.0f ms)", step_.divider,
                         step_.lowered ? ", the graph's while_moving values" : "", options_.budget_ms);
    }
    if (still_values_ && still_levels_.level() == 0) ImGui::TextColored(ImVec4(0.6f, 0.8f, 1, 1), "still: the graph's while_still values");
    if (still_values_ && still_levels_.level() > 0) {
      ImGui::TextColored(ImVec4(1, 0.8f, 0.4f, 1), "still: the graph's while_still values, level %zu of %zu (moved on refining frames of %.0f ms)",
                         still_levels_.level() + 1, still_levels_.levels(), still_levels_.judged());
    }
    if (frame.accumulated > 0) {
      ImGui::Text("mean of %llu frames%s", static_cast<unsigned long long>(frame.accumulated), frame.converging ? "" : ", converged");
    }
    if (frame.part != graph::FramePart::whole) {
      ImGui::TextColored(ImVec4(0.6f, 0.8f, 1, 1), "still: refining (%llu frames), the picture shown every %.1f to %.1f s%s",
                         static_cast<unsigned long long>(frame.frame.since_reset + 1), editor::kShowAfter, editor::kShowAtMost,
                         display_ends_.size() > 1 ? (" in " + std::to_string(display_ends_.size()) + " frames").c_str() : "");
    }
    ImGui::TextDisabled("F1 help, Tab hide panels");
    ImGui::Checkbox("continuous (C): render every frame, for timing", &continuous_);
    frame_panel(frame, executor_.plan(), gpu_history_);
    auto reconfigure = [this] { configure(); };
    if (ImGui::CollapsingHeader("enable passes")) pass_switches(session_, reconfigure);
    counters_and_memory(frame, executor_.plan(), executor_.scene());
    if (options_.parameter_panel && ImGui::CollapsingHeader("parameters", ImGuiTreeNodeFlags_DefaultOpen)) {
      parameter_panel(session_, reconfigure);
      ImGui::InputText("##save_as", save_as_, sizeof save_as_);
      ImGui::SameLine();
      if (ImGui::Button(save_as_[0] ? "save as" : "save")) save(save_as_[0] ? std::string(save_as_) : session_.graph_file);
    }
    ImGui::Checkbox("resource inspector", &inspector_.open);
    ImGui::End();
    if (inspector_.open) {
      if (auto chosen = inspector_.draw(executor_.plan(), inspected, static_cast<float>(swapchain_.extent.width)))
        select_inspected(*chosen);
    }
    if (owner_.extra_ui) owner_.extra_ui(frame);
    if (show_help_) {
      ImGui::SetNextWindowPos(ImVec2(390, 10), ImGuiCond_FirstUseEver);
      ImGui::Begin("help", &show_help_);
      ImGui::TextUnformatted(kViewerKeys);
      ImGui::End();
    }
  }

  // Writes the edited values into the graph file (only those values change), or into a new file.
  void save(const std::string& path) {
    try {
      io::write_text_atomically(path, graph::graph_text_with_values(edited(session_)));
      session_.status = "saved " + path;
      session_.status_is_error = false;
      if (path == session_.graph_file) session_.edits.clear();  // the file's defaults hold them now
    } catch (const std::exception& e) {
      session_.status = e.what();
      session_.status_is_error = true;
    }
  }

  void select_inspected(const std::string& name) {
    inspector_.inspected = name;
    configure();
    inspector_.fit_exposure = true;
  }

  // Whether a frame just run changed the picture: one that ran whole, or a display's last step
  // (frame_part() has counted the steps on by then).
  bool shows_the_result(const graph::FrameResult& frame) const {
    return frame.part == graph::FramePart::whole || (frame.part == graph::FramePart::display && display_step_ == 0);
  }

  void draw_frame(bool last) {
    const WindowEvents events = window_.take_events();
    handle_input(events);
    fit_frame_budget();
    // The output goes into the window on the device (a blit) when it is already display-ready
    // 8-bit at the window's size; otherwise, and for screenshots and the inspector, through a
    // read-back to the host.
    const graph::PlannedResource& out = executor_.plan().resources[executor_.plan().outputs.front()];
    const std::string output = out.name;
    const bool main_inspected = inspector_.in_main_view && !inspector_.inspected.empty();
    const bool blit = blit_supported_ && !main_inspected && out.format == graph::Format::rgba8 && out.width == render_size().width &&
                      out.height == render_size().height;
    const bool inspecting = !inspector_.inspected.empty() && (inspector_.open || inspector_.in_main_view);
    const bool read_back =
        !blit || inspecting || screenshot_keys_ > 0 || !pending_screenshot_.empty() || (last && !options_.screenshot.empty());
    const bool must_show = last || inspecting || screenshot_keys_ > 0 || !pending_screenshot_.empty();
    const auto [part, step] = frame_part(must_show);
    const graph::FrameResult frame = executor_.run_frame(read_back, {part, step});
    last_result_ = frame;
    const uint32_t compiled = executor_.compile_count();
    const graph::FrameImage output_image = executor_.frame_image(output);
    const io::ImageData image = read_back ? executor_.read_image(output) : io::ImageData{};
    const io::ImageData inspected =
        read_back && !inspector_.inspected.empty() ? executor_.read_image(inspector_.inspected) : io::ImageData{};
    if (inspector_.fit_exposure && inspected.width > 0) inspector_.expose_to_fit(inspected);
    inspector_.fit_exposure = false;
    if (last && !options_.screenshot.empty()) io::write_image(options_.screenshot, inspector_.inspected.empty() ? image : inspected);
    if (!pending_screenshot_.empty()) {
      io::write_image(pending_screenshot_, image);
      std::fprintf(stderr, "view: screenshot %s\n", pending_screenshot_.c_str());
      pending_screenshot_.clear();
    }
    // One file per press, even when several came within one slow frame.
    for (; screenshot_keys_ > 0; --screenshot_keys_) {
      const std::string name = "caustica_view_" + std::to_string(screenshots_++) + ".png";
      io::write_image(name, image);
      session_.report("screenshot " + name, false);
      std::fprintf(stderr, "view: screenshot %s\n", name.c_str());
    }

    const auto now = std::chrono::steady_clock::now();
    presented_ = editor::present_due(shows_the_result(frame) || must_show || last, events.any,
                                     std::chrono::duration<double>(now - last_presented_).count());
    if (!presented_) return;
    last_presented_ = now;
    ImGui_ImplVulkan_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    if (events.button_moved) ImGui::GetIO().MousePos = ImVec2(static_cast<float>(events.button_x), static_cast<float>(events.button_y));
    ImGui::NewFrame();
    window_.release_held_keys();  // this frame saw them pressed; the next sees them released
    draw_ui(frame, inspected);
    ImGui::Render();
    // An edit in the panels recompiled the graph: the frame's images are gone, show the next one.
    if (blit && executor_.compile_count() != compiled) {
      presented_ = false;
      return;
    }

    uint32_t index = 0;
    VkResult acquired =
        vkAcquireNextImageKHR(vk_.device(), swapchain_.swapchain.get(), UINT64_MAX, acquired_.get(), VK_NULL_HANDLE, &index);
    if (acquired == VK_ERROR_OUT_OF_DATE_KHR) {
      rebuild();
      return;
    }
    if (acquired != VK_SUBOPTIMAL_KHR) vk::check(acquired, "vkAcquireNextImageKHR");
    const float exposure = std::exp2(inspector_.exposure_stops);
    const io::ImageData panel = inspector_.panel.extent.width > 0 && inspected.width > 0
                                    ? fit_image(inspected, inspector_.panel.extent.width, inspector_.panel.extent.height)
                                    : io::ImageData{};
    upload(blit ? io::ImageData{} : main_inspected ? inspected : image, main_inspected ? exposure : 1.0f, panel, exposure);
    const bool shoot = last && !options_.window_shot.empty();

    vk::check(vkResetCommandBuffer(cmd_, 0), "vkResetCommandBuffer");
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    vk::check(vkBeginCommandBuffer(cmd_, &begin), "vkBeginCommandBuffer");
    // The wait on the acquire semaphore is at the transfer stage, so the transition waits for it too.
    passes::image_barrier(cmd_, swapchain_.images[index], VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                          VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_NONE,
                          VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
    VkBufferImageCopy regions[2]{};
    if (blit) {
      record_output_blit(cmd_, output_image, swapchain_.images[index], swapchain_.extent);
    } else {
      regions[0].imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
      regions[0].imageExtent = {std::min(uploaded_width_, swapchain_.extent.width), std::min(uploaded_height_, swapchain_.extent.height),
                                1};
      regions[0].bufferRowLength = uploaded_width_;
      vkCmdCopyBufferToImage(cmd_, staging_.get(), swapchain_.images[index], VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &regions[0]);
    }
    if (panel.width > 0 && clipped_copy(inspector_.panel.offset, panel.width, panel.height, swapchain_.extent,
                                        VkDeviceSize{uploaded_width_} * uploaded_height_ * 4, regions[1])) {
      // Regions of one copy land in no set order: the panel goes over the main view in a second.
      passes::memory_barrier(cmd_, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_TRANSFER_BIT,
                             VK_ACCESS_2_TRANSFER_WRITE_BIT);
      vkCmdCopyBufferToImage(cmd_, staging_.get(), swapchain_.images[index], VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &regions[1]);
    }
    VkRenderPassBeginInfo pass{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
    pass.renderPass = swapchain_.render_pass.get();
    pass.framebuffer = swapchain_.framebuffers[index].get();
    pass.renderArea.extent = swapchain_.extent;
    vkCmdBeginRenderPass(cmd_, &pass, VK_SUBPASS_CONTENTS_INLINE);
    ImGui_ImplVulkan_RenderDrawData(ImGui::GetDrawData(), cmd_);
    vkCmdEndRenderPass(cmd_);
    if (shoot) window_shot_.record(vk_, cmd_, swapchain_.images[index], swapchain_.extent);
    vk::check(vkEndCommandBuffer(cmd_), "vkEndCommandBuffer");

    const VkPipelineStageFlags wait_stage = VK_PIPELINE_STAGE_TRANSFER_BIT;
    VkSemaphore wait = acquired_.get(), signal = rendered_.get();
    VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    submit.waitSemaphoreCount = 1;
    submit.pWaitSemaphores = &wait;
    submit.pWaitDstStageMask = &wait_stage;
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &cmd_;
    submit.signalSemaphoreCount = 1;
    submit.pSignalSemaphores = &signal;
    VkFence fence = commands_.fence.get();
    vk::check(vkQueueSubmit(vk_.queue(), 1, &submit, fence), "vkQueueSubmit");
    VkSwapchainKHR sc = swapchain_.swapchain.get();
    VkPresentInfoKHR present{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
    present.waitSemaphoreCount = 1;
    present.pWaitSemaphores = &signal;
    present.swapchainCount = 1;
    present.pSwapchains = &sc;
    present.pImageIndices = &index;
    const VkResult presented = vkQueuePresentKHR(vk_.queue(), &present);
    // One frame in flight: the staging buffer and the semaphores are reused next frame.
    vk::check(vkWaitForFences(vk_.device(), 1, &fence, VK_TRUE, UINT64_MAX), "vkWaitForFences");
    vk::check(vkResetFences(vk_.device(), 1, &fence), "vkResetFences");
    if (shoot) write_window_shot();
    if (presented == VK_ERROR_OUT_OF_DATE_KHR || presented == VK_SUBOPTIMAL_KHR || size_changed())
      rebuild();
    else
      vk::check(presented, "vkQueuePresentKHR");
  }

  bool size_changed() const {
    int w = 0, h = 0;
    glfwGetFramebufferSize(window_.handle, &w, &h);
    return static_cast<uint32_t>(w) != swapchain_.extent.width || static_cast<uint32_t>(h) != swapchain_.extent.height;
  }

  void rebuild() {
    int w = 0, h = 0;
    glfwGetFramebufferSize(window_.handle, &w, &h);
    while ((w == 0 || h == 0) && !glfwWindowShouldClose(window_.handle)) {  // minimised
      glfwWaitEvents();
      glfwGetFramebufferSize(window_.handle, &w, &h);
    }
    build_swapchain(vk_, surface_, window_.handle, swapchain_);
    configure();
  }

  // The main view, then the inspector panel's image, as BGRA bytes in a host-visible buffer, for
  // the copies into the swapchain image.
  void upload(const io::ImageData& image, float scale, const io::ImageData& panel, float panel_scale) {
    uploaded_width_ = image.width;
    uploaded_height_ = image.height;
    const VkDeviceSize main_bytes = VkDeviceSize{image.width} * image.height * 4;
    const VkDeviceSize bytes = main_bytes + VkDeviceSize{panel.width} * panel.height * 4;
    if (staging_.size < bytes) {
      staging_ = vk::make_buffer(vk_, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                 VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT, "view staging",
                                 VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT);
    }
    auto* out = static_cast<uint8_t*>(staging_.mapped);
    encode_bgra(image, scale, out);
    encode_bgra(panel, panel_scale, out + main_bytes);
  }

  void write_window_shot() {
    io::write_image(options_.window_shot, window_shot_.image(swapchain_.extent));
    // Where the inspector's image lies in the shot, for tests and scripts that cut it out.
    const VkRect2D& panel = inspector_.panel;
    if (panel.extent.width > 0) {
      std::fprintf(stderr, "view: window shot %s; inspector image %s at %d,%d %ux%u\n", options_.window_shot.c_str(),
                   inspector_.inspected.c_str(), panel.offset.x, panel.offset.y, panel.extent.width, panel.extent.height);
    } else {
      std::fprintf(stderr, "view: window shot %s\n", options_.window_shot.c_str());
    }
  }

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
  glm::vec3 home_light_{0.0f};
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
  bool moved_ = false;                 // the camera or a light changed before the last frame
  double last_wall_ms_ = 0;            // the last frame's, input to present
  double last_whole_ms_ = 0;           // the last frame's of this plan that ran whole (graph::FramePart); its first's estimated
  std::chrono::steady_clock::time_point last_presented_;  // the last frame that went to the window
  bool presented_ = false;                                // the last frame went to the window
  std::chrono::steady_clock::time_point last_shown_;  // the last frame that showed the graph's result
  uint64_t accumulated_shown_ = 0;                    // the frames in the running mean it showed
  std::vector<double> showing_ms_;                    // measure_showing_passes()
  double frame_overhead_ms_ = 0;
  std::vector<size_t> display_ends_;   // the steps of the display under way (editor::display_steps)
  size_t display_step_ = 0;            // its next step; 0: none under way
  bool frame_measured_ = false;        // since the frame budget last judged
  editor::FrameBudget budget_{options_.budget_ms};  // what the frames render at while moving
  editor::FrameBudget::Step step_;                  // the step the plan was made for
  bool still_values_ = false;          // at rest, with the parameters' while_still values
  editor::StillLevels still_levels_{options_.budget_ms, 1};  // which of them, where a parameter lists several
  bool was_converging_ = false;        // the last frame had a pass converging
  bool still_values_refused_ = false;  // the device could not run them (until the graph changes)
  std::chrono::steady_clock::time_point last_move_ = std::chrono::steady_clock::now();
  uint32_t screenshots_ = 0;
  std::string pending_screenshot_;
};

Viewer::Viewer(const ViewerOptions& options) : impl_(std::make_unique<Impl>(*this, options)) {}
Viewer::~Viewer() = default;
int Viewer::run() {
  return impl_->run();
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
