// compute and fullscreen: passes whose shader, ports and parameters the graph file declares
// (graph/user_pass_type.h). The compiler has compiled the shader and checked it against the
// declarations; here its pipeline is laid out as the shader declares, each port bound by its name
// there, the parameters pushed as push constants or written into the pass's uniform buffer at their
// offsets, and the shader dispatched over its port or invocations, or drawn full screen.
#include <algorithm>
#include <array>
#include <cassert>
#include <cstddef>
#include <cstring>
#include <vector>

#include "builtin_passes.h"
#include "graph/pass.h"
#include "graph/user_pass_type.h"
#include "refraction.h"
#include "vk/buffer.h"
#include "vk/pipeline.h"

namespace caustica::passes {
namespace {

class UserPass final : public graph::Pass {
 public:
  void setup(graph::PassSetup& setup) override {
    decl_ = setup.pass().decl;
    shader_ = decl_->user_shader.get();
    assert(shader_ && "a user pass compiled without its shader");
    setup_counters(setup);
    if (shader_->params_block) {
      params_ = vk::make_buffer(setup.vk(), shader_->params_bytes, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, 0,
                                setup.pass().name + " parameters");
    }
    // Laid out as the shaders declare, as a built-in pass's pipeline is (vk::reflected_desc); the
    // shader as compiled for the plan's tracer.
    compute_tracer_ = setup.tracer() == graph::Tracer::compute && shader_->compute_tracer;
    const std::vector<uint32_t>& spirv = compute_tracer_ ? shader_->compute_tracer->spirv : shader_->spirv;
    const std::string& name = setup.pass().name;
    std::vector<shader::NamedReflection> stages{
        {shader_->path, compute_tracer_ ? &shader_->compute_tracer->reflection : &shader_->reflection}};
    if (shader_->kind == graph::UserShaderKind::compute) {
      pipeline_ = vk::make_compute_pipeline(setup.vk(), vk::reflected_desc(name, name, stages), spirv);
      return;
    }
    const char* vertex_path = "common/fullscreen.vert";
    const shader::ReflectedShader vertex =
        setup.shaders().compile_reflected(vertex_path, shader_->reads_uv ? shader::Defines{{"FULLSCREEN_UV", "1"}} : shader::Defines{});
    stages.insert(stages.begin(), {vertex_path, &vertex.reflection});
    std::vector<std::pair<uint32_t, VkFormat>> colors;
    for (const auto& b : shader_->bindings) {
      if (decl_->find_port(b.port)->usage == graph::PortUsage::color_attachment)
        colors.emplace_back(b.binding, graph::format_info(setup.resource(b.port).format).vk);
    }
    std::sort(colors.begin(), colors.end());
    std::vector<VkFormat> formats;
    for (const auto& [location, format] : colors) formats.push_back(format);
    pipeline_ = vk::make_fullscreen_pipeline(setup.vk(), vk::reflected_desc(name, name, stages), vertex.spirv, spirv, formats);
  }

  void execute(graph::PassContext& ctx) override {
    const graph::PassTypeDecl& decl = *decl_;
    VkCommandBuffer cmd = ctx.cmd();
    vk::DescriptorWriter writer;
    bind_scene(ctx, writer);
    std::vector<std::pair<uint32_t, VkImageView>> colors;
    for (const auto& b : shader_->bindings) {
      const graph::PortDecl& port = *decl.find_port(b.port);
      if (port.kind == graph::ResourceKind::buffer) {
        writer.buffer(b.name, ctx.buffer(b.port));
      } else if (port.usage == graph::PortUsage::sampled) {
        writer.image(b.name, ctx.view(b.port), ctx.nearest_sampler());
      } else if (port.usage == graph::PortUsage::storage) {
        writer.image(b.name, ctx.view(b.port));
      } else {
        colors.emplace_back(b.binding, ctx.view(b.port));
      }
    }
    if (counters_.buffer) {
      vkCmdFillBuffer(cmd, counters_.get(), 0, VK_WHOLE_SIZE, 0);
      // Also orders the frame's zeroing of the engine's counters before copy_counters' copy into them.
      vk::memory_barrier(
          cmd, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
          VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
          VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_TRANSFER_WRITE_BIT);
      if (shader_->counts_buffer) writer.buffer(shader_->counts_buffer->name, counters_.get());
      if (shader_->sums_buffer) writer.buffer(shader_->sums_buffer->name, counters_.get());
    }
    if (params_.buffer) writer.buffer(shader_->params_block->name, params_.get());
    record(ctx, writer, colors);
    if (counters_.buffer) copy_counters(ctx);
  }

 private:
  // The scene's blocks, acceleration structure and triangles, each under the shader's name for it.
  void bind_scene(const graph::PassContext& ctx, vk::DescriptorWriter& writer) const {
    if (shader_->scene_bindings.empty()) return;  // a pass without the scene may not ask for it
    const auto& scene = ctx.scene();
    for (const graph::UserSceneBinding& b : shader_->scene_bindings) {
      switch (b.resource) {
        case graph::SceneResource::frame: writer.buffer(b.name, scene.frame()); break;
        case graph::SceneResource::vertices: writer.buffer(b.name, scene.vertices()); break;
        case graph::SceneResource::objects: writer.buffer(b.name, scene.objects()); break;
        case graph::SceneResource::acceleration_structure:
          if (compute_tracer_) {
            writer.buffer("BvhBlock", traced_bvh(ctx).bvh.get());
          } else {
            writer.structure(b.name, traced(ctx).tlas());
          }
          break;
        case graph::SceneResource::triangles:
          writer.buffer(b.name, compute_tracer_ ? traced_bvh(ctx).triangles.get() : traced(ctx).triangles());
          break;
      }
    }
  }

  static const scene::AccelerationStructures& traced(const graph::PassContext& ctx) {
    const auto* acceleration = ctx.scene().built_acceleration();
    assert(acceleration && "the executor builds the scene's acceleration structures for every plan with a ray-query pass");
    return *acceleration;
  }
  static const scene::GpuScene::TracerBuffers& traced_bvh(const graph::PassContext& ctx) {
    const auto* bvh = ctx.scene().built_tracer_bvh();
    assert(bvh && "the executor builds the scene's BVH for every plan that traces with the compute tracer");
    return *bvh;
  }

  void record(graph::PassContext& ctx, const vk::DescriptorWriter& writer, std::vector<std::pair<uint32_t, VkImageView>>& colors) const {
    const graph::PassTypeDecl& decl = *decl_;
    VkCommandBuffer cmd = ctx.cmd();
    const std::vector<std::byte> params = parameter_block(decl, ctx.params());
    if (params_.buffer) update_params(cmd, params);
    if (shader_->kind == graph::UserShaderKind::compute) {
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_.pipeline.get());
      bind(ctx, writer);
      if (!params_.buffer && !params.empty())
        vkCmdPushConstants(cmd, pipeline_.layout.get(), pipeline_.stages, 0, static_cast<uint32_t>(params.size()), params.data());
      std::array<uint32_t, 3> invocations = shader_->invocations;
      if (!shader_->dispatch_port.empty()) {
        const VkExtent2D extent = ctx.extent(shader_->dispatch_port);
        invocations = {extent.width, extent.height, ctx.resource(shader_->dispatch_port).layers};
      }
      const auto& local = shader_->local_size;
      vkCmdDispatch(cmd, (invocations[0] + local[0] - 1) / local[0], (invocations[1] + local[1] - 1) / local[1],
                    (invocations[2] + local[2] - 1) / local[2]);
      return;
    }
    std::sort(colors.begin(), colors.end());
    std::vector<Attachment> attachments;
    for (const auto& [location, view] : colors) attachments.push_back({view, VK_ATTACHMENT_LOAD_OP_DONT_CARE});
    begin_rendering(cmd, ctx.extent(shader_->bindings.front().port), attachments, std::nullopt);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_.pipeline.get());
    bind(ctx, writer);
    if (!params_.buffer && !params.empty())
      vkCmdPushConstants(cmd, pipeline_.layout.get(), pipeline_.stages, 0, static_cast<uint32_t>(params.size()), params.data());
    vkCmdDraw(cmd, 3, 1, 0, 0);
    vkCmdEndRendering(cmd);
  }

  // Set 0 as pushed descriptors; set 1, the scene's textures, where the shader samples them.
  void bind(const graph::PassContext& ctx, const vk::DescriptorWriter& writer) const {
    writer.push(ctx.vk(), ctx.cmd(), pipeline_);
    if (shader_->scene_textures) bind_scene_textures(ctx, ctx.cmd(), pipeline_);
  }

  // The shader adds to a buffer of the pass's own, slot k its k-th counter, which is copied into
  // the engine's counters after it has run: the engine's slots of a pass's counters need not be
  // consecutive, nor aligned for a descriptor's offset, and no user shader can reach the slots of
  // another pass's counters.
  void setup_counters(graph::PassSetup& setup) {
    if (shader_->counters.empty()) return;
    slots_.clear();
    for (const auto& counter : shader_->counters) {
      // A copy would overwrite what the other pass added: a user pass's counters are its own.
      if (const std::string owner = setup.counter_owner(counter.name); !owner.empty()) {
        throw InputError("pass '" + setup.pass().name + "': counter '" + counter.name + "' is pass '" + owner +
                         "''s too; give the user pass's counter a name of its own");
      }
      slots_.push_back(
          setup.add_counter(counter.name, counter.sum ? graph::PassSetup::CounterKind::sum : graph::PassSetup::CounterKind::count));
    }
    counters_ = vk::make_buffer(setup.vk(), shader_->counters.size() * sizeof(uint32_t),
                                VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, 0,
                                setup.pass().name + " counters");
  }

  void copy_counters(const graph::PassContext& ctx) const {
    VkCommandBuffer cmd = ctx.cmd();
    vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                       VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
    std::vector<VkBufferCopy> regions;
    for (size_t k = 0; k < slots_.size(); ++k) regions.push_back({k * sizeof(uint32_t), ctx.counter_offset(slots_[k]), sizeof(uint32_t)});
    vkCmdCopyBuffer(cmd, counters_.get(), ctx.counter_buffer(), static_cast<uint32_t>(regions.size()), regions.data());
    // The passes after it add to the engine's counters too.
    vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                       VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                       VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  }

  // The parameter block: each parameter's 4 bytes at its member's offset.
  std::vector<std::byte> parameter_block(const graph::PassTypeDecl& decl, const nlohmann::json& params) const {
    std::vector<std::byte> block(shader_->params_bytes);
    for (const auto& member : shader_->params) {
      const graph::ParamDecl& param = *decl.find_param(member.name);
      const nlohmann::json& value = params[member.name];
      uint32_t word = 0;
      switch (param.type) {
        case graph::ParamType::float_: {
          const float f = value.get<float>();
          std::memcpy(&word, &f, sizeof word);
          break;
        }
        case graph::ParamType::int_: word = static_cast<uint32_t>(value.get<int32_t>()); break;
        case graph::ParamType::bool_: word = value.get<bool>() ? 1u : 0u; break;
        case graph::ParamType::choice:
          word = static_cast<uint32_t>(std::find(param.choices.begin(), param.choices.end(), value.get<std::string>()) -
                                       param.choices.begin());
          break;
      }
      std::memcpy(block.data() + member.offset, &word, sizeof word);
    }
    return block;
  }

  // Written in the command buffer each time the pass records, so that a parameter that follows the
  // frame has this frame's value; outside any rendering, as vkCmdUpdateBuffer must be.
  void update_params(VkCommandBuffer cmd, const std::vector<std::byte>& block) const {
    vkCmdUpdateBuffer(cmd, params_.get(), 0, block.size(), block.data());
    vk::memory_barrier(
        cmd, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
        shader_->kind == graph::UserShaderKind::compute ? VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT : VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
        VK_ACCESS_2_UNIFORM_READ_BIT);
  }

  const graph::PassTypeDecl* decl_ = nullptr;  // the pass's own type, which its plan holds
  const graph::UserShader* shader_ = nullptr;
  vk::Pipeline pipeline_;
  bool compute_tracer_ = false;
  vk::Buffer counters_;          // the shader's counter buffer, where the pass declares counters
  vk::Buffer params_;            // the uniform parameter block, where the shader declares one
  std::vector<uint32_t> slots_;  // the engine's slot of each
};

graph::PassTypeDecl user_pass_kind(const char* type, graph::UserShaderKind kind, const char* description) {
  graph::PassTypeDecl decl;
  decl.type = type;
  decl.description = description;
  decl.queue = kind == graph::UserShaderKind::compute ? graph::PassQueue::compute : graph::PassQueue::graphics;
  decl.create = [] { return std::make_unique<UserPass>(); };
  decl.user_kind = kind;
  return decl;
}

}  // namespace

graph::PassTypeDecl user_compute_pass_type() {
  return user_pass_kind(
      "compute", graph::UserShaderKind::compute,
      "Compute shader of your own: the pass names its .comp file and declares its ports (each a binding of the "
      "shader's, by name), parameters (its push-constant block or uniform block Params) and dispatch (docs/shader_passes.md).");
}

graph::PassTypeDecl user_fullscreen_pass_type() {
  return user_pass_kind(
      "fullscreen", graph::UserShaderKind::fullscreen,
      "Full-screen fragment shader of your own: the pass names its .frag file and declares its ports (inputs "
      "bound by name, outputs the shader's fragment outputs) and parameters (its push-constant block or uniform block Params) "
      "(docs/shader_passes.md).");
}

}  // namespace caustica::passes
