#include "scene/gpu_textures.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/error.h"
#include "vk/buffer.h"
#include "vk/pipeline.h"

namespace caustica::scene {
namespace {

float linear_to_srgb(float v) {
  return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

// The texture's mip chain, level 0 first, each level the 2x2 box average of the one above (in
// linear light for sRGB colour, so that minified colours keep their brightness).
std::vector<std::vector<uint8_t>> mip_chain(const Texture& texture) {
  std::vector<std::vector<uint8_t>> levels{texture.rgba};
  uint32_t w = texture.width, h = texture.height;
  while (w > 1 || h > 1) {
    const uint32_t nw = std::max(w / 2, 1u), nh = std::max(h / 2, 1u);
    const auto& above = levels.back();
    std::vector<uint8_t> level(size_t{nw} * nh * 4);
    for (uint32_t y = 0; y < nh; ++y) {
      for (uint32_t x = 0; x < nw; ++x) {
        for (uint32_t c = 0; c < 4; ++c) {
          const bool srgb = texture.srgb && c < 3;
          float sum = 0.0f;
          for (uint32_t k = 0; k < 4; ++k) {
            const uint32_t sx = std::min(2 * x + (k & 1), w - 1), sy = std::min(2 * y + (k >> 1), h - 1);
            const uint8_t byte = above[(size_t{sy} * w + sx) * 4 + c];
            sum += srgb ? srgb_byte_to_linear(byte) : static_cast<float>(byte) / 255.0f;
          }
          const float mean = sum / 4.0f;
          level[(size_t{y} * nw + x) * 4 + c] =
              static_cast<uint8_t>(std::lround(std::clamp(srgb ? linear_to_srgb(mean) : mean, 0.0f, 1.0f) * 255.0f));
        }
      }
    }
    levels.push_back(std::move(level));
    w = nw;
    h = nh;
  }
  return levels;
}

VkSamplerAddressMode address_mode(Wrap wrap) {
  switch (wrap) {
    case Wrap::clamp: return VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    case Wrap::mirror: return VK_SAMPLER_ADDRESS_MODE_MIRRORED_REPEAT;
    case Wrap::repeat:
    default: return VK_SAMPLER_ADDRESS_MODE_REPEAT;
  }
}

}  // namespace

GpuTextures::GpuTextures(vk::Context& vk, const Scene& scene) : vk_(vk) {
  if (scene.textures.size() > CAUSTICA_MAX_TEXTURES) {
    throw InputError(scene.path + ": the scene's materials use " + std::to_string(scene.textures.size()) +
                     " textures; caustica binds at most " + std::to_string(CAUSTICA_MAX_TEXTURES));
  }
  // The scene pipelines index the array per object whether or not the scene has textures.
  if (!vk.nonuniform_textures()) {
    throw DeviceError(vk.device_name() +
                      " cannot index textures per object (shaderSampledImageArrayNonUniformIndexing), which the scene "
                      "pipelines need");
  }
  Texture white;
  white.name = "white";
  white.width = white.height = 1;
  white.rgba = {255, 255, 255, 255};
  images_.push_back(upload(white));
  std::vector<VkDescriptorImageInfo> infos(CAUSTICA_MAX_TEXTURES,
                                           {sampler(white), images_[0].view.get(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL});
  for (size_t i = 0; i < scene.textures.size(); ++i) {
    images_.push_back(upload(scene.textures[i]));
    infos[i] = {sampler(scene.textures[i]), images_.back().view.get(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
  }
  layout_ = vk::texture_array_layout(vk, CAUSTICA_MAX_TEXTURES);
  const VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, CAUSTICA_MAX_TEXTURES};
  VkDescriptorPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  pool_info.maxSets = 1;
  pool_info.poolSizeCount = 1;
  pool_info.pPoolSizes = &size;
  VkDescriptorPool pool = VK_NULL_HANDLE;
  vk::check(vkCreateDescriptorPool(vk.device(), &pool_info, nullptr, &pool), "vkCreateDescriptorPool");
  pool_ = vk::OwnedDescriptorPool(vk, pool);
  VkDescriptorSetLayout layout = layout_.get();
  VkDescriptorSetAllocateInfo allocate{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  allocate.descriptorPool = pool;
  allocate.descriptorSetCount = 1;
  allocate.pSetLayouts = &layout;
  vk::check(vkAllocateDescriptorSets(vk.device(), &allocate, &set_), "vkAllocateDescriptorSets");
  VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
  write.dstSet = set_;
  write.descriptorCount = CAUSTICA_MAX_TEXTURES;
  write.descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
  write.pImageInfo = infos.data();
  vkUpdateDescriptorSets(vk.device(), 1, &write, 0, nullptr);
}

GpuTextures::Image GpuTextures::upload(const Texture& texture) {
  const auto levels = mip_chain(texture);
  VkImageCreateInfo create{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  create.imageType = VK_IMAGE_TYPE_2D;
  create.format = texture.srgb ? VK_FORMAT_R8G8B8A8_SRGB : VK_FORMAT_R8G8B8A8_UNORM;
  create.extent = {texture.width, texture.height, 1};
  create.mipLevels = static_cast<uint32_t>(levels.size());
  create.arrayLayers = 1;
  create.samples = VK_SAMPLE_COUNT_1_BIT;
  create.tiling = VK_IMAGE_TILING_OPTIMAL;
  create.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  create.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  Image out;
  VkImage image = VK_NULL_HANDLE;
  vk::check(vkCreateImage(vk_.device(), &create, nullptr, &image), "vkCreateImage");
  out.image = vk::OwnedImage(vk_, image);
  vk_.set_name(VK_OBJECT_TYPE_IMAGE, reinterpret_cast<uint64_t>(image), texture.name);
  VkMemoryRequirements requirements;
  vkGetImageMemoryRequirements(vk_.device(), image, &requirements);
  out.memory = vk_.allocate(requirements, 0, "scene texture");
  vk::check(vkBindImageMemory(vk_.device(), image, out.memory.get(), 0), "vkBindImageMemory");
  bytes_ += requirements.size;

  size_t total = 0;
  for (const auto& level : levels) total += level.size();
  vk::Buffer staging =
      vk::make_buffer(vk_, total, VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                      VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT, texture.name + " staging", 0);
  std::vector<VkBufferImageCopy> copies;
  size_t offset = 0;
  uint32_t w = texture.width, h = texture.height;
  for (uint32_t i = 0; i < levels.size(); ++i) {
    std::memcpy(static_cast<uint8_t*>(staging.mapped) + offset, levels[i].data(), levels[i].size());
    VkBufferImageCopy copy{};
    copy.bufferOffset = offset;
    copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, i, 0, 1};
    copy.imageExtent = {w, h, 1};
    copies.push_back(copy);
    offset += levels[i].size();
    w = std::max(w / 2, 1u);
    h = std::max(h / 2, 1u);
  }
  vk_.submit_and_wait([&](VkCommandBuffer cmd) {
    vk::image_barrier(cmd, image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                      VK_PIPELINE_STAGE_2_NONE, 0, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, create.mipLevels);
    vkCmdCopyBufferToImage(cmd, staging.get(), image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, static_cast<uint32_t>(copies.size()),
                           copies.data());
    vk::image_barrier(cmd, image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                      VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                      VK_ACCESS_2_SHADER_SAMPLED_READ_BIT, create.mipLevels);
  });

  VkImageViewCreateInfo view_info{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
  view_info.image = image;
  view_info.viewType = VK_IMAGE_VIEW_TYPE_2D;
  view_info.format = create.format;
  view_info.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, create.mipLevels, 0, 1};
  VkImageView view = VK_NULL_HANDLE;
  vk::check(vkCreateImageView(vk_.device(), &view_info, nullptr, &view), "vkCreateImageView");
  out.view = vk::OwnedImageView(vk_, view);
  return out;
}

VkSampler GpuTextures::sampler(const Texture& texture) {
  const uint32_t key = static_cast<uint32_t>(texture.wrap_u) * 8 + static_cast<uint32_t>(texture.wrap_v) * 2 + (texture.nearest ? 1 : 0);
  for (const auto& [k, s] : samplers_) {
    if (k == key) return s.get();
  }
  VkSamplerCreateInfo info{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
  info.magFilter = texture.nearest ? VK_FILTER_NEAREST : VK_FILTER_LINEAR;
  info.minFilter = VK_FILTER_LINEAR;  // minified: trilinear, whatever the file's minFilter (docs/gltf.md)
  info.mipmapMode = VK_SAMPLER_MIPMAP_MODE_LINEAR;
  info.addressModeU = address_mode(texture.wrap_u);
  info.addressModeV = address_mode(texture.wrap_v);
  info.addressModeW = VK_SAMPLER_ADDRESS_MODE_REPEAT;
  info.maxLod = VK_LOD_CLAMP_NONE;
  VkSampler sampler = VK_NULL_HANDLE;
  vk::check(vkCreateSampler(vk_.device(), &info, nullptr, &sampler), "vkCreateSampler");
  samplers_.emplace_back(key, vk::OwnedSampler(vk_, sampler));
  return sampler;
}

}  // namespace caustica::scene
