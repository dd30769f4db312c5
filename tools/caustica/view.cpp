// caustica view: the graph running in a window (GLFW, a Vulkan swapchain, Dear ImGui), with its
// passes' times, counters and memory, editable parameters, an orbit camera, a movable light, and
// hot reload of the graph and scene files. Each frame the executor renders the graph headless as
// `render` does; its first output is read back and copied into the swapchain image, and the UI is
// drawn over it in a render pass (ImGui 1.86's Vulkan backend needs one, not dynamic rendering).
#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>
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
#include "scene/acceleration.h"
#include "scene/gpu_scene.h"
#include "scene/scene.h"
#include "scene_draw.h"
#include "vk/buffer.h"

namespace caustica::cli {
namespace {

const char* kViewHelp = R"(usage: caustica view [--graph FILE] [--scene FILE] [--size WxH] [--frames N] [--screenshot F.png]
                     [--window-shot F.png] [--inspect IMAGE] [--validate] [--device NAME]

Opens a window that runs the graph on the scene (defaults as for render): the compiled passes in
order with their GPU and CPU times over the last frames, the counters, transient memory with and
without aliasing, passes switched off and on where the graph stays valid, the graph's parameters,
editable within their ranges and saved back into the graph
file (only the values change), and a resource inspector: any image of the graph (G-buffer normals,
light-view buffers, the caustic map, the caustic map's levels side by side) in its own panel, or
in place of the output, with an exposure. Saving the graph or the
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
  --screenshot F.png    with --frames: write the last frame's image and quit: the graph's output, or
                        with --inspect the inspected image at full size (.exr: its values as they are)
  --window-shot F.png   with --frames: write the whole window as shown, panels included, and quit
  --inspect IMAGE       open the resource inspector on one of the graph's images
  --validate            Khronos validation; any message makes the command exit 3
)";

// Ctrl-C or a termination request closes the window as its close button does.
std::atomic<bool> g_close_requested{false};
void request_close(int) {
  g_close_requested = true;
}

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
  for (auto it = std::filesystem::recursive_directory_iterator(folder, ec); !ec && it != std::filesystem::recursive_directory_iterator();
       it.increment(ec)) {
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
  bool readable = false;  // the images can be copied out (--window-shot)
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
  // TRANSFER_SRC where offered: --window-shot copies the presented image out.
  info.imageUsage =
      VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT | (caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
  sc.readable = (caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_SRC_BIT) != 0;
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
  std::set<std::string> disabled;            // passes switched off in the panel
  std::string status;                        // the last reload, or the error that kept the old files
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
  Viewer(const RenderOptions& o, uint32_t frames, std::string screenshot, std::string window_shot, std::string inspect)
      : frames_(frames),
        screenshot_(std::move(screenshot)),
        window_shot_(std::move(window_shot)),
        window_(o.width, o.height),
        vk_(context_options(o)),
        shaders_(data_dir() / "shaders"),
        executor_(vk_, shaders_, passes::builtin_registry()) {
    inspected_ = std::move(inspect);
    inspector_open_ = fit_exposure_ = !inspected_.empty();
    VkSurfaceKHR surface = VK_NULL_HANDLE;
    vk::check(glfwCreateWindowSurface(vk_.instance(), window_.handle, nullptr, &surface), "glfwCreateWindowSurface");
    vk_.adopt_surface(surface);
    surface_ = surface;
    VkBool32 supported = VK_FALSE;
    vkGetPhysicalDeviceSurfaceSupportKHR(vk_.physical_device(), vk_.queue_family(), surface, &supported);
    if (!supported) throw DeviceError(vk_.device_name() + " cannot present to this window from its queue");
    build_swapchain(vk_, surface_, window_.handle, swapchain_);
    blit_supported_ = can_blit_output();
    std::fprintf(stderr, "view: an 8-bit output at the window's size goes to the window %s\n",
                 blit_supported_ ? "by a blit on the device" : "through the host (this device cannot blit it)");
    if (!window_shot_.empty() && !swapchain_.readable)
      throw DeviceError(vk_.device_name() + ": this window's images cannot be copied out (--window-shot)");
    session_.graph_file = o.graph;
    session_.scene_file = o.scene;
    const std::string asked = inspected_;
    shader_time_ = newest_shader(data_dir() / "shaders");
    reload(true);
    if (!session_.graph) throw InputError(session_.status);
    if (inspected_ != asked)
      throw InputError("--inspect " + asked + ": not an image of " + session_.graph_file + " that a running pass writes");
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
      moved.camera.position =
          moved.camera.target + distance * glm::vec3(std::cos(pitch) * std::sin(yaw), std::sin(pitch), std::cos(pitch) * std::cos(yaw));
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

  void draw_ui(const graph::FrameResult& frame, const io::ImageData& inspected) {
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
      ImGui::Text("transient: %.1f MiB aliased (lifetime bound %.1f), %.1f MiB unaliased", double(plan.transient_bytes_aliased) / 1048576.0,
                  double(plan.transient_bytes_lifetime_bound) / 1048576.0, double(plan.transient_bytes_unaliased) / 1048576.0);
      ImGui::Text("persistent: %.1f MiB", double(plan.persistent_bytes) / 1048576.0);
      if (const auto* acceleration = executor_.scene() ? executor_.scene()->built_acceleration() : nullptr) {
        ImGui::Text("acceleration structures: %.1f MiB", double(acceleration->bytes()) / 1048576.0);
      }
    }
    if (ImGui::CollapsingHeader("parameters", ImGuiTreeNodeFlags_DefaultOpen)) {
      edit_parameters();
      ImGui::InputText("##save_as", save_as_, sizeof save_as_);
      ImGui::SameLine();
      if (ImGui::Button(save_as_[0] ? "save as" : "save")) save(save_as_[0] ? std::string(save_as_) : session_.graph_file);
    }
    ImGui::Checkbox("resource inspector", &inspector_open_);
    ImGui::End();
    panel_ = {};
    if (inspector_open_) inspector(inspected);
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
      if (on)
        session_.disabled.erase(pass.name);
      else
        session_.disabled.insert(pass.name);
      try {
        configure();
        session_.status = pass.name + (on ? " enabled" : " disabled");
        session_.status_is_error = false;
      } catch (const std::exception& e) {
        if (on)
          session_.disabled.insert(pass.name);
        else
          session_.disabled.erase(pass.name);
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

  // Any image of the graph with an exposure (G-buffer normals, light-view buffers, the caustic map
  // and its levels), fitted into the panel or in place of the output. The panel's image is copied
  // into the window before the UI draws (ImGui 1.86's Vulkan backend samples only its font), so
  // the panel has no background where the image lies and stays behind the other panels.
  void inspector(const io::ImageData& image) {
    const auto& plan = executor_.plan();
    ImGui::SetNextWindowPos(ImVec2(std::max(static_cast<float>(swapchain_.extent.width) - 430.0f, 450.0f), 10.0f), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(420, 360), ImGuiCond_FirstUseEver);
    if (!ImGui::Begin("inspector", &inspector_open_, ImGuiWindowFlags_NoBackground | ImGuiWindowFlags_NoBringToFrontOnFocus)) {
      ImGui::End();  // collapsed: no image to place
      return;
    }
    ImDrawList* draw = ImGui::GetWindowDrawList();
    draw->ChannelsSplit(2);  // 0: the background around the image, 1: the controls over it
    draw->ChannelsSetCurrent(1);
    if (ImGui::BeginCombo("image", inspected_.empty() ? "(choose one)" : inspected_.c_str())) {
      for (const auto& r : plan.resources) {
        if (r.kind == graph::ResourceKind::image && r.used() && ImGui::Selectable(r.name.c_str(), r.name == inspected_))
          select_inspected(r.name);
      }
      ImGui::EndCombo();
    }
    ImGui::SetNextItemWidth(ImGui::GetContentRegionAvail().x * 0.55f);
    ImGui::SliderFloat("exposure (stops)", &exposure_stops_, -32.0f, 32.0f);
    ImGui::SameLine();
    if (ImGui::Button("fit")) expose_to_fit(image);
    ImGui::Checkbox("in the main view", &inspect_in_main_view_);
    if (const int index = plan.find_resource(inspected_); index >= 0) {
      const auto& r = plan.resources[static_cast<size_t>(index)];
      ImGui::Text("%u x %u %s", r.width, r.height, graph::format_info(r.format).name);
    }
    const ImVec2 window_min = ImGui::GetWindowPos(),
                 window_max(window_min.x + ImGui::GetWindowWidth(), window_min.y + ImGui::GetWindowHeight());
    ImVec2 image_min = ImGui::GetCursorScreenPos(), image_max = image_min;
    const ImVec2 room = ImGui::GetContentRegionAvail();
    if (image.width > 0 && room.x >= 1.0f && room.y >= 1.0f) {
      const float fit = std::min(room.x / static_cast<float>(image.width), room.y / static_cast<float>(image.height));
      const ImVec2 size(std::max(1.0f, std::floor(static_cast<float>(image.width) * fit)),
                        std::max(1.0f, std::floor(static_cast<float>(image.height) * fit)));
      image_min = ImVec2(std::floor(image_min.x), std::floor(image_min.y));
      image_max = ImVec2(image_min.x + size.x, image_min.y + size.y);
      ImGui::Dummy(size);
      panel_ = {{static_cast<int32_t>(image_min.x), static_cast<int32_t>(image_min.y)},
                {static_cast<uint32_t>(size.x), static_cast<uint32_t>(size.y)}};
    }
    draw->ChannelsSetCurrent(0);
    draw->PushClipRect(window_min, window_max, false);
    const ImU32 background = ImGui::GetColorU32(ImGuiCol_WindowBg);
    draw->AddRectFilled(ImVec2(window_min.x, window_min.y + ImGui::GetFrameHeight()), ImVec2(window_max.x, image_min.y), background);
    draw->AddRectFilled(ImVec2(window_min.x, image_min.y), ImVec2(image_min.x, image_max.y), background);
    draw->AddRectFilled(ImVec2(image_max.x, image_min.y), ImVec2(window_max.x, image_max.y), background);
    draw->AddRectFilled(ImVec2(window_min.x, image_max.y), window_max, background);
    draw->PopClipRect();
    draw->ChannelsMerge();
    ImGui::End();
  }

  void select_inspected(const std::string& name) {
    inspected_ = name;
    configure();
    fit_exposure_ = true;  // once the first frame with it is read back
  }

  // The exposure that shows the image's brightest texel (any colour channel) at white (0 - x, so
  // that a brightest texel of 1 shows 0 stops, not -0).
  void expose_to_fit(const io::ImageData& image) {
    float brightest = 0.0f;
    for (size_t i = 0; i < image.rgba.size(); ++i) {
      if (i % 4 != 3 && std::isfinite(image.rgba[i])) brightest = std::max(brightest, image.rgba[i]);
    }
    exposure_stops_ = brightest > 0.0f && !image.display_encoded ? std::clamp(0.0f - std::log2(brightest), -32.0f, 32.0f) : 0.0f;
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
    // The output goes into the window on the device (a blit) when it is already display-ready
    // 8-bit at the window's size; otherwise, and for screenshots and the inspector, through a
    // read-back to the host.
    const graph::PlannedResource& out = executor_.plan().resources[executor_.plan().outputs.front()];
    const std::string output = out.name;
    const bool main_inspected = inspect_in_main_view_ && !inspected_.empty();
    const bool blit = blit_supported_ && !main_inspected && out.format == graph::Format::rgba8 && out.width == swapchain_.extent.width &&
                      out.height == swapchain_.extent.height;
    const bool inspecting = !inspected_.empty() && (inspector_open_ || inspect_in_main_view_);
    const bool read_back = !blit || inspecting || screenshot_key_ || (last && !screenshot_.empty());
    const graph::FrameResult frame = executor_.run_frame(read_back);
    const uint32_t compiled = executor_.compile_count();
    const graph::FrameImage output_image = executor_.frame_image(output);
    const io::ImageData image = read_back ? executor_.read_image(output) : io::ImageData{};
    const io::ImageData inspected = read_back && !inspected_.empty() ? executor_.read_image(inspected_) : io::ImageData{};
    if (fit_exposure_ && inspected.width > 0) expose_to_fit(inspected);
    fit_exposure_ = false;
    if (last && !screenshot_.empty()) io::write_image(screenshot_, inspected_.empty() ? image : inspected);
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
    draw_ui(frame, inspected);
    ImGui::Render();
    // An edit in the panels recompiled the graph: the frame's images are gone, show the next one.
    if (blit && executor_.compile_count() != compiled) return;

    uint32_t index = 0;
    VkResult acquired =
        vkAcquireNextImageKHR(vk_.device(), swapchain_.swapchain.get(), UINT64_MAX, acquired_.get(), VK_NULL_HANDLE, &index);
    if (acquired == VK_ERROR_OUT_OF_DATE_KHR) {
      rebuild();
      return;
    }
    if (acquired != VK_SUBOPTIMAL_KHR) vk::check(acquired, "vkAcquireNextImageKHR");
    const float exposure = std::exp2(exposure_stops_);
    const io::ImageData panel =
        panel_.extent.width > 0 && inspected.width > 0 ? fit(inspected, panel_.extent.width, panel_.extent.height) : io::ImageData{};
    upload(blit ? io::ImageData{} : main_inspected ? inspected : image, main_inspected ? exposure : 1.0f, panel, exposure);
    const bool shoot = last && !window_shot_.empty();

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
      record_output_blit(output_image, swapchain_.images[index]);
    } else {
      regions[0].imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
      regions[0].imageExtent = {std::min(uploaded_width_, swapchain_.extent.width), std::min(uploaded_height_, swapchain_.extent.height),
                                1};
      regions[0].bufferRowLength = uploaded_width_;
      vkCmdCopyBufferToImage(cmd_, staging_.get(), swapchain_.images[index], VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &regions[0]);
    }
    if (panel.width > 0 && panel_region(panel, regions[1])) {
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
    if (shoot) record_window_copy(swapchain_.images[index]);
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

  static void encode_bgra(const io::ImageData& image, float scale, uint8_t* out) {
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

  // `image` resampled to width x height: each target texel averages the source texels it covers
  // (the nearest one when enlarging), so a fine caustic is not lost between sampled texels.
  static io::ImageData fit(const io::ImageData& image, uint32_t width, uint32_t height) {
    io::ImageData out;
    out.width = width;
    out.height = height;
    out.display_encoded = image.display_encoded;
    out.rgba.assign(size_t{width} * height * 4, 0.0f);
    auto span = [](uint32_t i, uint32_t to, uint32_t from) {
      const uint32_t first = static_cast<uint32_t>(uint64_t{i} * from / to);
      return std::pair(first, std::max(first + 1, static_cast<uint32_t>(uint64_t{i + 1} * from / to)));
    };
    for (uint32_t y = 0; y < height; ++y) {
      const auto [y0, y1] = span(y, height, image.height);
      for (uint32_t x = 0; x < width; ++x) {
        const auto [x0, x1] = span(x, width, image.width);
        float* target = &out.rgba[(size_t{y} * width + x) * 4];
        for (uint32_t sy = y0; sy < y1; ++sy) {
          for (uint32_t sx = x0; sx < x1; ++sx) {
            for (int c = 0; c < 4; ++c) target[c] += image.rgba[(size_t{sy} * image.width + sx) * 4 + c];
          }
        }
        for (int c = 0; c < 4; ++c) target[c] /= static_cast<float>((y1 - y0) * (x1 - x0));
      }
    }
    return out;
  }

  // The copy of the panel's image (after the main view in the staging buffer) to its place in the
  // window, clipped to the window; false when nothing of it is inside.
  bool panel_region(const io::ImageData& panel, VkBufferImageCopy& region) const {
    const int32_t x0 = std::max(panel_.offset.x, 0), y0 = std::max(panel_.offset.y, 0);
    const int32_t x1 = std::min(panel_.offset.x + static_cast<int32_t>(panel.width), static_cast<int32_t>(swapchain_.extent.width));
    const int32_t y1 = std::min(panel_.offset.y + static_cast<int32_t>(panel.height), static_cast<int32_t>(swapchain_.extent.height));
    if (x1 <= x0 || y1 <= y0) return false;
    region = {};
    region.bufferOffset = VkDeviceSize{uploaded_width_} * uploaded_height_ * 4 +
                          (VkDeviceSize(y0 - panel_.offset.y) * panel.width + VkDeviceSize(x0 - panel_.offset.x)) * 4;
    region.bufferRowLength = panel.width;
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageOffset = {x0, y0, 0};
    region.imageExtent = {static_cast<uint32_t>(x1 - x0), static_cast<uint32_t>(y1 - y0), 1};
    return true;
  }

  // The graph's output into the swapchain image on the device; the blit swaps RGBA into BGRA. The
  // executor's frame finished before this submission (run_frame waits), so the barrier only has
  // to make its writes visible and bring the image into TRANSFER_SRC if it is not there.
  void record_output_blit(const graph::FrameImage& output, VkImage target) {
    passes::image_barrier(cmd_, output.image, VK_IMAGE_ASPECT_COLOR_BIT, output.layout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                          VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_WRITE_BIT, VK_PIPELINE_STAGE_2_BLIT_BIT,
                          VK_ACCESS_2_TRANSFER_READ_BIT);
    VkImageBlit region{};
    region.srcSubresource = region.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.srcOffsets[1] =
        region.dstOffsets[1] = {static_cast<int32_t>(output.extent.width), static_cast<int32_t>(output.extent.height), 1};
    vkCmdBlitImage(cmd_, output.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, target, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region,
                   VK_FILTER_NEAREST);
  }

  // Whether the device blits the graph's 8-bit output into the window's format.
  bool can_blit_output() const {
    VkFormatProperties from{}, to{};
    vkGetPhysicalDeviceFormatProperties(vk_.physical_device(), VK_FORMAT_R8G8B8A8_UNORM, &from);
    vkGetPhysicalDeviceFormatProperties(vk_.physical_device(), swapchain_.format, &to);
    return (from.optimalTilingFeatures & VK_FORMAT_FEATURE_BLIT_SRC_BIT) && (to.optimalTilingFeatures & VK_FORMAT_FEATURE_BLIT_DST_BIT);
  }

  // --window-shot: the presented image, panels included, copied out after the UI is drawn.
  void record_window_copy(VkImage image) {
    const VkDeviceSize bytes = VkDeviceSize{swapchain_.extent.width} * swapchain_.extent.height * 4;
    if (window_readback_.size < bytes) {
      window_readback_ = vk::make_buffer(vk_, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                         VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT, "view window shot",
                                         VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT);
    }
    passes::image_barrier(cmd_, image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                          VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
                          VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {swapchain_.extent.width, swapchain_.extent.height, 1};
    vkCmdCopyImageToBuffer(cmd_, image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, window_readback_.get(), 1, &region);
    passes::image_barrier(cmd_, image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR,
                          VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT, VK_PIPELINE_STAGE_2_NONE, VK_ACCESS_2_NONE);
  }

  void write_window_shot() {
    io::ImageData shot;
    shot.width = swapchain_.extent.width;
    shot.height = swapchain_.extent.height;
    shot.display_encoded = true;
    shot.rgba.resize(size_t{shot.width} * shot.height * 4);
    const auto* bgra = static_cast<const uint8_t*>(window_readback_.mapped);
    for (size_t p = 0; p < size_t{shot.width} * shot.height; ++p) {
      for (int c = 0; c < 3; ++c) shot.rgba[p * 4 + c] = static_cast<float>(bgra[p * 4 + 2 - c]) / 255.0f;
      shot.rgba[p * 4 + 3] = 1.0f;
    }
    io::write_image(window_shot_, shot);
    // Where the inspector's image lies in the shot, for tests and scripts that cut it out.
    if (panel_.extent.width > 0) {
      std::fprintf(stderr, "view: window shot %s; inspector image %s at %d,%d %ux%u\n", window_shot_.c_str(), inspected_.c_str(),
                   panel_.offset.x, panel_.offset.y, panel_.extent.width, panel_.extent.height);
    } else {
      std::fprintf(stderr, "view: window shot %s\n", window_shot_.c_str());
    }
  }

  uint32_t frames_;
  std::string screenshot_, window_shot_;
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
  vk::Buffer staging_, window_readback_;
  std::map<std::string, std::vector<float>> gpu_history_, cpu_history_;
  std::filesystem::file_time_type shader_time_{};
  std::string inspected_;  // empty: nothing chosen
  bool inspector_open_ = false, inspect_in_main_view_ = false, fit_exposure_ = false;
  bool blit_supported_ = false;  // the output can go into the window on the device
  VkRect2D panel_{};             // where the inspector's image goes this frame, in window pixels; empty: nowhere
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
  std::string screenshot, window_shot, inspect;
  o.width = 1280;
  o.height = 720;
  while (!args.done()) {
    std::string a = args.take();
    if (a == "--graph")
      o.graph = args.value(a);
    else if (a == "--scene")
      o.scene = args.value(a);
    else if (a == "--size")
      parse_size(args.value(a), o.width, o.height);
    else if (a == "--frames")
      frames = static_cast<uint32_t>(parse_uint(a, args.value(a), 1, 1000000));
    else if (a == "--screenshot")
      screenshot = args.value(a);
    else if (a == "--window-shot")
      window_shot = args.value(a);
    else if (a == "--inspect")
      inspect = args.value(a);
    else if (a == "--validate")
      o.validate = true;
    else if (a == "--device")
      o.device = args.value(a);
    else
      unknown_option(a,
                     {"--graph", "--scene", "--size", "--frames", "--screenshot", "--window-shot", "--inspect", "--validate", "--device"});
  }
  if (!screenshot.empty() && frames == 0) throw UsageError("--screenshot needs --frames N: the frame it captures");
  if (!window_shot.empty() && frames == 0) throw UsageError("--window-shot needs --frames N: the frame it captures");
  if (!screenshot.empty()) io::check_image_output(screenshot);
  if (!window_shot.empty()) io::check_image_output(window_shot);
  if (o.graph.empty()) o.graph = (data_dir() / kDefaultGraph).string();
  if (o.scene.empty()) o.scene = (data_dir() / kDefaultScene).string();
  Viewer viewer(o, frames, screenshot, window_shot, inspect);
  std::signal(SIGINT, request_close);
  std::signal(SIGTERM, request_close);
  return viewer.run();
}

}  // namespace caustica::cli
