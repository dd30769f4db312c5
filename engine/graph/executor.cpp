#include "graph/executor.h"
#include "graph/executor_internal.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <chrono>
#include <cstring>
#include <stdexcept>
#include <utility>

#include "core/error.h"
#include "core/low_discrepancy.h"
#include "graph/expression.h"
#include "graph/user_pass_type.h"
#include "vk/buffer.h"

namespace caustica::graph {
namespace {


using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// Back from where `to_transfer` took the read-back images that are kept across frames: where the
// next frame's first barriers expect them.
std::vector<PlannedBarrier> back_from_transfer(const Plan& plan, const std::vector<PlannedBarrier>& to_transfer) {
  std::vector<PlannedBarrier> back;
  for (const PlannedBarrier& b : to_transfer) {
    if (plan.resources[b.resource].kind != ResourceKind::image || !plan.resources[b.resource].kept_across_frames) continue;
    back.push_back({b.resource, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_NONE, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                    VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT, b.new_layout, b.old_layout, false});
  }
  return back;
}

// A frame starts its kept images from the layout the last frame left them in
// (compiler_dependencies.cpp): before the first frame, that layout.
std::vector<PlannedBarrier> kept_images_to_final_layouts(const Plan& plan) {
  std::vector<PlannedBarrier> barriers;
  for (uint32_t r = 0; r < plan.resources.size(); ++r) {
    const PlannedResource& res = plan.resources[r];
    if (!res.used() || !res.kept_across_frames || res.kind != ResourceKind::image) continue;
    barriers.push_back({r, VK_PIPELINE_STAGE_2_NONE, VK_ACCESS_2_NONE, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                        VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT, VK_IMAGE_LAYOUT_UNDEFINED, res.final_state.layout,
                        false});
  }
  return barriers;
}

VkImageAspectFlags aspect_of(Format format) {
  return format_info(format).depth ? VK_IMAGE_ASPECT_DEPTH_BIT : VK_IMAGE_ASPECT_COLOR_BIT;
}

// A barrier on all of `res`'s image `image`.
VkImageMemoryBarrier2 whole_image_barrier(VkImage image, const PlannedResource& res, VkPipelineStageFlags2 src_stages,
                                          VkAccessFlags2 src_access, VkPipelineStageFlags2 dst_stages, VkAccessFlags2 dst_access,
                                          VkImageLayout old_layout, VkImageLayout new_layout) {
  return vk::image_transition(image, aspect_of(res.format), old_layout, new_layout, src_stages, src_access, dst_stages, dst_access, res.mips,
                              res.layers);
}

void pipeline_barrier(VkCommandBuffer cmd, const std::vector<VkImageMemoryBarrier2>& images,
                      const std::vector<VkBufferMemoryBarrier2>& buffers = {}) {
  VkDependencyInfo dependency{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
  dependency.imageMemoryBarrierCount = static_cast<uint32_t>(images.size());
  dependency.pImageMemoryBarriers = images.data();
  dependency.bufferMemoryBarrierCount = static_cast<uint32_t>(buffers.size());
  dependency.pBufferMemoryBarriers = buffers.data();
  vkCmdPipelineBarrier2(cmd, &dependency);
}

// Copies every mip level and layer of `res`'s image `from` (in TRANSFER_SRC_OPTIMAL) to `to` (in
// TRANSFER_DST_OPTIMAL), an image of the same description.
void copy_whole_image(VkCommandBuffer cmd, const PlannedResource& res, VkImage from, VkImage to) {
  const VkImageAspectFlags aspect = aspect_of(res.format);
  std::vector<VkImageCopy> levels;
  for (uint32_t level = 0; level < res.mips; ++level) {
    const VkImageSubresourceLayers layers{aspect, level, 0, res.layers};
    levels.push_back({layers, {}, layers, {}, {std::max(1u, res.width >> level), std::max(1u, res.height >> level), 1}});
  }
  vkCmdCopyImage(cmd, from, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, to, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                 static_cast<uint32_t>(levels.size()), levels.data());
}

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

// Whether resource `a`'s image, in memory of its own, can stand for `b`'s (Executor::carry_results).
bool same_own_image(const PlannedResource& a, const PlannedResource& b) {
  return a.kind == ResourceKind::image && b.kind == ResourceKind::image && !a.transient && !b.transient && a.format == b.format &&
         a.width == b.width && a.height == b.height && a.mips == b.mips && a.layers == b.layers && a.image_usage == b.image_usage;
}

VkBufferCreateInfo buffer_info(const PlannedResource& r) {
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = r.buffer_size;
  info.usage = r.buffer_usage;
  return info;
}

// A pass's parameters with those that follow the frame evaluated for `frame`. The compiler checked
// each expression on the first frame; a later frame's value is clamped to the declared range, and
// one that is not finite (a division by a frame count that reached zero) keeps the first frame's.
nlohmann::json params_for_frame(const Plan& plan, const PlannedPass& pass, const FrameInfo& frame) {
  // In the order of kFrameNames.
  const double frame_values[] = {static_cast<double>(frame.index), static_cast<double>(frame.since_reset),
                                 static_cast<double>(frame.camera_jitter.x), static_cast<double>(frame.camera_jitter.y)};
  static_assert(sizeof(frame_values) / sizeof(double) == std::size(kFrameNames));
  ExpressionScope scope;
  scope.lookup = [&](std::string_view name) -> std::optional<double> {
    for (size_t i = 0; i < std::size(kFrameNames); ++i) {
      if (name == kFrameNames[i]) return frame_values[i];
    }
    const auto it = plan.expression_values.find(std::string(name));
    return it == plan.expression_values.end() ? std::nullopt : std::optional<double>(it->second);
  };
  nlohmann::json params = pass.params;
  for (const auto& [name, expression] : pass.frame_params) {
    try {
      params[name] = param_value_of_number(*pass.decl->find_param(name), evaluate_expression(expression, scope), true);
    } catch (const std::invalid_argument&) {  // not finite on this frame: the names and syntax were checked
    }
  }
  return params;
}

}  // namespace

// ---- Executor ------------------------------------------------------------------------------------

Executor::Executor(vk::Context& vk, shader::ShaderCompiler& shaders, const PassRegistry& registry)
    : vk_(vk), shaders_(shaders), registry_(registry) {}

void Executor::set_scene(std::shared_ptr<const scene::Scene> scene) {
  scene_.reset();  // its buffers are destroyed once the GPU is done with them
  if (scene) scene_ = std::make_unique<scene::GpuScene>(vk_, std::move(scene));
}

void Executor::set_view(const scene::View& camera, std::vector<scene::Light> lights) {
  if (!scene_) throw std::logic_error("Executor::set_view before set_scene: there is no scene to view");
  scene_->replace_view(camera, std::move(lights));
}

Executor::~Executor() {
  realized_.reset();
  scene_.reset();
  vk_.wait_idle();
}

CompileOptions Executor::compile_options(uint32_t width, uint32_t height) const {
  CompileOptions options;
  options.output_width = width;
  options.output_height = height;
  const auto& limits = vk_.properties().limits;
  options.limits.max_image_dimension_2d = limits.maxImageDimension2D;
  options.limits.max_storage_buffer_range = limits.maxStorageBufferRange;
  options.ray_queries = vk_.ray_queries().available;
  options.ray_queries_missing = vk_.ray_queries().missing + " (" + vk_.device_name() + ")";
  VkDevice device = vk_.device();
  options.memory_requirements = [device](const PlannedResource& r) {
    VkMemoryRequirements2 requirements{VK_STRUCTURE_TYPE_MEMORY_REQUIREMENTS_2};
    if (r.kind == ResourceKind::image) {
      VkImageCreateInfo create = image_info(r);
      VkDeviceImageMemoryRequirements query{VK_STRUCTURE_TYPE_DEVICE_IMAGE_MEMORY_REQUIREMENTS};
      query.pCreateInfo = &create;
      vkGetDeviceImageMemoryRequirements(device, &query, &requirements);
    } else {
      VkBufferCreateInfo create = buffer_info(r);
      VkDeviceBufferMemoryRequirements query{VK_STRUCTURE_TYPE_DEVICE_BUFFER_MEMORY_REQUIREMENTS};
      query.pCreateInfo = &create;
      vkGetDeviceBufferMemoryRequirements(device, &query, &requirements);
    }
    const auto& m = requirements.memoryRequirements;
    return MemoryRequirements{m.size, m.alignment, m.memoryTypeBits};
  };
  return options;
}

bool Executor::configure(const GraphDesc& graph, uint32_t width, uint32_t height, const std::set<std::string>& retained,
                         uint64_t memory_limit_bytes) {
  std::string key = graph.doc.path() + "\n" + graph.doc.root().dump() + "\n" + std::to_string(width) + "x" + std::to_string(height) + "\n" +
                    std::to_string(memory_limit_bytes) + (reuse_unchanged_passes_ ? "\nreuse" : "");
  for (const auto& p : graph.parameters) key += "\n" + p.decl.name + "=" + p.value.dump();
  for (const auto& r : retained) key += "\nretain " + r;
  const auto scene_values = scene_ ? scene_->scene().expression_values() : std::map<std::string, double>{};
  for (const auto& [name, value] : scene_values) key += "\n" + name + "=" + std::to_string(value);
  const bool picture_may_stand = std::exchange(picture_may_stand_, false);
  if (plan_ && key == configured_key_) {
    if (!plan_->ray_query_passes.empty()) scene_->acceleration();  // set_scene() may have replaced the scene
    return false;
  }
  CompileOptions options = compile_options(width, height);
  options.retained = retained;
  options.memory_limit_bytes = memory_limit_bytes;
  options.scene_values = scene_values;
  options.reuse_unchanged_passes = reuse_unchanged_passes_;
  Plan plan = compile_graph(graph, registry_, options);
  for (const auto& pass : plan.passes) {
    if (pass.decl->needs_scene && !scene_) {
      throw graph.error(pass.pointer, "pass '" + pass.name + "' (" + pass.decl->type + ") draws a scene, and none was given (--scene)");
    }
  }
  if (!plan.ray_query_passes.empty()) scene_->acceleration();
  realize(std::move(plan), picture_may_stand);
  configured_key_ = key;
  ++compile_count_;
  return true;
}

void Executor::realize(Plan plan, bool picture_may_stand) {
  // The previous plan stays whole until the new one is set up, so that a failure (a shader that no
  // longer compiles, memory) leaves it running; its objects are destroyed once the GPU is done.
  std::unique_ptr<const Plan> previous_plan = std::move(plan_);
  std::unique_ptr<Realized> previous = std::move(realized_);
  plan_ = std::make_unique<const Plan>(std::move(plan));
  realized_ = std::make_unique<Realized>();
  try {
    realize_passes_and_resources();
  } catch (...) {
    realized_ = std::move(previous);
    plan_ = std::move(previous_plan);
    throw;
  }
  carry_results(std::move(previous_plan), std::move(previous), picture_may_stand);
}

bool Executor::picture_standing() const {
  return realized_ && realized_->standing.has_value();
}

std::set<std::filesystem::path> Executor::shader_files() const {
  std::set<std::filesystem::path> files;
  if (realized_) {
    for (const auto& pass_files : realized_->shader_files) files.insert(pass_files.begin(), pass_files.end());
  }
  return files;
}

std::vector<bool> Executor::stale_passes(const Plan& plan, const Realized& realized, const std::set<std::filesystem::path>& edited) const {
  std::vector<bool> stale(plan.passes.size(), false);
  std::set<uint32_t> recomputed;  // resources of `plan`
  for (size_t j = 0; j < plan.passes.size(); ++j) {
    const PlannedPass& pass = plan.passes[j];
    const auto& files = realized.shader_files[j];
    bool edited_or_reads = std::any_of(files.begin(), files.end(), [&](const std::filesystem::path& f) { return edited.count(f) != 0; });
    for (const auto& [port, resource] : pass.ports)
      edited_or_reads = edited_or_reads || (pass.decl->find_port(port)->access != PortAccess::write && recomputed.count(resource));
    if (!edited_or_reads) continue;
    stale[j] = true;
    for (const auto& [port, resource] : pass.ports) {
      if (pass.decl->find_port(port)->access != PortAccess::read) recomputed.insert(resource);
    }
  }
  return stale;
}

void Executor::carry_running_results(const Plan& before, Realized& realized_before, const std::vector<bool>& stale) {
  constexpr size_t kParkedRunning = 8;
  Realized& real = *realized_;
  real.reset_keys.resize(plan_->passes.size());
  real.pass_frames.resize(plan_->passes.size());
  real.converging.resize(plan_->passes.size());
  // Those of the plan before that have a running result to hand on (a plan that never ran has the
  // ones it was given).
  std::vector<RunningResult> offered;
  for (size_t j = 0; j < before.passes.size(); ++j) {
    if (before.passes[j].running_key == 0 || stale[j] || j >= realized_before.reset_keys.size() || !realized_before.reset_keys[j]) {
      continue;
    }
    offered.push_back({before.passes[j].running_key, std::move(realized_before.passes[j]), realized_before.reset_keys[j],
                       realized_before.pass_frames[j], j < realized_before.converging.size() && realized_before.converging[j]});
  }
  for (size_t i = 0; i < plan_->passes.size(); ++i) {
    const uint64_t key = plan_->passes[i].running_key;
    if (key == 0) continue;
    auto taken = [&](std::vector<RunningResult>& from) {
      const auto found = std::find_if(from.begin(), from.end(), [&](const RunningResult& r) { return r.running_key == key; });
      if (found == from.end()) return false;
      real.passes[i]->continue_from(*found->pass);
      real.reset_keys[i] = found->reset_key;
      real.pass_frames[i] = found->frames;
      real.converging[i] = found->converging;
      from.erase(found);
      return true;
    };
    if (!taken(offered)) taken(parked_running_);
  }
  for (auto& result : offered) parked_running_.push_back(std::move(result));
  if (parked_running_.size() > kParkedRunning) {
    parked_running_.erase(parked_running_.begin(), parked_running_.end() - static_cast<std::ptrdiff_t>(kParkedRunning));
  }
}

void Executor::carry_results(std::unique_ptr<const Plan> before, std::unique_ptr<Realized> realized_before, bool picture_may_stand) {
  const bool carry = std::exchange(carry_results_, true);
  const std::set<std::filesystem::path> edited = std::exchange(edited_shaders_, {});
  // A parked result may come from a shader saved since; invalidate() starts everything over.
  if (!carry || !edited.empty()) parked_running_.clear();
  const bool both_reuse = before && before->reuses_unchanged_passes && plan_->reuses_unchanged_passes;
  if (carry && both_reuse) carry_running_results(*before, *realized_before, stale_passes(*before, *realized_before, edited));
  // A plan replaced before its first frame (two edits between frames) has no results of its own:
  // what it was to carry over comes from the plan before it.
  if (realized_before && realized_before->frame_index == 0 && carried_.realized) {
    for (const auto& [from, to] : carried_.handed) swap_image(*carried_.realized, from, *realized_before, to);  // handed back
    before = std::move(carried_.plan);
    realized_before = std::move(carried_.realized);
  }
  carried_ = {};
  if (!carry || !both_reuse || realized_before->frame_index == 0) return;
  const std::vector<bool> stale = stale_passes(*before, *realized_before, edited);
  // Result key, or showing key -> the pass that has it, where it ran.
  std::map<uint64_t, size_t> ran_before, shown_before;
  for (size_t j = 0; j < before->passes.size(); ++j) {
    const PlannedPass& pass = before->passes[j];
    if (stale[j] || j >= realized_before->reset_keys.size() || !realized_before->reset_keys[j]) continue;
    if (pass.result_key != 0) ran_before[pass.result_key] = j;
    if (pass.showing_key != 0) shown_before[pass.showing_key] = j;
  }
  auto carried_from = [&](const PlannedPass& pass) -> std::optional<size_t> {
    if (const auto found = ran_before.find(pass.result_key); pass.result_key != 0 && found != ran_before.end()) return found->second;
    if (const auto found = shown_before.find(pass.showing_key); pass.showing_key != 0 && found != shown_before.end()) return found->second;
    return std::nullopt;
  };
  Realized& real = *realized_;
  real.reset_keys.resize(plan_->passes.size());
  real.pass_frames.resize(plan_->passes.size());
  for (size_t i = 0; i < plan_->passes.size(); ++i) {
    const PlannedPass& pass = plan_->passes[i];
    const std::optional<size_t> from = carried_from(pass);
    if (!from) continue;
    const PlannedPass& was = before->passes[*from];
    std::vector<std::pair<uint32_t, uint32_t>> images;
    bool images_only = true;
    for (const auto& [port, resource] : pass.ports) {
      if (pass.decl->find_port(port)->access == PortAccess::read) continue;
      images_only &= plan_->resources[resource].kind == ResourceKind::image;
      images.emplace_back(was.ports.at(port), resource);
    }
    if (!images_only) continue;  // a result in a buffer is computed again
    for (const auto& image : images) {
      // A resource that several carried passes write (one rewriting another's) is carried once.
      auto& handed = carried_.handed;
      if (carried_.carries_from(image.first) || carried_.carries_to(image.second)) continue;
      // The image itself, where the plans describe it alike and it has memory of its own: nothing to
      // copy (about 0.1 s of copies at 1280x720 on lavapipe, for a still level's step).
      if (same_own_image(before->resources[image.first], plan_->resources[image.second])) {
        swap_image(*realized_before, image.first, real, image.second);
        handed.push_back(image);
      } else {
        carried_.images.push_back(image);
      }
    }
    real.reset_keys[i] = realized_before->reset_keys[*from];
    real.pass_frames[i] = realized_before->pass_frames[*from];
    for (const auto& [counter, owner] : realized_before->counter_passes) {
      if (owner == pass.name) real.last_counters[counter] = realized_before->last_counters[counter];
    }
  }
  if (picture_may_stand && plan_->refines_apart) stand_picture(*before, *realized_before);
  if (carried_.images.empty() && carried_.handed.empty()) return;
  carried_.plan = std::move(before);
  carried_.realized = std::move(realized_before);
}

bool Executor::Carried::carries_from(uint32_t from) const {
  const auto is_from = [&](const auto& pair) { return pair.first == from; };
  return std::any_of(handed.begin(), handed.end(), is_from) || std::any_of(images.begin(), images.end(), is_from);
}

bool Executor::Carried::carries_to(uint32_t to) const {
  const auto is_to = [&](const auto& pair) { return pair.second == to; };
  return std::any_of(handed.begin(), handed.end(), is_to) || std::any_of(images.begin(), images.end(), is_to);
}

void Executor::stand_picture(const Plan& before, Realized& realized_before) {
  Realized& real = *realized_;
  const auto outputs_carried = [&] {
    return std::all_of(plan_->outputs.begin(), plan_->outputs.end(), [&](uint32_t output) { return carried_.carries_to(output); });
  };
  if (outputs_carried()) return;  // the showing passes carried theirs: no picture to stand in
  for (size_t i = 0; i < plan_->passes.size(); ++i) {
    const PlannedPass& pass = plan_->passes[i];
    if (pass.refines || real.reset_keys[i]) continue;  // refining, or its results carried over
    for (const auto& [port, resource] : pass.ports) {
      if (pass.decl->find_port(port)->access == PortAccess::read || carried_.carries_to(resource)) continue;
      const int was = before.find_resource(plan_->resources[resource].name);
      if (was < 0) continue;
      const auto from = static_cast<uint32_t>(was);
      if (!same_own_image(before.resources[from], plan_->resources[resource]) || carried_.carries_from(from)) continue;
      swap_image(realized_before, from, real, resource);
      carried_.handed.emplace_back(from, resource);
    }
  }
  if (outputs_carried()) real.standing = realized_before.standing ? *realized_before.standing : realized_before.parts_now;
}

void Executor::swap_image(Realized& a, uint32_t ia, Realized& b, uint32_t ib) {
  std::swap(a.images[ia], b.images[ib]);
  std::swap(a.dedicated[ia], b.dedicated[ib]);
}

void Executor::record_carried(VkCommandBuffer cmd) {
  if (carried_.images.empty() && carried_.handed.empty()) return;
  std::vector<VkImageMemoryBarrier2> before, after;
  // A handed image goes on from where the plan before left it (kept_images_to_final_layouts skips it).
  for (const auto& [from, to] : carried_.handed) {
    const PlannedResource& was = carried_.plan->resources[from];
    const PlannedResource& res = plan_->resources[to];
    after.push_back(whole_image_barrier(realized_->images[to].image.get(), res, was.final_state.stages, was.final_state.access,
                                        VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT,
                                        was.final_state.layout, res.final_state.layout));
  }
  for (const auto& [from, to] : carried_.images) {
    const PlannedResource& was = carried_.plan->resources[from];
    const PlannedResource& res = plan_->resources[to];
    before.push_back(whole_image_barrier(carried_.realized->images[from].image.get(), was, was.final_state.stages, was.final_state.access,
                                         VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT, was.final_state.layout,
                                         VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL));
    // After kept_images_to_final_layouts' transition of it; overwritten whole.
    before.push_back(whole_image_barrier(realized_->images[to].image.get(), res, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                                         VK_ACCESS_2_MEMORY_WRITE_BIT, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                                         VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL));
    after.push_back(whole_image_barrier(realized_->images[to].image.get(), res, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                                        VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                                        VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                                        res.final_state.layout));
  }
  vk_.begin_label(cmd, "carried results");
  pipeline_barrier(cmd, before);
  for (const auto& [from, to] : carried_.images) {
    copy_whole_image(cmd, plan_->resources[to], carried_.realized->images[from].image.get(), realized_->images[to].image.get());
  }
  pipeline_barrier(cmd, after);
  vk_.end_label(cmd);
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
      view_info.viewType = res.layers > 1 ? VK_IMAGE_VIEW_TYPE_2D_ARRAY : VK_IMAGE_VIEW_TYPE_2D;
      view_info.format = create.format;
      view_info.subresourceRange = {aspect_of(res.format), 0, res.mips, 0, res.layers};
      VkImageView view = VK_NULL_HANDLE;
      vk::check(vkCreateImageView(device, &view_info, nullptr, &view), "vkCreateImageView");
      real.images[i].view = vk::OwnedImageView(vk_, view);
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

void Executor::record_barriers(VkCommandBuffer cmd, const std::vector<PlannedBarrier>& barriers) const {
  if (barriers.empty()) return;
  std::vector<VkImageMemoryBarrier2> images;
  std::vector<VkBufferMemoryBarrier2> buffers;
  for (const auto& b : barriers) {
    const PlannedResource& res = plan_->resources[b.resource];
    if (res.kind == ResourceKind::image) {
      images.push_back(whole_image_barrier(realized_->images[b.resource].image.get(), res, b.src_stages, b.src_access, b.dst_stages,
                                           b.dst_access, b.old_layout, b.new_layout));
    } else {
      VkBufferMemoryBarrier2 bb{VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER_2};
      bb.srcStageMask = b.src_stages;
      bb.srcAccessMask = b.src_access;
      bb.dstStageMask = b.dst_stages;
      bb.dstAccessMask = b.dst_access;
      bb.srcQueueFamilyIndex = bb.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
      bb.buffer = realized_->buffers[b.resource].buffer.get();
      bb.size = VK_WHOLE_SIZE;
      buffers.push_back(bb);
    }
  }
  pipeline_barrier(cmd, images, buffers);
}

void Executor::record_history(VkCommandBuffer cmd) {
  Realized& real = *realized_;
  const Plan& p = *plan_;
  std::vector<PlannedBarrier> before, after;
  std::vector<std::pair<uint32_t, bool>> fills;  // history resource, and whether it restarts (zeros) or copies
  for (uint32_t h = 0; h < p.resources.size(); ++h) {
    const PlannedResource& history = p.resources[h];
    if (history.previous_of == kNoResource || !history.used()) continue;
    const uint32_t d = history.history_depends;
    const uint64_t key = scene_ ? scene_->parts_key(d & kDependsOnGeometry, d & kDependsOnLights, d & kDependsOnCamera) : 0;
    const auto last = real.history_keys.find(h);
    const bool restart = last == real.history_keys.end() || last->second != key;
    real.history_keys[h] = key;
    fills.emplace_back(h, restart);
    const bool image = history.kind == ResourceKind::image;
    const VkImageLayout dst_layout = image ? VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL : VK_IMAGE_LAYOUT_UNDEFINED;
    const VkImageLayout src_layout = image ? VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL : VK_IMAGE_LAYOUT_UNDEFINED;
    const AccessState& was = history.final_state;
    // Its old contents are overwritten whole: from "undefined".
    before.push_back({h, was.stages, was.access, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                      VK_IMAGE_LAYOUT_UNDEFINED, dst_layout, false});
    after.push_back({h, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                     VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT, dst_layout, was.layout, false});
    if (restart) continue;
    const AccessState& source = p.resources[history.previous_of].final_state;
    before.push_back({history.previous_of, source.stages, source.access, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                      VK_ACCESS_2_TRANSFER_READ_BIT, source.layout, src_layout, false});
    after.push_back({history.previous_of, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_NONE, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                     VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT, src_layout, source.layout, false});
  }
  if (fills.empty()) return;
  vk_.begin_label(cmd, "history");
  record_barriers(cmd, before);
  for (const auto& [h, restart] : fills) {
    const PlannedResource& history = p.resources[h];
    if (history.kind == ResourceKind::buffer) {
      const VkBuffer to = real.buffers[h].buffer.get();
      if (restart)
        vkCmdFillBuffer(cmd, to, 0, VK_WHOLE_SIZE, 0);
      else
        vkCmdCopyBuffer(cmd, real.buffers[history.previous_of].buffer.get(), to, 1, std::array{VkBufferCopy{0, 0, history.buffer_size}}.data());
      continue;
    }
    const VkImage to = real.images[h].image.get();
    const VkImageSubresourceRange all{aspect_of(history.format), 0, history.mips, 0, history.layers};
    if (restart && format_info(history.format).depth) {
      const VkClearDepthStencilValue zero{};
      vkCmdClearDepthStencilImage(cmd, to, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &zero, 1, &all);
    } else if (restart) {
      const VkClearColorValue zero{};
      vkCmdClearColorImage(cmd, to, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &zero, 1, &all);
    } else {
      copy_whole_image(cmd, history, real.images[history.previous_of].image.get(), to);
    }
  }
  record_barriers(cmd, after);
  vk_.end_label(cmd);
}

FrameResult Executor::run_frame(bool read_back, FramePart part, DisplayStep step) {
  assert(plan_ && "configure() before run_frame()");
  Realized& real = *realized_;
  const Plan& p = *plan_;
  VkCommandBuffer cmd = real.cmd;
  FrameResult result;
  const auto frame_start = Clock::now();
  const uint64_t submission = vk_.begin_submission();
  if (scene_) scene_->update_frame(p.output_width, p.output_height);
  real.reset_keys.resize(p.passes.size());
  real.pass_frames.resize(p.passes.size());
  real.converging.resize(p.passes.size());
  real.parts_at_last_run.resize(p.passes.size());
  real.frames_held.resize(p.passes.size());
  if (scene_)
    real.parts_now = {scene_->parts_key(true, false, false), scene_->parts_key(false, true, false), scene_->parts_key(false, false, true)};
  std::vector<uint64_t> keys(p.passes.size(), 0);
  for (size_t i = 0; i < p.passes.size(); ++i) {
    const uint32_t depends = p.passes[i].depends;
    if (scene_) keys[i] = scene_->parts_key(depends & kDependsOnGeometry, depends & kDependsOnLights, depends & kDependsOnCamera);
  }
  auto in_part = [&](size_t i) {
    if (part == FramePart::whole) return true;
    if (part == FramePart::refine) return p.passes[i].refines;
    return !p.passes[i].refines && p.passes[i].showing >= step.first && p.passes[i].showing < step.last;
  };
  if (!p.refines_apart) part = FramePart::whole;
  // While the picture of the plan before stands for this scene, a showing pass that has not run yet
  // waits for its display step; one that a step would need before it has to run now.
  const bool picture_stands = real.standing == real.parts_now;
  const auto waits = [&](size_t i) {
    return picture_stands && !real.reset_keys[i] && !p.passes[i].refines && (part == FramePart::refine || p.passes[i].showing >= step.last);
  };
  for (size_t i = 0; i < p.passes.size() && part != FramePart::whole; ++i) {
    if (!in_part(i) && real.reset_keys[i] != keys[i] && !waits(i)) part = FramePart::whole;
  }
  result.part = part;
  glm::vec2 camera_jitter(0.0f);
  if (scene_ && p.jitters_camera && part != FramePart::display) {
    // Counted from the scene's last change (the camera, a light, the geometry), so that the first
    // frame after any change is a fresh render's.
    const uint64_t key = scene_->parts_key(true, true, true);
    if (real.jitter_key != key) {
      real.jitter_key = key;
      real.jittered_frames = 0;
    }
    camera_jitter = r2_point(real.jittered_frames++) - 0.5f;
    scene_->jitter_camera(camera_jitter);
  }
  real.host_counters.clear();

  vk::check(vkResetCommandBuffer(cmd, 0), "vkResetCommandBuffer");
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  vk::check(vkBeginCommandBuffer(cmd, &begin), "vkBeginCommandBuffer");
  vkCmdResetQueryPool(cmd, real.queries.get(), 0, real.query_count);
  uint32_t next_query = 0;
  auto stamp = [&]() {
    uint32_t index = next_query;
    vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, real.queries.get(), next_query++);
    vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, real.queries.get(), next_query++);  // the dummy
    return index;
  };

  vkCmdFillBuffer(cmd, real.counters.get(), 0, VK_WHOLE_SIZE, 0);
  VkMemoryBarrier2 counters_ready{VK_STRUCTURE_TYPE_MEMORY_BARRIER_2};
  counters_ready.srcStageMask = VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT;
  counters_ready.srcAccessMask = VK_ACCESS_2_TRANSFER_WRITE_BIT;
  counters_ready.dstStageMask = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT;
  counters_ready.dstAccessMask = VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;
  VkDependencyInfo counters_dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
  counters_dep.memoryBarrierCount = 1;
  counters_dep.pMemoryBarriers = &counters_ready;
  vkCmdPipelineBarrier2(cmd, &counters_dep);

  if (real.frame_index == 0) {
    std::vector<PlannedBarrier> kept = kept_images_to_final_layouts(p);
    std::erase_if(kept, [&](const PlannedBarrier& b) {
      return std::any_of(carried_.handed.begin(), carried_.handed.end(), [&](const auto& handed) { return handed.second == b.resource; });
    });
    record_barriers(cmd, kept);
    record_carried(cmd);
  }
  const uint32_t frame_begin = stamp();
  record_history(cmd);
  std::vector<std::pair<uint32_t, uint32_t>> pass_stamps;
  std::set<std::string> skipped;
  for (size_t i = 0; i < p.passes.size(); ++i) {
    const PlannedPass& pass = p.passes[i];
    const auto pass_start = Clock::now();
    vk_.begin_label(cmd, pass.name);
    uint32_t start = stamp();  // a pass's barriers count as part of its cost
    record_barriers(cmd, pass.barriers);
    const uint64_t key = keys[i];
    // What a pass's history (an accumulated mean, a jitter sequence) follows: a change of anything
    // it depends on restarts it, and nothing else does (a camera move leaves light-space history).
    FrameInfo& pass_frame = real.pass_frames[i];
    pass_frame.index = real.frame_index;
    pass_frame.camera_jitter = camera_jitter;
    // The same key decides a reusable pass's skip: it ran when its key last changed, and every
    // frame since has left its result as it was.
    const bool changed = real.reset_keys[i] != key;
    if (changed && in_part(i)) {
      real.reset_keys[i] = key;
      pass_frame.since_reset = 0;
    }
    const bool run = in_part(i) && (changed || !pass.reusable(p.reuses_unchanged_passes));
    if (run) {
      real.recording = &pass_frame;
      real.recording_pass = i;
      real.converging[i] = false;
      real.frames_held[i].reset();
      real.recording_params = &pass.params;
      if (!pass.frame_params.empty()) {
        real.frame_params.resize(p.passes.size());
        real.frame_params[i] = params_for_frame(p, pass, pass_frame);
        real.recording_params = &real.frame_params[i];
      }
      PassContext context(*this, pass, cmd);
      real.passes[i]->execute(context);
      real.parts_at_last_run[i] = real.parts_now;
    } else {
      skipped.insert(pass.name);
    }
    uint32_t end = stamp();
    vk_.end_label(cmd);
    pass_stamps.emplace_back(start, end);
    result.passes.push_back(
        {pass.name, 0, ms_since(pass_start), 0, std::chrono::duration<double, std::milli>(pass_start - frame_start).count(), run});
  }
  const uint32_t frame_end = stamp();
  if (real.standing && std::all_of(real.reset_keys.begin(), real.reset_keys.end(), [](const auto& k) { return k.has_value(); }))
    real.standing.reset();  // every pass has run: the picture is this plan's

  if (read_back) {
    std::vector<PlannedBarrier> to_transfer;
    for (const auto& rb : real.readbacks) {
      const PlannedResource& res = p.resources[rb.resource];
      to_transfer.push_back({rb.resource, res.final_state.stages, res.final_state.access, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                             VK_ACCESS_2_TRANSFER_READ_BIT, res.final_state.layout,
                             res.kind == ResourceKind::image ? VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL : VK_IMAGE_LAYOUT_UNDEFINED, false});
    }
    vk_.begin_label(cmd, "read back");
    record_barriers(cmd, to_transfer);
    for (const auto& rb : real.readbacks) {
      const PlannedResource& res = p.resources[rb.resource];
      if (res.kind == ResourceKind::image) {
        VkBufferImageCopy copy{};
        copy.imageSubresource = {aspect_of(res.format), 0, 0, res.layers};
        copy.imageExtent = {res.width, res.height, 1};
        vkCmdCopyImageToBuffer(cmd, real.images[rb.resource].image.get(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, rb.buffer.get(), 1, &copy);
      } else {
        VkBufferCopy copy{0, 0, rb.bytes};
        vkCmdCopyBuffer(cmd, real.buffers[rb.resource].buffer.get(), rb.buffer.get(), 1, &copy);
      }
    }
    // A skipped pass or a history input finds its images where the last frame left them.
    record_barriers(cmd, back_from_transfer(p, to_transfer));
    vk_.end_label(cmd);
  }
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_WRITE_BIT, VK_PIPELINE_STAGE_2_HOST_BIT,
                     VK_ACCESS_2_HOST_READ_BIT);
  vk::check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");

  VkCommandBufferSubmitInfo cmd_submit{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
  cmd_submit.commandBuffer = cmd;
  VkSubmitInfo2 submit{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
  submit.commandBufferInfoCount = 1;
  submit.pCommandBufferInfos = &cmd_submit;
  vk::check(vkQueueSubmit2(vk_.queue(), 1, &submit, real.fence.get()), "vkQueueSubmit2");
  result.cpu_ms = ms_since(frame_start);

  // A lost device or a hung GPU ends the frame with an error instead of waiting forever. A plan's
  // first frame gets longer: lavapipe compiles each pipeline with LLVM when it first runs, and the
  // ray-query kernels from a cold shader cache took more than two minutes (full_hybrid at 640x360).
  const uint64_t timeout_s = real.frame_index == 0 ? 900 : 120;
  VkFence fence = real.fence.get();
  VkResult waited = vk_.frame_result(vkWaitForFences(vk_.device(), 1, &fence, VK_TRUE, timeout_s * 1000 * 1000 * 1000));
  if (waited == VK_TIMEOUT) throw DeviceError("frame did not finish within " + std::to_string(timeout_s) + " s (VK_TIMEOUT)");
  vk::check(waited, "vkWaitForFences");
  vk::check(vkResetFences(vk_.device(), 1, &fence), "vkResetFences");
  vk_.retire(submission);
  carried_ = {};  // copied and handed over: the plan before can go

  std::vector<uint64_t> stamps(real.query_count);
  vk::check(vkGetQueryPoolResults(vk_.device(), real.queries.get(), 0, next_query, stamps.size() * sizeof(uint64_t), stamps.data(),
                                  sizeof(uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
            "vkGetQueryPoolResults");
  const double period_ms = static_cast<double>(vk_.properties().limits.timestampPeriod) * 1e-6;
  const uint64_t mask = vk_.timestamp_valid_bits() >= 64 ? ~0ull : (1ull << vk_.timestamp_valid_bits()) - 1;
  auto elapsed = [&](uint32_t a, uint32_t b) { return static_cast<double>((stamps[b] - stamps[a]) & mask) * period_ms; };
  result.gpu_ms = elapsed(frame_begin, frame_end);
  for (size_t i = 0; i < pass_stamps.size(); ++i) {
    result.passes[i].gpu_ms = elapsed(pass_stamps[i].first, pass_stamps[i].second);
    result.passes[i].gpu_start_ms = elapsed(frame_begin, pass_stamps[i].first);
  }
  for (size_t c = 0; c < real.counter_names.size(); ++c) {
    const std::string& name = real.counter_names[c];
    if (skipped.count(real.counter_passes[name])) {
      result.counters[name] = real.last_counters[name];
      continue;
    }
    if (auto host = real.host_counters.find(static_cast<uint32_t>(c)); host != real.host_counters.end()) {
      result.counters[real.counter_names[c]] = host->second;
      continue;
    }
    const auto* slot = static_cast<const unsigned char*>(real.counters.mapped) + c * sizeof(uint32_t);
    if (real.counter_is_sum[c]) {
      float sum;
      std::memcpy(&sum, slot, sizeof(sum));  // the zero fill is 0.0f too
      result.counters[real.counter_names[c]] = static_cast<double>(sum);
    } else {
      uint32_t count;
      std::memcpy(&count, slot, sizeof(count));
      result.counters[real.counter_names[c]] = count;
    }
  }
  result.counter_passes = real.counter_passes;
  result.converging = std::find(real.converging.begin(), real.converging.end(), true) != real.converging.end();
  real.last_counters = result.counters;
  real.read_back_done = read_back;
  result.frame = {real.frame_index, real.frame_index};
  // A pass outside the frame's part stays where it was: the next frame it runs is its next one (a
  // slice of a photon grid, a jitter). A frame apart counts the frames of the running results: a
  // display frame shows them as the last refining frame left them.
  for (size_t i = 0; i < p.passes.size(); ++i) {
    FrameInfo& f = real.pass_frames[i];
    if (part == FramePart::whole || p.passes[i].refines) {
      const uint64_t shown = part == FramePart::display && f.since_reset > 0 ? f.since_reset - 1 : f.since_reset;
      result.frame.since_reset = std::min(result.frame.since_reset, shown);
    }
    if (in_part(i)) ++f.since_reset;
    if (p.passes[i].decl->accumulates) {
      const uint64_t held = real.frames_held[i] ? std::min(*real.frames_held[i], f.since_reset) : f.since_reset;
      result.accumulated = result.accumulated == 0 ? held : std::min(result.accumulated, held);
    }
  }
  ++real.frame_index;
  return result;
}

FrameImage Executor::frame_image(const std::string& name) const {
  const int index = plan_->find_resource(plan_->resolve(name));
  if (index < 0 || plan_->resources[static_cast<size_t>(index)].kind != ResourceKind::image ||
      plan_->resources[static_cast<size_t>(index)].transient || !plan_->resources[static_cast<size_t>(index)].used()) {
    throw InputError("'" + name + "' is not an image output or a retained image of graph " + plan_->graph_path);
  }
  const PlannedResource& res = plan_->resources[static_cast<size_t>(index)];
  // A frame that read back left every read-back image ready for a copy (unless it is kept across
  // frames: then back in its final layout).
  const VkImageLayout layout =
      realized_->read_back_done && !res.kept_across_frames ? VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL : res.final_state.layout;
  return {realized_->images[static_cast<size_t>(index)].image.get(), layout, res.format, {res.width, res.height}};
}

io::ImageData Executor::read_image(const std::string& name) const {
  const int index = plan_->find_resource(plan_->resolve(name));
  const auto& real = *realized_;
  auto rb = std::find_if(real.readbacks.begin(), real.readbacks.end(),
                         [&](const Realized::Readback& r) { return static_cast<int>(r.resource) == index; });
  if (index < 0 || rb == real.readbacks.end() || plan_->resources[static_cast<size_t>(index)].kind != ResourceKind::image) {
    throw InputError("'" + name + "' is not an image output or a retained image of graph " + plan_->graph_path);
  }
  if (!real.read_back_done) throw DeviceError("read_image('" + name + "') before a frame that read back");
  const PlannedResource& res = plan_->resources[static_cast<size_t>(index)];
  io::ImageData image;
  image.width = res.width;
  image.height = res.height;
  const size_t texels = size_t{res.width} * res.height;
  image.rgba.assign(texels * 4, 0.0f);
  const auto* bytes = static_cast<const uint8_t*>(rb->buffer.mapped);
  const FormatInfo& info = format_info(res.format);
  for (size_t t = 0; t < texels; ++t) {
    float* out = &image.rgba[t * 4];
    const uint8_t* in = bytes + t * info.bytes_per_texel;
    auto f32 = [&](int c) {
      float v;
      std::memcpy(&v, in + 4 * c, 4);
      return v;
    };
    auto f16 = [&](int c) {
      uint16_t h;
      std::memcpy(&h, in + 2 * c, 2);
      return io::half_to_float(h);
    };
    switch (res.format) {
      case Format::rgba8:
      case Format::rgba8_srgb:
        for (int c = 0; c < 4; ++c) out[c] = static_cast<float>(in[c]) / 255.0f;
        break;
      case Format::rgba16f:
        for (int c = 0; c < 4; ++c) out[c] = f16(c);
        break;
      case Format::rgba32f:
        for (int c = 0; c < 4; ++c) out[c] = f32(c);
        break;
      case Format::r16f:
        out[0] = out[1] = out[2] = f16(0);
        out[3] = 1;
        break;
      case Format::rg16f:
        out[0] = f16(0);
        out[1] = f16(1);
        out[3] = 1;
        break;
      case Format::r32f:
      case Format::d32f:
        if (res.layers > 1) {  // layer k is channel k (see kMaxImageLayers; only r32f has layers)
          for (uint32_t layer = 0; layer < res.layers; ++layer) {
            std::memcpy(&out[layer], bytes + (layer * texels + t) * info.bytes_per_texel, 4);
          }
          if (res.layers < 4) out[3] = 1;
          break;
        }
        out[0] = out[1] = out[2] = f32(0);
        out[3] = 1;
        break;
      case Format::rg32f:
        out[0] = f32(0);
        out[1] = f32(1);
        out[3] = 1;
        break;
      case Format::r32ui: {
        uint32_t v;
        std::memcpy(&v, in, 4);
        out[0] = out[1] = out[2] = static_cast<float>(v);
        out[3] = 1;
        break;
      }
    }
  }
  image.display_encoded = res.format == Format::rgba8 || res.format == Format::rgba8_srgb;
  return image;
}

}  // namespace caustica::graph
