#include "vk/pipeline.h"

#include <cassert>
#include <type_traits>

#include "common/scene_types.h"  // CAUSTICA_MAX_TEXTURES, the size of set 1
#include "core/error.h"

namespace caustica::vk {
namespace {

OwnedShaderModule make_module(Context& vk, const std::vector<uint32_t>& spirv) {
  VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  info.codeSize = spirv.size() * sizeof(uint32_t);
  info.pCode = spirv.data();
  VkShaderModule module = VK_NULL_HANDLE;
  check(vkCreateShaderModule(vk.device(), &info, nullptr, &module), "vkCreateShaderModule");
  return OwnedShaderModule(vk, module);
}

// Everything that makes two pipelines the same, as bytes.
class Key {
 public:
  explicit Key(const char* kind, const PipelineDesc& desc) : text_(kind) {
    *this << desc.name << desc.bindings << desc.counts << desc.push_constant_bytes << desc.texture_array;
  }
  Key& operator<<(const std::string& s) { return bytes(s.data(), s.size()) << '\0'; }
  template <typename T>
  Key& operator<<(const std::vector<T>& v) {
    *this << v.size();
    return bytes(v.data(), v.size() * sizeof(T));
  }
  template <typename T>
  Key& operator<<(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    return bytes(&value, sizeof(T));
  }
  const std::string& text() const { return text_; }

 private:
  Key& bytes(const void* data, size_t size) {
    text_.append(static_cast<const char*>(data), size);
    return *this;
  }
  std::string text_;
};

void make_layout(Context& vk, const PipelineDesc& desc, VkShaderStageFlags stages, Pipeline& out) {
  std::vector<VkDescriptorSetLayoutBinding> bindings;
  for (uint32_t i = 0; i < desc.bindings.size(); ++i) {
    const uint32_t count = i < desc.counts.size() ? desc.counts[i] : 1;
    if (desc.bindings[i] != VK_DESCRIPTOR_TYPE_MAX_ENUM) bindings.push_back({i, desc.bindings[i], count, stages, nullptr});
  }
  VkDescriptorSetLayoutCreateInfo set_info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  set_info.flags = VK_DESCRIPTOR_SET_LAYOUT_CREATE_PUSH_DESCRIPTOR_BIT_KHR;
  set_info.bindingCount = static_cast<uint32_t>(bindings.size());
  set_info.pBindings = bindings.data();
  VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
  check(vkCreateDescriptorSetLayout(vk.device(), &set_info, nullptr, &set_layout), "vkCreateDescriptorSetLayout");
  out.set_layout = Shared(OwnedSetLayout(vk, set_layout));

  std::vector<VkDescriptorSetLayout> sets{set_layout};
  if (desc.texture_array > 0) {
    out.texture_set_layout = Shared(texture_array_layout(vk, desc.texture_array));
    sets.push_back(out.texture_set_layout.get());
  }
  VkPushConstantRange range{stages, 0, desc.push_constant_bytes};
  VkPipelineLayoutCreateInfo layout_info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  layout_info.setLayoutCount = static_cast<uint32_t>(sets.size());
  layout_info.pSetLayouts = sets.data();
  layout_info.pushConstantRangeCount = desc.push_constant_bytes ? 1 : 0;
  layout_info.pPushConstantRanges = &range;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  check(vkCreatePipelineLayout(vk.device(), &layout_info, nullptr, &layout), "vkCreatePipelineLayout");
  out.layout = Shared(OwnedPipelineLayout(vk, layout));
  out.stages = stages;
}

// The cache's pipeline as `desc`'s pass sees it: identical pipelines of two passes share their
// objects, and each names its own pass in what its descriptor writes are refused for.
Pipeline with_interface(Pipeline pipeline, const PipelineDesc& desc) {
  pipeline.interface = desc.interface;
  return pipeline;
}

VkDescriptorType descriptor_type(shader::BindingKind kind) {
  switch (kind) {
    case shader::BindingKind::sampled_image: return VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    case shader::BindingKind::storage_image: return VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
    case shader::BindingKind::uniform_buffer: return VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    case shader::BindingKind::acceleration_structure: return VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR;
    case shader::BindingKind::storage_buffer:
    case shader::BindingKind::other: break;
  }
  return VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
}

std::vector<shader::BindingKind> kinds_of(VkDescriptorType type) {
  switch (type) {
    case VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER: return {shader::BindingKind::sampled_image};
    case VK_DESCRIPTOR_TYPE_STORAGE_IMAGE: return {shader::BindingKind::storage_image};
    case VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR: return {shader::BindingKind::acceleration_structure};
    default: return {shader::BindingKind::storage_buffer, shader::BindingKind::uniform_buffer};
  }
}

}  // namespace

PipelineDesc reflected_desc(std::string name, std::shared_ptr<const shader::ShaderInterface> interface) {
  PipelineDesc desc{std::move(name), {}, {}, interface->push_size(), 0, interface};
  for (const shader::InterfaceBinding& b : interface->bindings()) {
    if (b.set == 1) {
      desc.texture_array = CAUSTICA_MAX_TEXTURES;
      continue;
    }
    if (desc.bindings.size() <= b.binding) {
      desc.bindings.resize(b.binding + 1, VK_DESCRIPTOR_TYPE_MAX_ENUM);
      desc.counts.resize(b.binding + 1, 1);
    }
    desc.bindings[b.binding] = descriptor_type(b.kind);
    desc.counts[b.binding] = b.count;
  }
  return desc;
}

PipelineDesc reflected_desc(std::string name, std::string pass, const std::vector<shader::NamedReflection>& shaders) {
  return reflected_desc(std::move(name), std::make_shared<const shader::ShaderInterface>(std::move(pass), shaders));
}

OwnedSetLayout texture_array_layout(Context& vk, uint32_t count) {
  const VkDescriptorSetLayoutBinding binding{0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, count, VK_SHADER_STAGE_ALL, nullptr};
  VkDescriptorSetLayoutCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  info.bindingCount = 1;
  info.pBindings = &binding;
  VkDescriptorSetLayout layout = VK_NULL_HANDLE;
  check(vkCreateDescriptorSetLayout(vk.device(), &info, nullptr, &layout), "vkCreateDescriptorSetLayout");
  return OwnedSetLayout(vk, layout);
}

Pipeline make_compute_pipeline(Context& vk, const PipelineDesc& desc, const std::vector<uint32_t>& spirv) {
  Key key("compute", desc);
  key << spirv;
  if (const Pipeline* made = vk.pipelines().find(key.text())) return with_interface(*made, desc);
  Pipeline out;
  out.bind_point = VK_PIPELINE_BIND_POINT_COMPUTE;
  make_layout(vk, desc, VK_SHADER_STAGE_COMPUTE_BIT, out);
  OwnedShaderModule module = make_module(vk, spirv);
  VkComputePipelineCreateInfo info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  info.stage = {
      VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0, VK_SHADER_STAGE_COMPUTE_BIT, module.get(), "main", nullptr};
  info.layout = out.layout.get();
  VkPipeline pipeline = VK_NULL_HANDLE;
  check(vkCreateComputePipelines(vk.device(), VK_NULL_HANDLE, 1, &info, nullptr, &pipeline), "vkCreateComputePipelines");
  out.pipeline = Shared(OwnedPipeline(vk, pipeline));
  vk.set_name(VK_OBJECT_TYPE_PIPELINE, reinterpret_cast<uint64_t>(pipeline), desc.name);
  return with_interface(vk.pipelines().insert(key.text(), std::move(out)), desc);
}

Pipeline make_fullscreen_pipeline(Context& vk, const PipelineDesc& desc, const std::vector<uint32_t>& vertex_spirv,
                                  const std::vector<uint32_t>& fragment_spirv, const std::vector<VkFormat>& color_formats) {
  RasterState state;
  state.color_formats = color_formats;
  return make_graphics_pipeline(vk, desc, vertex_spirv, fragment_spirv, state);
}

Pipeline make_graphics_pipeline(Context& vk, const PipelineDesc& desc, const std::vector<uint32_t>& vertex_spirv,
                                const std::vector<uint32_t>& fragment_spirv, const RasterState& state) {
  Key key("graphics", desc);
  key << vertex_spirv << fragment_spirv << state.color_formats << state.depth_format << state.depth_write << state.depth_compare
      << state.cull;
  if (const Pipeline* made = vk.pipelines().find(key.text())) return with_interface(*made, desc);
  const std::vector<VkFormat>& color_formats = state.color_formats;
  Pipeline out;
  out.bind_point = VK_PIPELINE_BIND_POINT_GRAPHICS;
  make_layout(vk, desc, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, out);
  OwnedShaderModule vertex = make_module(vk, vertex_spirv);
  OwnedShaderModule fragment = make_module(vk, fragment_spirv);
  VkPipelineShaderStageCreateInfo stages[] = {
      {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0, VK_SHADER_STAGE_VERTEX_BIT, vertex.get(), "main", nullptr},
      {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0, VK_SHADER_STAGE_FRAGMENT_BIT, fragment.get(), "main", nullptr}};
  VkPipelineVertexInputStateCreateInfo vertex_input{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
  VkPipelineInputAssemblyStateCreateInfo assembly{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
  assembly.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
  VkPipelineViewportStateCreateInfo viewport{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
  viewport.viewportCount = 1;
  viewport.scissorCount = 1;
  VkPipelineRasterizationStateCreateInfo raster{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
  raster.polygonMode = VK_POLYGON_MODE_FILL;
  raster.cullMode = state.cull;
  raster.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
  raster.lineWidth = 1.0f;
  VkPipelineMultisampleStateCreateInfo multisample{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
  multisample.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
  VkPipelineDepthStencilStateCreateInfo depth{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
  depth.depthTestEnable = state.depth_format != VK_FORMAT_UNDEFINED;
  depth.depthWriteEnable = state.depth_format != VK_FORMAT_UNDEFINED && state.depth_write;
  depth.depthCompareOp = state.depth_compare;
  std::vector<VkPipelineColorBlendAttachmentState> blend(color_formats.size());
  for (auto& b : blend) b.colorWriteMask = 0xF;
  VkPipelineColorBlendStateCreateInfo blend_state{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
  blend_state.attachmentCount = static_cast<uint32_t>(blend.size());
  blend_state.pAttachments = blend.data();
  VkDynamicState dynamic_states[] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
  VkPipelineDynamicStateCreateInfo dynamic{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
  dynamic.dynamicStateCount = 2;
  dynamic.pDynamicStates = dynamic_states;
  VkPipelineRenderingCreateInfo rendering{VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO};
  rendering.colorAttachmentCount = static_cast<uint32_t>(color_formats.size());
  rendering.pColorAttachmentFormats = color_formats.data();
  rendering.depthAttachmentFormat = state.depth_format;
  VkGraphicsPipelineCreateInfo info{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
  info.pNext = &rendering;
  info.stageCount = 2;
  info.pStages = stages;
  info.pVertexInputState = &vertex_input;
  info.pInputAssemblyState = &assembly;
  info.pViewportState = &viewport;
  info.pRasterizationState = &raster;
  info.pMultisampleState = &multisample;
  info.pDepthStencilState = &depth;
  info.pColorBlendState = &blend_state;
  info.pDynamicState = &dynamic;
  info.layout = out.layout.get();
  VkPipeline pipeline = VK_NULL_HANDLE;
  check(vkCreateGraphicsPipelines(vk.device(), VK_NULL_HANDLE, 1, &info, nullptr, &pipeline), "vkCreateGraphicsPipelines");
  out.pipeline = Shared(OwnedPipeline(vk, pipeline));
  vk.set_name(VK_OBJECT_TYPE_PIPELINE, reinterpret_cast<uint64_t>(pipeline), desc.name);
  return with_interface(vk.pipelines().insert(key.text(), std::move(out)), desc);
}

const Pipeline* PipelineCache::find(const std::string& key) const {
  const auto found = pipelines_.find(key);
  return found == pipelines_.end() ? nullptr : &found->second;
}

const Pipeline& PipelineCache::insert(const std::string& key, Pipeline pipeline) {
  if (pipelines_.size() >= kKeep) std::erase_if(pipelines_, [](const auto& entry) { return !entry.second.pipeline.shared_elsewhere(); });
  return pipelines_.insert_or_assign(key, std::move(pipeline)).first->second;
}

DescriptorWriter::Item& DescriptorWriter::named(const std::string& name, VkDescriptorType type) {
  Item& item = items_.emplace_back(Item{0, type, 0, {}, {}});
  item.name = name;
  return item;
}

DescriptorWriter& DescriptorWriter::image(const std::string& name, VkImageView view, VkSampler sampler) {
  named(name, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER).image = {sampler, view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
  return *this;
}

DescriptorWriter& DescriptorWriter::image_element(const std::string& name, uint32_t element, VkImageView view, VkSampler sampler) {
  Item& item = named(name, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER);
  item.image = {sampler, view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
  item.element = element;
  return *this;
}

DescriptorWriter& DescriptorWriter::image(const std::string& name, VkImageView view) {
  named(name, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE).image = {VK_NULL_HANDLE, view, VK_IMAGE_LAYOUT_GENERAL};
  return *this;
}

DescriptorWriter& DescriptorWriter::buffer(const std::string& name, VkBuffer buffer, VkDeviceSize offset, VkDeviceSize range) {
  named(name, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER).buffer = {buffer, offset, range};
  return *this;
}

DescriptorWriter& DescriptorWriter::structure(const std::string& name, VkAccelerationStructureKHR structure) {
  named(name, VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR).structure = structure;
  return *this;
}

void DescriptorWriter::push(const Context& vk, VkCommandBuffer cmd, const Pipeline& pipeline) const {
  const std::vector<Item> items = resolved(pipeline);
  std::vector<VkWriteDescriptorSet> writes;
  // Acceleration structures are written through a chained struct; reserved so pointers stay put.
  std::vector<VkWriteDescriptorSetAccelerationStructureKHR> structures;
  structures.reserve(items.size());
  for (const auto& item : items) {
    VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    w.dstBinding = item.binding;
    w.dstArrayElement = item.element;
    w.descriptorCount = 1;
    w.descriptorType = item.type;
    if (item.type == VK_DESCRIPTOR_TYPE_STORAGE_BUFFER || item.type == VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER) {
      w.pBufferInfo = &item.buffer;
    } else if (item.type == VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR) {
      auto& write = structures.emplace_back();
      write = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET_ACCELERATION_STRUCTURE_KHR};
      write.accelerationStructureCount = 1;
      write.pAccelerationStructures = &item.structure;
      w.pNext = &write;
    } else {
      w.pImageInfo = &item.image;
    }
    writes.push_back(w);
  }
  if (writes.empty()) return;  // a pipeline without descriptors (a fullscreen pass that only draws): pushing none is invalid
  vk.push_descriptor_set(cmd, pipeline.bind_point, pipeline.layout.get(), 0, static_cast<uint32_t>(writes.size()), writes.data());
}

std::vector<DescriptorWriter::Item> DescriptorWriter::resolved(const Pipeline& pipeline) const {
  std::vector<Item> items = items_;
  assert(pipeline.interface && "every pipeline is laid out as its shaders declare (reflected_desc)");
  const shader::ShaderInterface& interface = *pipeline.interface;
  std::vector<std::pair<size_t, uint32_t>> written;
  for (Item& item : items) {
    const shader::InterfaceBinding& b = interface.find(item.name, kinds_of(item.type));
    if (item.element >= b.count) {
      throw InputError("pass '" + interface.pass() + "' writes element " + std::to_string(item.element) + " of '" + item.name +
                       "', which has " + std::to_string(b.count));
    }
    item.binding = b.binding;
    item.type = descriptor_type(b.kind);
    written.emplace_back(static_cast<size_t>(&b - interface.bindings().data()), item.element);
  }
  interface.check_written(written);
  return items;
}

void dispatch_over_image(const Context& vk, VkCommandBuffer cmd, const Pipeline& pipeline, const DescriptorWriter& descriptors,
                         std::span<const std::byte> push_constants, VkExtent2D extent, uint32_t depth) {
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.pipeline.get());
  descriptors.push(vk, cmd, pipeline);
  if (!push_constants.empty()) {
    vkCmdPushConstants(cmd, pipeline.layout.get(), pipeline.stages, 0, static_cast<uint32_t>(push_constants.size()), push_constants.data());
  }
  vkCmdDispatch(cmd, (extent.width + 7) / 8, (extent.height + 7) / 8, depth);
}

}  // namespace caustica::vk
