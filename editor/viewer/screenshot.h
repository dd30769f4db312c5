#pragma once
// Pixels out of the window and into it: the presented image copied back (--window-shot), and images
// encoded as the swapchain's BGRA bytes.
#include <cstdint>

#include "io/image_io.h"
#include "vk/buffer.h"
#include "vk/context.h"

namespace caustica::editor {

class WindowShot {
 public:
  // Records the copy of a presented swapchain image (after the UI is drawn) into a host buffer.
  void record(vk::Context& vk, VkCommandBuffer cmd, VkImage image, VkExtent2D extent);
  // The copied image, once the recorded commands have finished.
  io::ImageData image(VkExtent2D extent) const;

 private:
  vk::Buffer readback_;
};

// `image` times `scale` (unless already display-encoded), sRGB-encoded as BGRA bytes.
void encode_bgra(const io::ImageData& image, float scale, uint8_t* out);

}  // namespace caustica::editor
