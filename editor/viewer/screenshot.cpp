#include "viewer/screenshot.h"

#include <algorithm>
#include <cmath>

#include "scene_draw.h"

namespace caustica::editor {

void WindowShot::record(vk::Context& vk, VkCommandBuffer cmd, VkImage image, VkExtent2D extent) {
  const VkDeviceSize bytes = VkDeviceSize{extent.width} * extent.height * 4;
  if (readback_.size < bytes) {
    readback_ = vk::make_buffer(vk, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT, "view window shot",
                                VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT);
  }
  passes::image_barrier(cmd, image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                        VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
                        VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
  VkBufferImageCopy region{};
  region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.imageExtent = {extent.width, extent.height, 1};
  vkCmdCopyImageToBuffer(cmd, image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readback_.get(), 1, &region);
  passes::image_barrier(cmd, image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR,
                        VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT, VK_PIPELINE_STAGE_2_NONE, VK_ACCESS_2_NONE);
}

io::ImageData WindowShot::image(VkExtent2D extent) const {
  io::ImageData shot;
  shot.width = extent.width;
  shot.height = extent.height;
  shot.display_encoded = true;
  shot.rgba.resize(size_t{shot.width} * shot.height * 4);
  const auto* bgra = static_cast<const uint8_t*>(readback_.mapped);
  for (size_t p = 0; p < size_t{shot.width} * shot.height; ++p) {
    for (int c = 0; c < 3; ++c) shot.rgba[p * 4 + c] = static_cast<float>(bgra[p * 4 + 2 - c]) / 255.0f;
    shot.rgba[p * 4 + 3] = 1.0f;
  }
  return shot;
}

void encode_bgra(const io::ImageData& image, float scale, uint8_t* out) {
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

}  // namespace caustica::editor
