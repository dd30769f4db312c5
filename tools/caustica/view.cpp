// caustica view: the graph running in a window (GLFW, a Vulkan swapchain, Dear ImGui), with its
// passes' times, counters and memory, editable parameters, an orbit camera, a movable light, and
// hot reload of the graph and scene files. Each frame the executor renders the graph headless as
// `render` does; its first output is read back and copied into the swapchain image, and the UI is
// drawn over it in a render pass (ImGui 1.86's Vulkan backend needs one, not dynamic rendering).
#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_vulkan.h>

#include <algorithm>
#include <atomic>
#include <csignal>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <set>

#include "builtin_passes.h"
#include "cli.h"
#include "core/paths.h"
#include "graph/executor.h"
#include "io/image_io.h"
#include "scene/scene.h"
#include "vk/buffer.h"

namespace caustica::cli {
namespace {

const char* kViewHelp = R"(usage: caustica view [--graph FILE] [--scene FILE] [--size WxH] [--frames N] [--screenshot F.png]
                     [--inspect IMAGE] [--validate] [--device NAME]

Opens a window that runs the graph on the scene (defaults as for render): the compiled passes in
order with their GPU and CPU times over the last frames, the counters, transient memory with and
without aliasing, passes switched off and on where the graph stays valid, the graph's parameters,
editable within their ranges and saved back into the graph
file (only the values change), and any image of the graph shown in place of the output with an
exposure (G-buffer normals, light-view buffers, the caustic map). Saving the graph or the
scene file, or a shader, in an editor reloads it within a second; a file that fails to load or
compile leaves the last good one running and shows the error on screen.

keys and mouse:
  left drag   orbit the camera around its target       wheel      move the camera closer or farther
  arrows      move the first light (x, z)              PgUp/PgDn  move the light up or down
  R           reset camera and light                   P          screenshot (caustica_view_N.png)
  F1          this help on screen                      Esc        quit (as do Ctrl-C and SIGTERM, exit code 0)

options:
  --size WxH            window size (default 1280x720)
  --frames N            quit after N frames (default: run until the window is closed)
  --screenshot F.png    with --frames: write the last frame's image (what is shown under the UI) and quit
  --inspect IMAGE       show one of the graph's images instead of its output (the 'inspect' panel)
  --validate            Khronos validation; any message makes the command exit 3
)";

// Ctrl-C or a termination request closes the window as its close button does.
std::atomic<bool> g_close_requested{false};
void request_close(int) { g_close_requested = true; }

std::filesystem::file_time_type modified(const std::string& path) {
  std::error_code ec;
  const auto t = std::filesystem::last_write_time(path, ec);
  return ec ? std::filesystem::file_time_type{} : t;
}

// The newest modification under the shader folder: a saved shader or include changes it.
std::filesystem::file_time_type newest_shader(const std::filesystem::path& folder) {
  // file_time_type's epoch lies in the future on libstdc++: today's times are negative.
  auto newest = std::filesystem::file_time_type::min();
  std::error_code ec;
  for (auto it = std::filesystem::recursive_directory_iterator(folder, ec); !ec && it != std::filesystem::recursive_directory_iterator(); it.increment(ec)) {
    if (it->is_regular_file(ec)) newest = std::max(newest, it->last_write_time(ec));
  }
  return newest;
}

struct Window {
  GLFWwindow* handle = nullptr;
  Window(uint32_t width, uint32_t height) {
    if (!glfwInit()) throw DeviceError("cannot open a window: GLFW found no display (headless? run under xvfb-run)");
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    handle = glfwCreateWindow(static_cast<int>(width), static_cast<int>(height), "caustica", nullptr, nullptr);
    if (!handle) {
      glfwTerminate();
      throw DeviceError("cannot open a window (glfwCreateWindow failed)");
    }
  }
  ~Window() {
    glfwDestroyWindow(handle);
    glfwTerminate();
  }
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;
};

// The swapchain with what draws into it: a render pass that keeps the copied frame and ends in
// PRESENT_SRC, and one framebuffer per image.
struct Swapchain {
  vk::OwnedSwapchain swapchain;
  VkFormat format = VK_FORMAT_B8G8R8A8_UNORM;
  VkExtent2D extent{};
  std::vector<VkImage> images;
  std::vector<vk::OwnedImageView> views;
  std::vector<vk::OwnedFramebuffer> framebuffers;
  vk::OwnedRenderPass render_pass;
};

VkRenderPass make_render_pass(vk::Context& vk, VkFormat format) {
  VkAttachmentDescription color{};
  color.format = format;
  color.samples = VK_SAMPLE_COUNT_1_BIT;
  color.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;  // the frame copied in before the UI
  color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  color.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
  color.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  color.initialLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
  color.finalLayout = VK_IMAGE_LAYOUT_PRESENT_SRC_KHR;
  VkAttachmentReference ref{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
  VkSubpassDescription subpass{};
  subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
  subpass.colorAttachmentCount = 1;
  subpass.pColorAttachments = &ref;
  // The copy into the image happens before the render pass reads and writes it.
  VkSubpassDependency after_copy{};
  after_copy.srcSubpass = VK_SUBPASS_EXTERNAL;
  after_copy.dstSubpass = 0;
  after_copy.srcStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT;
  after_copy.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  after_copy.dstStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
  after_copy.dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
  VkRenderPassCreateInfo info{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
  info.attachmentCount = 1;
  info.pAttachments = &color;
  info.subpassCount = 1;
  info.pSubpasses = &subpass;
  info.dependencyCount = 1;
  info.pDependencies = &after_copy;
  VkRenderPass pass = VK_NULL_HANDLE;
  vk::check(vkCreateRenderPass(vk.device(), &info, nullptr, &pass), "vkCreateRenderPass");
  return pass;
}

void build_swapchain(vk::Context& vk, VkSurfaceKHR surface, GLFWwindow* window, Swapchain& sc) {
  VkSurfaceCapabilitiesKHR caps{};
  vk::check(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(vk.physical_device(), surface, &caps), "vkGetPhysicalDeviceSurfaceCapabilitiesKHR");
  int w = 0, h = 0;
  glfwGetFramebufferSize(window, &w, &h);
  sc.extent = caps.currentExtent.width != UINT32_MAX
                  ? caps.currentExtent
                  : VkExtent2D{std::clamp(static_cast<uint32_t>(w), caps.minImageExtent.width, caps.maxImageExtent.width),
                               std::clamp(static_cast<uint32_t>(h), caps.minImageExtent.height, caps.maxImageExtent.height)};
  uint32_t count = 0;
  vkGetPhysicalDeviceSurfaceFormatsKHR(vk.physical_device(), surface, &count, nullptr);
  std::vector<VkSurfaceFormatKHR> formats(count);
  vkGetPhysicalDeviceSurfaceFormatsKHR(vk.physical_device(), surface, &count, formats.data());
  // The graph's output is already display-encoded (sRGB bytes): a UNORM target keeps it as it is.
  const bool has_bgra = std::any_of(formats.begin(), formats.end(), [](const auto& f) { return f.format == VK_FORMAT_B8G8R8A8_UNORM; });
  if (!has_bgra) throw DeviceError(vk.device_name() + ": the window surface offers no B8G8R8A8_UNORM format");
  VkSwapchainCreateInfoKHR info{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
  info.surface = surface;
  info.minImageCount = std::max(caps.minImageCount, 2u);
  if (caps.maxImageCount > 0) info.minImageCount = std::min(info.minImageCount, caps.maxImageCount);
  info.imageFormat = sc.format;
  info.imageColorSpace = VK_COLOR_SPACE_SRGB_NONLINEAR_KHR;
  info.imageExtent = sc.extent;
  info.imageArrayLayers = 1;
  info.imageUsage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  info.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
  info.preTransform = caps.currentTransform;
  info.compositeAlpha = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
  info.presentMode = VK_PRESENT_MODE_FIFO_KHR;  // always supported
  info.clipped = VK_TRUE;
  info.oldSwapchain = sc.swapchain.get();
  VkSwapchainKHR handle = VK_NULL_HANDLE;
  vk::check(vkCreateSwapchainKHR(vk.device(), &info, nullptr, &handle), "vkCreateSwapchainKHR");
  vk.wait_idle();  // the old swapchain's images may still be in flight
  sc.framebuffers.clear();
  sc.views.clear();
  sc.swapchain = vk::OwnedSwapchain(vk, handle);
  vk::check(vkGetSwapchainImagesKHR(vk.device(), handle, &count, nullptr), "vkGetSwapchainImagesKHR");
  sc.images.resize(count);
  vk::check(vkGetSwapchainImagesKHR(vk.device(), handle, &count, sc.images.data()), "vkGetSwapchainImagesKHR");
  if (!sc.render_pass) sc.render_pass = vk::OwnedRenderPass(vk, make_render_pass(vk, sc.format));
  for (VkImage image : sc.images) {
    VkImageViewCreateInfo view_info{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    view_info.image = image;
    view_info.viewType = VK_IMAGE_VIEW_TYPE_2D;
    view_info.format = sc.format;
    view_info.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    VkImageView view = VK_NULL_HANDLE;
    vk::check(vkCreateImageView(vk.device(), &view_info, nullptr, &view), "vkCreateImageView");
    sc.views.emplace_back(vk, view);
    VkFramebufferCreateInfo fb_info{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
    fb_info.renderPass = sc.render_pass.get();
    fb_info.attachmentCount = 1;
    fb_info.pAttachments = &view;
    fb_info.width = sc.extent.width;
    fb_info.height = sc.extent.height;
    fb_info.layers = 1;
    VkFramebuffer fb = VK_NULL_HANDLE;
    vk::check(vkCreateFramebuffer(vk.device(), &fb_info, nullptr, &fb), "vkCreateFramebuffer");
    sc.framebuffers.emplace_back(vk, fb);
  }
}

// The graph and scene as last loaded successfully, with the user's parameter edits on top.
struct Session {
  std::string graph_file, scene_file;
  std::filesystem::file_time_type graph_time, scene_time;
  std::optional<graph::GraphDesc> graph;  // as loaded, before edits
  std::shared_ptr<const scene::Scene> scene;
  std::map<std::string, std::string> edits;  // parameter -> JSON value
  std::set<std::string> disabled;             // passes switched off in the panel
  std::string status;                         // the last reload, or the error that kept the old files
  bool status_is_error = false;
};

graph::GraphDesc edited(const Session& s) {
  graph::GraphDesc g = *s.graph;
  for (auto& pass : g.passes) {
    if (s.disabled.count(pass.name)) pass.enabled = "0";
  }
  std::vector<std::string> sets;
  for (const auto& [name, value] : s.edits) sets.push_back(name + "=" + value);
  graph::apply_overrides(g, sets);
  return g;
}

class Viewer {
 public:
  Viewer(const RenderOptions& o, uint32_t frames, std::string screenshot, std::string inspect)
      : frames_(frames), screenshot_(std::move(screenshot)), window_(o.width, o.height), vk_(context_options(o)),
        shaders_(data_dir() / "shaders"), executor_(vk_, shaders_, passes::builtin_registry()) {
    inspected_ = std::move(inspect);
    VkSurfaceKHR surface = VK_NULL_HANDLE;
    vk::check(glfwCreateWindowSurface(vk_.instance(), window_.handle, nullptr, &surface), "glfwCreateWindowSurface");
    vk_.adopt_surface(surface);
    surface_ = surface;
    VkBool32 supported = VK_FALSE;
    vkGetPhysicalDeviceSurfaceSupportKHR(vk_.physical_device(), vk_.queue_family(), surface, &supported);
    if (!supported) throw DeviceError(vk_.device_name() + " cannot present to this window from its queue");
    build_swapchain(vk_, surface_, window_.handle, swapchain_);
    session_.graph_file = o.graph;
    session_.scene_file = o.scene;
    const std::string asked = inspected_;
    shader_time_ = newest_shader(data_dir() / "shaders");
    reload(true);
    if (!session_.graph) throw InputError(session_.status);
    if (inspected_ != asked) throw InputError("--inspect " + asked + ": not an image of " + session_.graph_file + " that a running pass writes");
    home_camera_ = session_.scene->camera;
    home_light_ = session_.scene->lights.empty() ? glm::vec3(0.0f) : session_.scene->lights.front().view.position;
    init_imgui();
  }

  ~Viewer() {
    vk_.wait_idle();
    if (imgui_ready_) {
      ImGui_ImplVulkan_Shutdown();
      ImGui_ImplGlfw_Shutdown();
      ImGui::DestroyContext();
    }
  }

  int run() {
    auto last_check = std::chrono::steady_clock::now();
    for (uint32_t frame = 0; !glfwWindowShouldClose(window_.handle) && (frames_ == 0 || frame < frames_); ++frame) {
      glfwPollEvents();
      if (quit_ || g_close_requested) break;
      if (std::chrono::steady_clock::now() - last_check > std::chrono::milliseconds(250)) {
        reload(false);
        reload_shaders();
        last_check = std::chrono::steady_clock::now();
      }
      draw_frame(frames_ != 0 && frame + 1 == frames_);
    }
    vk_.wait_idle();
    if (vk_.validation_messages() > 0) {
      std::fprintf(stderr, "caustica: %u validation messages (see above)\n", vk_.validation_messages());
      return 3;
    }
    return 0;
  }

 private:
  static vk::ContextOptions context_options(const RenderOptions& o) {
    vk::ContextOptions options = device_options(o.device, o.validate);
    uint32_t count = 0;
    const char** names = glfwGetRequiredInstanceExtensions(&count);
    if (!names) throw DeviceError("GLFW finds no Vulkan window-system support (is libvulkan's WSI available?)");
    for (uint32_t i = 0; i < count; ++i) options.instance_extensions.emplace_back(names[i]);
    options.presentation = true;
    return options;
  }

  // Recompiles every pass when a shader changed; a shader that fails to compile leaves the last
  // good pipelines running (the executor keeps its plan when set-up fails).
  void reload_shaders() {
    const auto newest = newest_shader(data_dir() / "shaders");
    if (newest == shader_time_) return;
    shader_time_ = newest;
    try {
      executor_.invalidate();
      configure();
      session_.status = "reloaded shaders";
      session_.status_is_error = false;
    } catch (const std::exception& e) {
      session_.status = e.what();
      session_.status_is_error = true;
    }
    std::fprintf(stderr, "view: %s%s\n", session_.status_is_error ? "kept the last good shaders: " : "", session_.status.c_str());
  }

  // Loads what changed on disk (everything when `first`); a failure keeps the last good version.
  void reload(bool first) {
    const auto graph_time = modified(session_.graph_file), scene_time = modified(session_.scene_file);
    if (!first && graph_time == session_.graph_time && scene_time == session_.scene_time) return;
    try {
      graph::GraphDesc g = graph::load_graph_file(session_.graph_file);
      auto scene = std::make_shared<const scene::Scene>(scene::load_scene_file(session_.scene_file));
      std::optional<graph::GraphDesc> previous = std::move(session_.graph);
      session_.graph = std::move(g);
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
      session_.status = first ? "loaded " + session_.graph_file : "reloaded " + session_.graph_file + " and " + session_.scene_file;
      session_.status_is_error = false;
      std::fprintf(stderr, "view: %s\n", session_.status.c_str());
    } catch (const std::exception& e) {
      session_.status = e.what();
      session_.status_is_error = true;
      std::fprintf(stderr, "view: kept the last good files: %s\n", e.what());
    }
    session_.graph_time = graph_time;
    session_.scene_time = scene_time;
  }

  void configure() {
    std::set<std::string> retained;
    if (!inspected_.empty()) retained.insert(inspected_);
    try {
      executor_.configure(edited(session_), swapchain_.extent.width, swapchain_.extent.height, retained);
    } catch (const InputError&) {
      if (inspected_.empty()) throw;
      inspected_.clear();  // the inspected image left the graph: back to its output
      executor_.configure(edited(session_), swapchain_.extent.width, swapchain_.extent.height);
    }
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

  void handle_input() {
    ImGuiIO& io = ImGui::GetIO();
    if (ImGui::IsKeyPressed(GLFW_KEY_ESCAPE)) quit_ = true;
    if (ImGui::IsKeyPressed(GLFW_KEY_F1)) show_help_ = !show_help_;
    if (io.WantCaptureKeyboard && io.WantCaptureMouse) return;
    scene::Scene moved = *session_.scene;
    bool changed = false;
    if (!io.WantCaptureMouse && (ImGui::IsMouseDragging(ImGuiMouseButton_Left) || io.MouseWheel != 0.0f)) {
      // Orbit: yaw and pitch of the camera's offset from its target, distance by the wheel.
      glm::vec3 offset = moved.camera.position - moved.camera.target;
      const float distance = glm::length(offset) * std::pow(0.9f, io.MouseWheel);
      float yaw = std::atan2(offset.x, offset.z) - io.MouseDelta.x * 0.01f;
      float pitch = std::clamp(std::asin(offset.y / glm::length(offset)) + io.MouseDelta.y * 0.01f, -1.5f, 1.5f);
      moved.camera.position = moved.camera.target + distance * glm::vec3(std::cos(pitch) * std::sin(yaw), std::sin(pitch), std::cos(pitch) * std::cos(yaw));
      changed = true;
    }
    if (!io.WantCaptureKeyboard && !moved.lights.empty()) {
      const float step = 0.05f;
      glm::vec3& light = moved.lights.front().view.position;
      const glm::vec3 before = light;
      if (ImGui::IsKeyDown(GLFW_KEY_LEFT)) light.x -= step;
      if (ImGui::IsKeyDown(GLFW_KEY_RIGHT)) light.x += step;
      if (ImGui::IsKeyDown(GLFW_KEY_UP)) light.z -= step;
      if (ImGui::IsKeyDown(GLFW_KEY_DOWN)) light.z += step;
      if (ImGui::IsKeyDown(GLFW_KEY_PAGE_UP)) light.y += step;
      if (ImGui::IsKeyDown(GLFW_KEY_PAGE_DOWN)) light.y -= step;
      if (ImGui::IsKeyPressed(GLFW_KEY_R)) {
        moved.camera = home_camera_;
        light = home_light_;
        changed = true;
      }
      changed = changed || light != before;
      if (ImGui::IsKeyPressed(GLFW_KEY_P)) screenshot_key_ = true;
    }
    if (changed) {
      session_.scene = std::make_shared<const scene::Scene>(std::move(moved));
      executor_.set_scene(session_.scene);
    }
  }

  void draw_ui(const graph::FrameResult& frame) {
    ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(430, 560), ImGuiCond_FirstUseEver);
    ImGui::Begin(executor_.plan().graph_name.c_str());
    ImGui::TextColored(session_.status_is_error ? ImVec4(1, 0.4f, 0.3f, 1) : ImVec4(0.6f, 0.9f, 0.6f, 1), "%s", session_.status.c_str());
    ImGui::Text("frame: GPU %.2f ms, CPU %.2f ms  (F1: help)", frame.gpu_ms, frame.cpu_ms);
    if (ImGui::CollapsingHeader("passes", ImGuiTreeNodeFlags_DefaultOpen)) {
      // Per pass, the last 120 frames: GPU time (blue bars), CPU recording time (orange bars).
      auto bars = [](std::vector<float>& history, double ms, const std::string& id, ImU32 colour) {
        history.push_back(static_cast<float>(ms));
        if (history.size() > 120) history.erase(history.begin());
        ImGui::PushStyleColor(ImGuiCol_PlotHistogram, colour);
        ImGui::PlotHistogram(id.c_str(), history.data(), static_cast<int>(history.size()), 0, nullptr, 0.0f, FLT_MAX, ImVec2(90, 16));
        ImGui::PopStyleColor();
        ImGui::SameLine();
      };
      for (const auto& p : frame.passes) {
        bars(gpu_history_[p.name], p.gpu_ms, "##gpu" + p.name, IM_COL32(90, 150, 240, 255));
        bars(cpu_history_[p.name], p.cpu_ms, "##cpu" + p.name, IM_COL32(240, 160, 60, 255));
        ImGui::Text("%-18s GPU %7.2f  CPU %5.2f ms", p.name.c_str(), p.gpu_ms, p.cpu_ms);
      }
      for (const auto& culled : executor_.plan().culled) ImGui::TextDisabled("%s (culled)", culled.c_str());
    }
    if (ImGui::CollapsingHeader("enable passes")) toggle_passes();
    if (ImGui::CollapsingHeader("counters")) {
      for (const auto& [name, value] : frame.counters) ImGui::Text("%-28s %.6g", name.c_str(), value);
    }
    if (ImGui::CollapsingHeader("memory")) {
      const auto& plan = executor_.plan();
      ImGui::Text("transient: %.1f MiB aliased, %.1f MiB unaliased", double(plan.transient_bytes_aliased) / 1048576.0,
                  double(plan.transient_bytes_unaliased) / 1048576.0);
      ImGui::Text("persistent: %.1f MiB", double(plan.persistent_bytes) / 1048576.0);
    }
    if (ImGui::CollapsingHeader("parameters", ImGuiTreeNodeFlags_DefaultOpen)) {
      edit_parameters();
      ImGui::InputText("##save_as", save_as_, sizeof save_as_);
      ImGui::SameLine();
      if (ImGui::Button(save_as_[0] ? "save as" : "save")) save(save_as_[0] ? std::string(save_as_) : session_.graph_file);
    }
    if (ImGui::CollapsingHeader("inspect")) inspect();
    ImGui::End();
    if (show_help_) {
      ImGui::SetNextWindowPos(ImVec2(460, 10), ImGuiCond_FirstUseEver);
      ImGui::Begin("help", &show_help_);
      ImGui::TextUnformatted(kViewHelp);
      ImGui::End();
    }
  }

  // A pass switched off stays off only if the graph still compiles without it (its outputs have a
  // fallback or nothing needs them); otherwise it comes back on with the compiler's message.
  void toggle_passes() {
    for (const auto& pass : session_.graph->passes) {
      bool on = !session_.disabled.count(pass.name);
      if (!ImGui::Checkbox(pass.name.c_str(), &on)) continue;
      if (on) session_.disabled.erase(pass.name);
      else session_.disabled.insert(pass.name);
      try {
        configure();
        session_.status = pass.name + (on ? " enabled" : " disabled");
        session_.status_is_error = false;
      } catch (const std::exception& e) {
        if (on) session_.disabled.insert(pass.name);
        else session_.disabled.erase(pass.name);
        configure();
        session_.status = "cannot disable " + pass.name + ": " + e.what();
        session_.status_is_error = true;
      }
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

  // Any image of the graph in place of its output, with an exposure: G-buffer normals, light-view
  // buffers, the caustic map.
  void inspect() {
    const auto& plan = executor_.plan();
    if (ImGui::BeginCombo("image", inspected_.empty() ? "(the graph's output)" : inspected_.c_str())) {
      if (ImGui::Selectable("(the graph's output)", inspected_.empty())) select_inspected("");
      for (const auto& r : plan.resources) {
        if (r.kind == graph::ResourceKind::image && r.used() && ImGui::Selectable(r.name.c_str(), r.name == inspected_)) select_inspected(r.name);
      }
      ImGui::EndCombo();
    }
    ImGui::SliderFloat("exposure (stops)", &exposure_stops_, -16.0f, 16.0f);
  }

  void select_inspected(const std::string& name) {
    inspected_ = name;
    configure();
  }

  void edit_parameters() {
    for (const auto& parameter : session_.graph->parameters) {
      const auto& d = parameter.decl;
      const auto found = session_.edits.find(d.name);
      nlohmann::json value = found != session_.edits.end() ? nlohmann::json::parse(found->second) : parameter.value;
      std::optional<nlohmann::json> next;
      if (d.type == graph::ParamType::bool_) {
        bool v = value.get<bool>();
        if (ImGui::Checkbox(d.name.c_str(), &v)) next = v;
      } else if (d.type == graph::ParamType::int_) {
        int v = value.get<int>();
        if (ImGui::SliderInt(d.name.c_str(), &v, static_cast<int>(d.min.value_or(0)), static_cast<int>(d.max.value_or(1024)))) next = v;
      } else if (d.type == graph::ParamType::float_) {
        float v = value.get<float>();
        if (ImGui::SliderFloat(d.name.c_str(), &v, static_cast<float>(d.min.value_or(0)), static_cast<float>(d.max.value_or(10)))) next = v;
      } else if (d.type == graph::ParamType::choice) {
        const std::string current = value.get<std::string>();
        if (ImGui::BeginCombo(d.name.c_str(), current.c_str())) {
          for (const auto& c : d.choices) {
            if (ImGui::Selectable(c.c_str(), c == current)) next = c;
          }
          ImGui::EndCombo();
        }
      }
      if (ImGui::IsItemHovered() && !d.description.empty()) ImGui::SetTooltip("%s", d.description.c_str());
      if (next) {
        const auto previous = session_.edits;
        session_.edits[d.name] = next->dump();
        try {
          configure();
          session_.status = d.name + " = " + next->dump();
          session_.status_is_error = false;
        } catch (const std::exception& e) {
          session_.edits = previous;
          configure();
          session_.status = e.what();
          session_.status_is_error = true;
        }
      }
    }
  }

  void draw_frame(bool last) {
    handle_input();
    const graph::FrameResult frame = executor_.run_frame(true);
    const std::string output = executor_.plan().resources[executor_.plan().outputs.front()].name;
    const io::ImageData image = executor_.read_image(output);
    const io::ImageData shown = inspected_.empty() ? io::ImageData{} : executor_.read_image(inspected_);
    if (last && !screenshot_.empty()) io::write_image(screenshot_, inspected_.empty() ? image : shown);
    if (screenshot_key_) {
      const std::string name = "caustica_view_" + std::to_string(screenshots_++) + ".png";
      io::write_image(name, image);
      session_.status = "screenshot " + name;
      session_.status_is_error = false;
      screenshot_key_ = false;
    }

    ImGui_ImplVulkan_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    draw_ui(frame);
    ImGui::Render();

    uint32_t index = 0;
    VkResult acquired = vkAcquireNextImageKHR(vk_.device(), swapchain_.swapchain.get(), UINT64_MAX, acquired_.get(), VK_NULL_HANDLE, &index);
    if (acquired == VK_ERROR_OUT_OF_DATE_KHR) {
      rebuild();
      return;
    }
    if (acquired != VK_SUBOPTIMAL_KHR) vk::check(acquired, "vkAcquireNextImageKHR");
    upload(inspected_.empty() ? image : shown, inspected_.empty() ? 1.0f : std::exp2(exposure_stops_));

    vk::check(vkResetCommandBuffer(cmd_, 0), "vkResetCommandBuffer");
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    vk::check(vkBeginCommandBuffer(cmd_, &begin), "vkBeginCommandBuffer");
    VkImageMemoryBarrier to_copy{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
    to_copy.srcAccessMask = 0;
    to_copy.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    to_copy.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    to_copy.newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
    to_copy.srcQueueFamilyIndex = to_copy.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    to_copy.image = swapchain_.images[index];
    to_copy.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    vkCmdPipelineBarrier(cmd_, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, nullptr, 0, nullptr, 1, &to_copy);
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {std::min(uploaded_width_, swapchain_.extent.width), std::min(uploaded_height_, swapchain_.extent.height), 1};
    region.bufferRowLength = uploaded_width_;
    vkCmdCopyBufferToImage(cmd_, staging_.get(), swapchain_.images[index], VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
    VkRenderPassBeginInfo pass{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
    pass.renderPass = swapchain_.render_pass.get();
    pass.framebuffer = swapchain_.framebuffers[index].get();
    pass.renderArea.extent = swapchain_.extent;
    vkCmdBeginRenderPass(cmd_, &pass, VK_SUBPASS_CONTENTS_INLINE);
    ImGui_ImplVulkan_RenderDrawData(ImGui::GetDrawData(), cmd_);
    vkCmdEndRenderPass(cmd_);
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
    if (presented == VK_ERROR_OUT_OF_DATE_KHR || presented == VK_SUBOPTIMAL_KHR || size_changed()) rebuild();
    else vk::check(presented, "vkQueuePresentKHR");
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

  // The frame as BGRA bytes in a host-visible buffer, for the copy into the swapchain image.
  void upload(const io::ImageData& image, float scale) {
    uploaded_width_ = image.width;
    uploaded_height_ = image.height;
    const VkDeviceSize bytes = VkDeviceSize{image.width} * image.height * 4;
    if (staging_.size < bytes) {
      staging_ = vk::make_buffer(vk_, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT,
                                 "view staging", VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT);
    }
    auto* out = static_cast<uint8_t*>(staging_.mapped);
    for (size_t p = 0; p < size_t{image.width} * image.height; ++p) {
      const float* px = &image.rgba[p * 4];
      auto encode = [&](float v) {
        if (!image.display_encoded) v = io::srgb_encode(v * scale);
        return static_cast<uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
      };
      out[p * 4 + 0] = encode(px[2]);
      out[p * 4 + 1] = encode(px[1]);
      out[p * 4 + 2] = encode(px[0]);
      out[p * 4 + 3] = 255;
    }
  }

  uint32_t frames_;
  std::string screenshot_;
  Window window_;
  vk::Context vk_;
  shader::ShaderCompiler shaders_;
  graph::Executor executor_;
  VkSurfaceKHR surface_ = VK_NULL_HANDLE;
  Swapchain swapchain_;
  Session session_;
  scene::View home_camera_;
  glm::vec3 home_light_{0.0f};
  vk::OwnedDescriptorPool imgui_pool_;
  vk::FrameCommands commands_;
  VkCommandBuffer cmd_ = VK_NULL_HANDLE;  // commands_.cmd
  vk::OwnedSemaphore acquired_, rendered_;
  vk::Buffer staging_;
  std::map<std::string, std::vector<float>> gpu_history_, cpu_history_;
  std::filesystem::file_time_type shader_time_{};
  std::string inspected_;  // empty: the graph's output
  float exposure_stops_ = 0.0f;
  uint32_t uploaded_width_ = 0, uploaded_height_ = 0;
  char save_as_[512] = {};
  bool imgui_ready_ = false, show_help_ = false, quit_ = false, screenshot_key_ = false;
  uint32_t screenshots_ = 0;
};

}  // namespace

int cmd_view(Args& args) {
  if (args.wants_help()) {
    std::cout << kViewHelp;
    return 0;
  }
  RenderOptions o;
  uint32_t frames = 0;
  std::string screenshot, inspect;
  o.width = 1280;
  o.height = 720;
  while (!args.done()) {
    std::string a = args.take();
    if (a == "--graph") o.graph = args.value(a);
    else if (a == "--scene") o.scene = args.value(a);
    else if (a == "--size") parse_size(args.value(a), o.width, o.height);
    else if (a == "--frames") frames = static_cast<uint32_t>(parse_uint(a, args.value(a), 1, 1000000));
    else if (a == "--screenshot") screenshot = args.value(a);
    else if (a == "--inspect") inspect = args.value(a);
    else if (a == "--validate") o.validate = true;
    else if (a == "--device") o.device = args.value(a);
    else unknown_option(a, {"--graph", "--scene", "--size", "--frames", "--screenshot", "--inspect", "--validate", "--device"});
  }
  if (!screenshot.empty() && frames == 0) throw UsageError("--screenshot needs --frames N: the frame it captures");
  if (!screenshot.empty()) io::check_image_output(screenshot);
  if (o.graph.empty()) o.graph = (data_dir() / kDefaultGraph).string();
  if (o.scene.empty()) o.scene = (data_dir() / kDefaultScene).string();
  Viewer viewer(o, frames, screenshot, inspect);
  std::signal(SIGINT, request_close);
  std::signal(SIGTERM, request_close);
  return viewer.run();
}

}  // namespace caustica::cli
