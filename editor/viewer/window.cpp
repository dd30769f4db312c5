#include "viewer/window.h"

#include <algorithm>

#include "core/error.h"
#include "scene_draw.h"

namespace caustica::editor {
namespace {

WindowEvents& events_of(GLFWwindow* window) {
  return static_cast<Window*>(glfwGetWindowUserPointer(window))->events;
}

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

}  // namespace

void Window::set_title(const std::string& title) {
  glfwSetWindowTitle(handle, title.c_str());
}

Window::Window(uint32_t width, uint32_t height) {
  if (!glfwInit()) throw DeviceError("cannot open a window: GLFW found no display (headless? run under xvfb-run)");
  glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
  handle = glfwCreateWindow(static_cast<int>(width), static_cast<int>(height), "caustica", nullptr, nullptr);
  if (!handle) {
    glfwTerminate();
    throw DeviceError("cannot open a window (glfwCreateWindow failed)");
  }
}

Window::~Window() {
  glfwDestroyWindow(handle);
  glfwTerminate();
}

void Window::capture_events() {
  // ImGui 1.86's GLFW backend keeps its own state elsewhere: the user pointer is ours.
  glfwSetWindowUserPointer(handle, this);
  glfwSetKeyCallback(handle, [](GLFWwindow* w, int key, int, int action, int mods) {
    WindowEvents& e = events_of(w);
    e.any = true;
    if (action == GLFW_PRESS || action == GLFW_REPEAT) e.pressed.push_back({key, mods});
  });
  glfwSetCharCallback(handle, [](GLFWwindow* w, unsigned) { events_of(w).any = true; });
  glfwSetMouseButtonCallback(handle, [](GLFWwindow* w, int, int, int) {
    WindowEvents& e = events_of(w);
    e.any = true;
    // The last motion event's position, not glfwGetCursorPos: that asks the X server where the
    // pointer is now, which may be past the click already.
    Window& self = *static_cast<Window*>(glfwGetWindowUserPointer(w));
    if (!e.button_moved) {
      e.button_x = self.cursor_x_;
      e.button_y = self.cursor_y_;
    }
    e.button_moved = true;
  });
  glfwSetScrollCallback(handle, [](GLFWwindow* w, double, double) { events_of(w).any = true; });
  glfwSetCursorPosCallback(handle, [](GLFWwindow* w, double x, double y) {
    Window& self = *static_cast<Window*>(glfwGetWindowUserPointer(w));
    self.cursor_x_ = x;
    self.cursor_y_ = y;
    self.events.any = true;
  });
  glfwSetCursorEnterCallback(handle, [](GLFWwindow* w, int) { events_of(w).any = true; });
  glfwSetWindowFocusCallback(handle, [](GLFWwindow* w, int) { events_of(w).any = true; });
  glfwSetFramebufferSizeCallback(handle, [](GLFWwindow* w, int, int) { events_of(w).any = true; });
  glfwSetWindowRefreshCallback(handle, [](GLFWwindow* w) { events_of(w).any = true; });
}

void Window::hold_short_key_taps() {
  imgui_key_ = glfwSetKeyCallback(handle, [](GLFWwindow* w, int key, int scancode, int action, int mods) {
    Window& self = *static_cast<Window*>(glfwGetWindowUserPointer(w));
    auto& pressed = self.pressed_since_frame_;
    if (action == GLFW_PRESS) pressed.push_back(key);
    if (action == GLFW_RELEASE && std::find(pressed.begin(), pressed.end(), key) != pressed.end()) {
      self.held_.push_back({key, scancode, action, mods});
      return;
    }
    if (self.imgui_key_) self.imgui_key_(w, key, scancode, action, mods);
  });
}

void Window::release_held_keys() {
  pressed_since_frame_.clear();
  const std::vector<KeyEvent> held = std::move(held_);
  held_.clear();
  for (const auto& e : held) {
    if (imgui_key_) imgui_key_(handle, e.key, e.scancode, e.action, e.mods);
  }
}

WindowEvents Window::take_events() {
  WindowEvents out = std::move(events);
  events = {};
  return out;
}

bool Window::held(int key) const {
  if (glfwGetKey(handle, key) == GLFW_PRESS) return true;
  return std::any_of(events.pressed.begin(), events.pressed.end(), [&](const WindowEvents::Key& k) { return k.key == key; });
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

bool can_blit_to_window(VkPhysicalDevice device, VkFormat window_format) {
  VkFormatProperties from{}, to{};
  vkGetPhysicalDeviceFormatProperties(device, VK_FORMAT_R8G8B8A8_UNORM, &from);
  vkGetPhysicalDeviceFormatProperties(device, window_format, &to);
  return (from.optimalTilingFeatures & VK_FORMAT_FEATURE_BLIT_SRC_BIT) && (to.optimalTilingFeatures & VK_FORMAT_FEATURE_BLIT_DST_BIT);
}

void record_output_blit(VkCommandBuffer cmd, const graph::FrameImage& output, VkImage target, VkExtent2D target_extent) {
  passes::image_barrier(cmd, output.image, VK_IMAGE_ASPECT_COLOR_BIT, output.layout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                        VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_WRITE_BIT, VK_PIPELINE_STAGE_2_BLIT_BIT,
                        VK_ACCESS_2_TRANSFER_READ_BIT);
  VkImageBlit region{};
  region.srcSubresource = region.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.srcOffsets[1] = {static_cast<int32_t>(output.extent.width), static_cast<int32_t>(output.extent.height), 1};
  region.dstOffsets[1] = {static_cast<int32_t>(target_extent.width), static_cast<int32_t>(target_extent.height), 1};
  // One to one at full size; a frame rendered smaller while moving (the frame budget) is scaled up.
  const bool same = output.extent.width == target_extent.width && output.extent.height == target_extent.height;
  vkCmdBlitImage(cmd, output.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, target, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region,
                 same ? VK_FILTER_NEAREST : VK_FILTER_LINEAR);
  // Back as the frame left it: a plan that reuses passes starts its next frame from there.
  passes::image_barrier(cmd, output.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, output.layout,
                        VK_PIPELINE_STAGE_2_BLIT_BIT, VK_ACCESS_2_NONE, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                        VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT);
}

bool clipped_copy(VkOffset2D place, uint32_t width, uint32_t height, VkExtent2D window, VkDeviceSize buffer_offset,
                  VkBufferImageCopy& region) {
  const int32_t x0 = std::max(place.x, 0), y0 = std::max(place.y, 0);
  const int32_t x1 = std::min(place.x + static_cast<int32_t>(width), static_cast<int32_t>(window.width));
  const int32_t y1 = std::min(place.y + static_cast<int32_t>(height), static_cast<int32_t>(window.height));
  if (x1 <= x0 || y1 <= y0) return false;
  region = {};
  region.bufferOffset = buffer_offset + (VkDeviceSize(y0 - place.y) * width + VkDeviceSize(x0 - place.x)) * 4;
  region.bufferRowLength = width;
  region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.imageOffset = {x0, y0, 0};
  region.imageExtent = {static_cast<uint32_t>(x1 - x0), static_cast<uint32_t>(y1 - y0), 1};
  return true;
}

}  // namespace caustica::editor
