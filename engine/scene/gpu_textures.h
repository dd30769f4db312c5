#pragma once
// The scene's textures on the device: one image per Texture with its full mip chain (made on the
// host), a sampler per wrap and filter combination, and the descriptor set (set 1 of every
// pipeline that samples them) that holds them all, its unused slots a white texel.
#include <vector>

#include "common/scene_types.h"
#include "scene/scene.h"
#include "vk/context.h"

namespace caustica::scene {

class GpuTextures {
 public:
  // Throws InputError when the scene has more textures than CAUSTICA_MAX_TEXTURES, DeviceError when
  // the device cannot index them per object (lavapipe and desktop GPU drivers can).
  GpuTextures(vk::Context& vk, const Scene& scene);

  VkDescriptorSet set() const { return set_; }
  uint64_t bytes() const { return bytes_; }  // device memory of the images

 private:
  struct Image {
    vk::OwnedImage image;
    vk::OwnedMemory memory;
    vk::OwnedImageView view;
  };
  Image upload(const Texture& texture);
  VkSampler sampler(const Texture& texture);

  vk::Context& vk_;
  std::vector<Image> images_;
  std::vector<std::pair<uint32_t, vk::OwnedSampler>> samplers_;  // keyed by wrap modes and filter
  vk::OwnedSetLayout layout_;
  vk::OwnedDescriptorPool pool_;
  VkDescriptorSet set_ = VK_NULL_HANDLE;  // freed with the pool
  uint64_t bytes_ = 0;
};

}  // namespace caustica::scene
