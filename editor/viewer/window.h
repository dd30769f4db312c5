#pragma once
// The viewer's window and swapchain (GLFW and Vulkan's WSI), and the window's input as events, so
// that a key tap shorter than a frame is never lost and the viewer can sleep until something happens.
#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include <string>
#include <vector>

#include "graph/executor.h"
#include "vk/context.h"

namespace caustica::editor {

// What the window saw since the viewer last asked: key presses in order (a press and its release
// within one frame still count), and whether anything at all happened (input, resize, expose).
struct WindowEvents {
  struct Key {
    int key = 0;
    int mods = 0;
  };
  std::vector<Key> pressed;
  bool any = false;
  // Where the cursor was at the first mouse-button press or release since the last frame: ImGui 1.86
  // reads the cursor once a frame, so at a few frames a second a click would land where the mouse
  // has moved to since.
  bool button_moved = false;
  double button_x = 0, button_y = 0;
};

struct Window {
  GLFWwindow* handle = nullptr;
  Window(uint32_t width, uint32_t height);
  ~Window();
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;

  void set_title(const std::string& title);
  // Installs the callbacks that fill events(); call before ImGui's backend, which chains to them.
  void capture_events();
  // The events since the last call, and clears them.
  WindowEvents take_events();
  // Call after ImGui's GLFW backend is installed. ImGui 1.86 reads key state once a frame, so a key
  // pressed and released between two frames would never reach its widgets (Enter in a text field):
  // such a release is held back and let through by release_held_keys(), after the next NewFrame.
  void hold_short_key_taps();
  void release_held_keys();
  // Whether a key is held now, or was pressed since the events were last taken.
  bool held(int key) const;

  WindowEvents events;

 private:
  struct KeyEvent {
    int key, scancode, action, mods;
  };
  GLFWkeyfun imgui_key_ = nullptr;
  double cursor_x_ = 0, cursor_y_ = 0;  // as of the last motion event handled
  std::vector<int> pressed_since_frame_;
  std::vector<KeyEvent> held_;
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

void build_swapchain(vk::Context& vk, VkSurfaceKHR surface, GLFWwindow* window, Swapchain& sc);

// Whether the device blits the graph's 8-bit output into the window's format.
bool can_blit_to_window(VkPhysicalDevice device, VkFormat window_format);
// The graph's output into a swapchain image (in TRANSFER_DST) on the device; the blit swaps RGBA
// into BGRA. The executor's frame finished before this submission (run_frame waits), so the barrier
// only makes its writes visible and brings the image into TRANSFER_SRC.
void record_output_blit(VkCommandBuffer cmd, const graph::FrameImage& output, VkImage target, VkExtent2D target_extent);
// The copy of a width x height image, `buffer_offset` into a staging buffer, to `place` in the
// window, clipped to the window; false when nothing of it is inside.
bool clipped_copy(VkOffset2D place, uint32_t width, uint32_t height, VkExtent2D window, VkDeviceSize buffer_offset,
                  VkBufferImageCopy& region);

}  // namespace caustica::editor
