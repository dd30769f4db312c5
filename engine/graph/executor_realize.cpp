// A plan made real: its memory blocks and resources, read-back buffers, counters, samplers, command
// buffer and queries, and its passes set up.
#include <cassert>

#include "graph/executor_internal.h"
#include "graph/user_pass_type.h"

namespace caustica::graph {

VkImageCreateInfo image_info(const PlannedResource& r) {
  VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  info.imageType = VK_IMAGE_TYPE_2D;
  info.format = format_info(r.format).vk;
  info.extent = {r.width, r.height, 1};
  info.mipLevels = r.mips;
  info.arrayLayers = r.layers;
  info.samples = VK_SAMPLE_COUNT_1_BIT;
  info.tiling = VK_IMAGE_TILING_OPTIMAL;
  info.usage = r.image_usage;
  info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  return info;
}

VkBufferCreateInfo buffer_info(const PlannedResource& r) {
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = r.buffer_size;
  info.usage = r.buffer_usage;
  return info;
}

void Executor::realize_passes_and_resources() {
  Realized& real = *realized_;
  const Plan& p = *plan_;
  VkDevice device = vk_.device();

  for (size_t b = 0; b < p.blocks.size(); ++b) {
    VkMemoryRequirements req{p.blocks[b].size, p.blocks[b].alignment, p.blocks[b].type_bits};
    real.blocks.push_back(vk_.allocate(req, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, ("transient block " + std::to_string(b)).c_str()));
  }
  real.images.resize(p.resources.size());
  real.buffers.resize(p.resources.size());
  real.dedicated.resize(p.resources.size());
  for (uint32_t i = 0; i < p.resources.size(); ++i) {
    const PlannedResource& res = p.resources[i];
    if (!res.used()) continue;
    VkDeviceMemory memory;
    VkDeviceSize offset;
    if (res.transient) {
      memory = real.blocks[res.block].get();
      offset = res.offset;
    } else {
      real.dedicated[i] = vk_.allocate({res.memory.size, res.memory.alignment, res.memory.type_bits}, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT,
                                       res.name.c_str());
      memory = real.dedicated[i].get();
      offset = 0;
    }
    if (res.kind == ResourceKind::image) {
      VkImageCreateInfo create = image_info(res);
      VkImage image = VK_NULL_HANDLE;
      vk::check(vkCreateImage(device, &create, nullptr, &image), "vkCreateImage");
      real.images[i].image = vk::OwnedImage(vk_, image);
      vk::check(vkBindImageMemory(device, image, memory, offset), "vkBindImageMemory");
      vk_.set_name(VK_OBJECT_TYPE_IMAGE, reinterpret_cast<uint64_t>(image), res.name);
      VkImageViewCreateInfo view_info{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
      view_info.image = image;
      view_info.format = create.format;
      auto make_view = [&](VkImageViewType type, uint32_t first_layer, uint32_t layers) {
        view_info.viewType = type;
        view_info.subresourceRange = {aspect_of(res.format), 0, res.mips, first_layer, layers};
        VkImageView view = VK_NULL_HANDLE;
        vk::check(vkCreateImageView(device, &view_info, nullptr, &view), "vkCreateImageView");
        return vk::OwnedImageView(vk_, view);
      };
      real.images[i].view = make_view(res.layers > 1 ? VK_IMAGE_VIEW_TYPE_2D_ARRAY : VK_IMAGE_VIEW_TYPE_2D, 0, res.layers);
      if (res.layers == 1 && (create.usage & VK_IMAGE_USAGE_SAMPLED_BIT))
        real.images[i].array_view = make_view(VK_IMAGE_VIEW_TYPE_2D_ARRAY, 0, 1);
      if (res.layers > 1 && (create.usage & (VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT))) {
        for (uint32_t layer = 0; layer < res.layers; ++layer)
          real.images[i].layer_views.push_back(make_view(VK_IMAGE_VIEW_TYPE_2D, layer, 1));
      }
    } else {
      VkBufferCreateInfo create = buffer_info(res);
      VkBuffer buffer = VK_NULL_HANDLE;
      vk::check(vkCreateBuffer(device, &create, nullptr, &buffer), "vkCreateBuffer");
      real.buffers[i].buffer = vk::OwnedBuffer(vk_, buffer);
      vk::check(vkBindBufferMemory(device, buffer, memory, offset), "vkBindBufferMemory");
      vk_.set_name(VK_OBJECT_TYPE_BUFFER, reinterpret_cast<uint64_t>(buffer), res.name);
    }
  }

  const VkMemoryPropertyFlags host = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
  for (uint32_t i = 0; i < p.resources.size(); ++i) {
    const PlannedResource& res = p.resources[i];
    if (!res.used() || res.transient) continue;
    Realized::Readback rb;
    rb.resource = i;
    rb.bytes = res.kind == ResourceKind::image ? uint64_t{res.width} * res.height * res.layers * format_info(res.format).bytes_per_texel
                                               : res.buffer_size;
    rb.buffer =
        vk::make_buffer(vk_, rb.bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, host, "readback " + res.name, VK_MEMORY_PROPERTY_HOST_CACHED_BIT);
    real.readbacks.push_back(std::move(rb));
  }
  real.counters =
      vk::make_buffer(vk_, kMaxCounters * sizeof(uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, host,
                      "pass counters", VK_MEMORY_PROPERTY_HOST_CACHED_BIT);
  real.finished = vk::make_buffer(vk_, std::max<size_t>(1, p.passes.size()) * sizeof(uint32_t), VK_BUFFER_USAGE_TRANSFER_DST_BIT, host,
                                  "passes finished", VK_MEMORY_PROPERTY_HOST_CACHED_BIT);

  for (VkFilter filter : {VK_FILTER_LINEAR, VK_FILTER_NEAREST}) {
    VkSamplerCreateInfo info{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    info.magFilter = info.minFilter = filter;
    info.mipmapMode = filter == VK_FILTER_LINEAR ? VK_SAMPLER_MIPMAP_MODE_LINEAR : VK_SAMPLER_MIPMAP_MODE_NEAREST;
    info.addressModeU = info.addressModeV = info.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    info.maxLod = VK_LOD_CLAMP_NONE;
    VkSampler sampler = VK_NULL_HANDLE;
    vk::check(vkCreateSampler(device, &info, nullptr, &sampler), "vkCreateSampler");
    (filter == VK_FILTER_LINEAR ? real.linear : real.nearest) = vk::OwnedSampler(vk_, sampler);
  }

  vk::FrameCommands commands = vk::make_frame_commands(vk_);
  real.pool = std::move(commands.pool);
  real.cmd = commands.cmd;
  real.fence = std::move(commands.fence);
  // Two timestamps per pass plus two for the frame, each followed by a dummy (docs/lavapipe.md: on
  // lavapipe a timestamp after a render pass is only right when another timestamp follows it).
  real.query_count = 2 * (2 * static_cast<uint32_t>(p.passes.size()) + 2);
  VkQueryPoolCreateInfo query_info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
  query_info.queryType = VK_QUERY_TYPE_TIMESTAMP;
  query_info.queryCount = real.query_count;
  VkQueryPool queries = VK_NULL_HANDLE;
  vk::check(vkCreateQueryPool(device, &query_info, nullptr, &queries), "vkCreateQueryPool");
  real.queries = vk::OwnedQueryPool(vk_, queries);

  for (const auto& pass : p.passes) {
    assert(pass.decl && pass.decl->create && "a registered pass type without an implementation");
    real.passes.push_back(pass.decl->create());
    PassSetup setup(*this, pass);
    auto& files = real.shader_files.emplace_back();
    // A user pass's shader was compiled with the plan; a built-in pass compiles its own now.
    if (pass.decl->user_shader) files = pass.decl->user_shader->files;
    shaders_.log_files_to(&files);
    try {
      real.passes.back()->setup(setup);
    } catch (...) {
      shaders_.log_files_to(nullptr);
      throw;
    }
    shaders_.log_files_to(nullptr);
  }
}

}  // namespace caustica::graph
