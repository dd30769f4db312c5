// The pass interfaces: what a pass sees of the executor at set-up (PassSetup) and while recording (PassContext).
#include <algorithm>
#include <cassert>

#include "core/error.h"
#include "graph/executor_internal.h"
#include "graph/pass.h"

namespace caustica::graph {

vk::Context& PassSetup::vk() const {
  return executor_.vk_;
}
shader::ShaderCompiler& PassSetup::shaders() const {
  return executor_.shaders_;
}
Tracer PassSetup::tracer() const {
  return executor_.plan_->tracer;
}
double PassSetup::scene_value(const std::string& name) const {
  if (!executor_.scene_) return 0.0;
  const auto values = executor_.scene_->scene().expression_values();
  const auto it = values.find(name);
  return it == values.end() ? 0.0 : it->second;
}
const PlannedResource& PassSetup::resource(const std::string& port) const {
  return executor_.plan_->resources[pass_.ports.at(port)];
}
uint32_t PassSetup::add_counter(const std::string& name, CounterKind kind) {
  auto& slots = executor_.realized_->counter_slots;
  const auto pass = static_cast<size_t>(&pass_ - executor_.plan_->passes.data());
  const auto it = std::find_if(slots.begin(), slots.end(), [&](const auto& slot) { return slot.pass == pass && slot.name == name; });
  if (it != slots.end()) return static_cast<uint32_t>(it - slots.begin());
  if (slots.size() >= kMaxCounters) throw DeviceError("more than " + std::to_string(kMaxCounters) + " pass counters");
  slots.push_back({name, pass, kind == CounterKind::sum});
  return static_cast<uint32_t>(slots.size() - 1);
}
std::string PassSetup::counter_owner(const std::string& name) const {
  for (const auto& slot : executor_.realized_->counter_slots) {
    if (slot.name == name) return executor_.plan_->passes[slot.pass].name;
  }
  return {};
}
vk::Pipeline PassSetup::compute_pipeline(const std::string& name, const ShaderFile& shader) {
  return compute_pipeline(shared_layout(name, {shader}), shader);
}
vk::PipelineDesc PassSetup::shared_layout(const std::string& name, const std::vector<ShaderFile>& shaders) {
  std::vector<shader::ReflectedShader> compiled;
  for (const ShaderFile& shader : shaders) compiled.push_back(this->shaders().compile_reflected(shader.path, shader.defines));
  std::vector<shader::NamedReflection> reflections;
  for (size_t i = 0; i < shaders.size(); ++i) reflections.push_back({shaders[i].path, &compiled[i].reflection});
  return vk::reflected_desc(name, pass_.name, reflections);
}
vk::Pipeline PassSetup::compute_pipeline(const vk::PipelineDesc& layout, const ShaderFile& shader) {
  return vk::make_compute_pipeline(vk(), layout, shaders().compile(shader.path, shader.defines));
}
vk::Pipeline PassSetup::graphics_pipeline(const std::string& name, const ShaderFile& vertex, const ShaderFile& fragment,
                                          const vk::RasterState& state) {
  const shader::ReflectedShader v = shaders().compile_reflected(vertex.path, vertex.defines);
  const shader::ReflectedShader f = shaders().compile_reflected(fragment.path, fragment.defines);
  return vk::make_graphics_pipeline(
      vk(), vk::reflected_desc(name, pass_.name, {{vertex.path, &v.reflection}, {fragment.path, &f.reflection}}), v.spirv, f.spirv, state);
}

vk::Context& PassContext::vk() const {
  return executor_.vk_;
}
const PlannedResource& PassContext::resource(const std::string& port) const {
  return executor_.plan_->resources[pass_.ports.at(port)];
}
VkImage PassContext::image(const std::string& port) const {
  return executor_.realized_->images[pass_.ports.at(port)].image.get();
}
VkImageView PassContext::view(const std::string& port) const {
  return executor_.realized_->images[pass_.ports.at(port)].view.get();
}
VkImageView PassContext::array_view(const std::string& port) const {
  const auto& real = executor_.realized_->images[pass_.ports.at(port)];
  return resource(port).layers > 1 ? real.view.get() : real.array_view.get();
}
VkImageView PassContext::layer_view(const std::string& port, uint32_t layer) const {
  const auto& real = executor_.realized_->images[pass_.ports.at(port)];
  if (resource(port).layers == 1) return real.view.get();
  assert(layer < real.layer_views.size() && "layer_view of a layered render target");
  return real.layer_views[layer].get();
}
VkBuffer PassContext::buffer(const std::string& port) const {
  return executor_.realized_->buffers[pass_.ports.at(port)].buffer.get();
}
VkExtent2D PassContext::extent(const std::string& port) const {
  const auto& r = resource(port);
  return {r.width, r.height};
}
VkSampler PassContext::linear_sampler() const {
  return executor_.realized_->linear.get();
}
VkSampler PassContext::nearest_sampler() const {
  return executor_.realized_->nearest.get();
}
VkBuffer PassContext::counter_buffer() const {
  return executor_.realized_->counters.get();
}
void PassContext::set_counter(uint32_t counter, double value) const {
  executor_.realized_->host_counters[counter] = value;
}
void PassContext::still_converging() const {
  executor_.realized_->run.passes[executor_.realized_->recording_pass].converging = true;
}
void PassContext::holds_frames(uint64_t frames) const {
  executor_.realized_->run.passes[executor_.realized_->recording_pass].frames_held = frames;
}
const FrameInfo& PassContext::frame() const {
  return executor_.realized_->run.passes[executor_.realized_->recording_pass].frames;
}
bool PassContext::scene_unchanged_since_last_run(uint32_t parts) const {
  const Executor::Realized& real = *executor_.realized_;
  const auto& then = real.run.passes[real.recording_pass].last_run_scene;
  if (!then || executor_.plan_->jitters_camera || !pass_.frame_params.empty()) return false;
  return then->masked(parts, pass_.lights) == real.scene_now.value_or(SceneKeys{}).masked(parts, pass_.lights);
}
bool PassContext::kept_since_last_run(const std::string& port) const {
  const PlannedResource& r = resource(port);
  const auto self = static_cast<uint32_t>(executor_.realized_->recording_pass);
  return r.kept_across_frames && r.first_use == self && r.last_use == self;
}
const nlohmann::json& PassContext::params() const {
  return *executor_.realized_->recording_params;
}
const scene::GpuScene& PassContext::scene() const {
  assert(executor_.scene_ && pass_.decl->needs_scene && "scene() from a pass type that does not declare needs_scene");
  return *executor_.scene_;
}
}  // namespace caustica::graph
