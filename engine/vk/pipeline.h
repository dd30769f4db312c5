#pragma once
// Pipelines with one push-descriptor set: passes push their bindings each frame and need no pools.
// A pipeline that samples the scene's textures also has set 1, an array of them that the scene
// writes once (vk::texture_array_layout).
#include <cstddef>
#include <memory>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include "shader/shader_interface.h"
#include "vk/context.h"

namespace caustica::vk {

struct PipelineDesc {
  std::string name;
  std::vector<VkDescriptorType> bindings;  // binding i has type bindings[i]; VK_DESCRIPTOR_TYPE_MAX_ENUM: none
  std::vector<uint32_t> counts;            // and counts[i] descriptors (an array), where given; else 1
  uint32_t push_constant_bytes = 0;
  uint32_t texture_array = 0;  // > 0: set 1 is an array of this many combined image samplers
  // Where the shaders' declarations give the layout (reflected_desc): the pipeline's descriptors are
  // then written by name and checked against them (DescriptorWriter).
  std::shared_ptr<const shader::ShaderInterface> interface;
};

// The layout `interface` declares: set 0's bindings, set 1 where a shader samples the scene's
// textures (shaders/scene/textures.glsl), the push-constant block's size.
PipelineDesc reflected_desc(std::string name, std::shared_ptr<const shader::ShaderInterface> interface);
// The same with the interface of `shaders` (a pipeline's stages), its messages naming pass `pass`.
PipelineDesc reflected_desc(std::string name, std::string pass, const std::vector<shader::NamedReflection>& shaders);

// Copies share their objects: the process keeps the pipelines it made (PipelineCache) and hands
// the same ones to every pass that asks for an identical pipeline.
struct Pipeline {
  Shared<OwnedSetLayout> set_layout;
  Shared<OwnedSetLayout> texture_set_layout;  // when PipelineDesc::texture_array
  Shared<OwnedPipelineLayout> layout;
  Shared<OwnedPipeline> pipeline;
  VkPipelineBindPoint bind_point = VK_PIPELINE_BIND_POINT_COMPUTE;
  VkShaderStageFlags stages = 0;
  std::shared_ptr<const shader::ShaderInterface> interface;  // PipelineDesc::interface
};

// The pipelines a Context has made, by everything that defines them (kind, layout, SPIR-V, fixed
// state, name). An executor that compiles a graph again (another scene or size, an edit elsewhere
// in the graph, the test matrix) gets its unchanged pipelines back instead of having the driver
// compile them again: lavapipe compiles each with LLVM, most of a graph's set-up time. Pipelines no
// pass holds any more are let go once the cache passes kKeep entries.
class PipelineCache {
 public:
  const Pipeline* find(const std::string& key) const;
  const Pipeline& insert(const std::string& key, Pipeline pipeline);

 private:
  static constexpr size_t kKeep = 256;
  std::unordered_map<std::string, Pipeline> pipelines_;
};

// Fixed-function state of a graphics pipeline drawn with dynamic rendering; viewport and scissor
// are dynamic. Vertices are pulled from storage buffers, so there is no vertex input state.
struct RasterState {
  std::vector<VkFormat> color_formats;
  VkFormat depth_format = VK_FORMAT_UNDEFINED;  // no depth test without one
  bool depth_write = true;
  VkCompareOp depth_compare = VK_COMPARE_OP_LESS;
  VkCullModeFlags cull = VK_CULL_MODE_NONE;  // counter-clockwise triangles face the viewer
};

// Set 1 of a pipeline with a texture array: `count` combined image samplers, every stage, every
// one written. Layouts made by this function with one count are compatible with each other.
OwnedSetLayout texture_array_layout(Context& vk, uint32_t count);

Pipeline make_compute_pipeline(Context& vk, const PipelineDesc& desc, const std::vector<uint32_t>& spirv);
// A full-screen triangle drawn with dynamic rendering into `color_formats`.
Pipeline make_fullscreen_pipeline(Context& vk, const PipelineDesc& desc, const std::vector<uint32_t>& vertex_spirv,
                                  const std::vector<uint32_t>& fragment_spirv, const std::vector<VkFormat>& color_formats);
Pipeline make_graphics_pipeline(Context& vk, const PipelineDesc& desc, const std::vector<uint32_t>& vertex_spirv,
                                const std::vector<uint32_t>& fragment_spirv, const RasterState& state);

// Collects descriptor writes by the names the pipeline's shaders declare (every pipeline is laid out
// by reflected_desc) and pushes them in one call: push() refuses a name they do not declare, a
// resource of another kind, and a declared binding left unwritten, naming the pass, shader and
// variable. No binding number is written by hand.
class DescriptorWriter {
 public:
  DescriptorWriter& image(const std::string& name, VkImageView view, VkSampler sampler);  // a sampler2D
  // Element `element` of an array of samplers (sampler2DArray shadow_maps[8]).
  DescriptorWriter& image_element(const std::string& name, uint32_t element, VkImageView view, VkSampler sampler);
  DescriptorWriter& image(const std::string& name, VkImageView view);  // an image2D
  // A storage or uniform buffer, as the shader declares it.
  DescriptorWriter& buffer(const std::string& name, VkBuffer buffer, VkDeviceSize offset = 0, VkDeviceSize range = VK_WHOLE_SIZE);
  DescriptorWriter& structure(const std::string& name, VkAccelerationStructureKHR structure);

  void push(const Context& vk, VkCommandBuffer cmd, const Pipeline& pipeline) const;

 private:
  struct Item {
    uint32_t binding;
    VkDescriptorType type;
    uint32_t element = 0;
    VkDescriptorImageInfo image;
    VkDescriptorBufferInfo buffer;
    VkAccelerationStructureKHR structure = VK_NULL_HANDLE;
    std::string name;  // its binding and type come from the pipeline's interface
  };
  Item& named(const std::string& name, VkDescriptorType type);
  // The items with their bindings: a named one's from `pipeline`'s interface, checked there.
  std::vector<Item> resolved(const Pipeline& pipeline) const;
  std::vector<Item> items_;
};

// Records a compute pipeline over every texel of `extent`, `depth` layers deep, in the 8x8 groups
// that the project's image kernels declare: binds it, then pushes its descriptors and push constants.
void dispatch_over_image(const Context& vk, VkCommandBuffer cmd, const Pipeline& pipeline, const DescriptorWriter& descriptors,
                         std::span<const std::byte> push_constants, VkExtent2D extent, uint32_t depth = 1);

template <class T>
std::span<const std::byte> bytes_of(const T& value) {
  return std::as_bytes(std::span<const T, 1>(&value, 1));
}

}  // namespace caustica::vk
