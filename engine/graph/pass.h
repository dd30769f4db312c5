#pragma once
// The device side of a pass type. setup() runs once per compiled plan (pipelines, counters);
// execute() records commands each frame. Both see resources only through their port names.
#include <vulkan/vulkan.h>

#include <string>
#include <utility>

#include "core/error.h"
#include "graph/frame_info.h"
#include "graph/plan.h"
#include "scene/gpu_scene.h"
#include "shader/shader_compiler.h"
#include "vk/context.h"
#include "vk/pipeline.h"

namespace caustica::graph {

class Executor;

class PassSetup {
 public:
  PassSetup(Executor& executor, const PlannedPass& pass) : executor_(executor), pass_(pass) {}
  vk::Context& vk() const;
  shader::ShaderCompiler& shaders() const;
  const PlannedPass& pass() const { return pass_; }
  const PlannedResource& resource(const std::string& port) const;
  bool bound(const std::string& port) const { return pass_.ports.count(port) != 0; }
  // A named counter the pass increments on the device; reported in --stats and the trace. A count
  // is a uint32 (atomicAdd on uint); a sum is a float32 in the same slot (atomicAdd on float).
  enum class CounterKind { count, sum };
  uint32_t add_counter(const std::string& name, CounterKind kind = CounterKind::count);
  // The pass that set up counter `name` first, or "" where none has: passes that count under one
  // name add into one counter.
  std::string counter_owner(const std::string& name) const;
  // How the plan's passes that trace walk the scene (Tracer::none where none traces).
  Tracer tracer() const;
  // A value of the scene the plan is compiled for (Scene::expression_values: "scene.surface_layers",
  // ...); 0 without a scene or such a value. A change of any of them compiles the plan again, so a
  // pass may set up for the scene's value.
  double scene_value(const std::string& name) const;
  // A shader of a pipeline: its path under the shader root and its defines.
  struct ShaderFile {
    std::string path;
    shader::Defines defines;
  };
  // Pipelines laid out as their shaders declare (vk::reflected_desc, named `name` for the driver):
  // the pass writes their descriptors by name, and checks a C++ mirror of their push-constant block
  // with Pipeline::interface->check_push.
  vk::Pipeline compute_pipeline(const std::string& name, const ShaderFile& shader);
  // One layout for a family of kernels that bind the same resources, from all their shaders'
  // declarations together: each of its pipelines is written with every binding of the family.
  vk::PipelineDesc shared_layout(const std::string& name, const std::vector<ShaderFile>& shaders);
  vk::Pipeline compute_pipeline(const vk::PipelineDesc& layout, const ShaderFile& shader);
  vk::Pipeline graphics_pipeline(const std::string& name, const ShaderFile& vertex, const ShaderFile& fragment,
                                 const vk::RasterState& state);
  // A rule about bindings or parameters belongs in PassTypeDecl::check, where the compiler (and so
  // `validate`) sees it; set-up fails only for what no plan can know (a shader, the device).

 private:
  Executor& executor_;
  const PlannedPass& pass_;
};

class PassContext {
 public:
  PassContext(Executor& executor, const PlannedPass& pass, VkCommandBuffer cmd) : executor_(executor), pass_(pass), cmd_(cmd) {}
  VkCommandBuffer cmd() const { return cmd_; }
  vk::Context& vk() const;
  // As resolved, with the parameters that follow the frame (PlannedPass::frame_params) evaluated for this one.
  const nlohmann::json& params() const;
  bool bound(const std::string& port) const { return pass_.ports.count(port) != 0; }
  const PlannedResource& resource(const std::string& port) const;
  VkImage image(const std::string& port) const;
  VkImageView view(const std::string& port) const;
  // The image as a 2D array whatever its layers (a sampler2DArray reads a spot light's one-layer
  // shadow map and a point light's six alike), and one layer of a layered render target.
  VkImageView array_view(const std::string& port) const;
  VkImageView layer_view(const std::string& port, uint32_t layer) const;
  VkBuffer buffer(const std::string& port) const;
  VkExtent2D extent(const std::string& port) const;
  VkSampler linear_sampler() const;
  VkSampler nearest_sampler() const;
  // The buffer holding every counter (uint32 each) and the byte offset of one.
  VkBuffer counter_buffer() const;
  // The scene being rendered; only passes whose type declares needs_scene may ask.
  const scene::GpuScene& scene() const;
  VkDeviceSize counter_offset(uint32_t counter) const { return counter * sizeof(uint32_t); }
  // A counter whose value the pass knows while recording (layers, batches): reported as it is,
  // without a device write. No shader may add to it.
  void set_counter(uint32_t counter, double value) const;
  const FrameInfo& frame() const;
  // For a pass that redraws only what changed: whether the scene parts named in `parts`
  // (SceneDependency bits: what the part to be kept follows, which may be less than the pass
  // depends on) and its own parameters are as they were when it last ran in this plan (what it
  // reads from other passes may have changed; a jittered camera never is), and whether `port`'s
  // image still holds what the pass left in it then (kept across frames, and written by no other
  // pass).
  bool scene_unchanged_since_last_run(uint32_t parts) const;
  bool kept_since_last_run(const std::string& port) const;
  // More frames of an unchanged scene would still change this pass's result (a running mean short of
  // its frame count): a viewer keeps drawing while any pass of the frame says so.
  void still_converging() const;
  // For a pass that accumulates: the frames its running result holds, where that is fewer than the
  // frames it ran since its reset (a mean held at its max_frames); FrameResult::accumulated reports it.
  void holds_frames(uint64_t frames) const;

 private:
  Executor& executor_;
  const PlannedPass& pass_;
  VkCommandBuffer cmd_;
};

class Pass {
 public:
  virtual ~Pass() = default;
  virtual void setup(PassSetup& setup) { (void)setup; }
  virtual void execute(PassContext& context) = 0;
  // A pass that keeps a running result of its own besides its images (accumulate's sums) takes it
  // over from the pass of an earlier plan with the same PlannedPass::running_id (so of its type),
  // which is not run again: the result goes on where that plan left it.
  virtual void continue_from(Pass& earlier) { (void)earlier; }
};

}  // namespace caustica::graph
