#include "graph/executor.h"

#include <algorithm>
#include <utility>

#include "core/error.h"
#include "graph/executor_internal.h"

namespace caustica::graph {

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
  options.tracer = tracer_from_environment();
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

bool Executor::configure(const GraphDesc& graph, uint32_t width, uint32_t height, const ConfigureOptions& options) {
  std::string key = graph.doc.path() + "\n" + graph.doc.root().dump() + "\n" + std::to_string(width) + "x" + std::to_string(height) + "\n" +
                    std::to_string(options.memory_limit_bytes) + (options.reuse_unchanged_passes ? "\nreuse" : "") +
                    (options.tracer ? std::string("\ntracer ") + tracer_name(*options.tracer) : "");
  for (const auto& p : graph.parameters) key += "\n" + p.decl.name + "=" + p.value.dump();
  for (const auto& r : options.retained) key += "\nretain " + r;
  const auto scene_values = scene_ ? scene_->scene().expression_values() : std::map<std::string, double>{};
  for (const auto& [name, value] : scene_values) key += "\n" + name + "=" + std::to_string(value);
  const bool start_over = options.hand_over.start_over || !options.hand_over.edited_shaders.empty();
  if (plan_ && key == configured_key_ && !start_over) {
    build_tracer_structures(*plan_);  // set_scene() may have replaced the scene
    return false;
  }
  CompileOptions compile = compile_options(width, height);
  compile.retained = options.retained;
  compile.memory_limit_bytes = options.memory_limit_bytes;
  compile.scene_values = scene_values;
  compile.reuse_unchanged_passes = options.reuse_unchanged_passes;
  if (options.tracer) compile.tracer = options.tracer;
  Plan plan = compile_graph(graph, registry_, compile);
  for (const auto& pass : plan.passes) {
    if (pass.decl->needs_scene && !scene_) {
      throw graph.error(pass.pointer, "pass '" + pass.name + "' (" + pass.decl->type + ") draws a scene, and none was given (--scene)");
    }
  }
  build_tracer_structures(plan);
  realize(std::move(plan), options.hand_over);
  configured_key_ = key;
  ++compile_count_;
  return true;
}

void Executor::build_tracer_structures(const Plan& plan) {
  if (plan.tracer == Tracer::ray_query) scene_->acceleration();
  if (plan.tracer == Tracer::compute) scene_->tracer_bvh();
}

void Executor::realize(Plan plan, const HandOverOptions& options) {
  // The previous plan stays whole until the new one is set up, so that a failure (a shader that no
  // longer compiles, memory) leaves it running; its objects are destroyed once the GPU is done.
  std::unique_ptr<const Plan> previous_plan = std::move(plan_);
  std::unique_ptr<Realized> previous = std::move(realized_);
  plan_ = std::make_unique<const Plan>(std::move(plan));
  realized_ = std::make_unique<Realized>();
  realized_->run = initial_run_state(*plan_);
  try {
    realize_passes_and_resources();
  } catch (...) {
    realized_ = std::move(previous);
    plan_ = std::move(previous_plan);
    throw;
  }
  hand_over(std::move(previous_plan), std::move(previous), options);
}

void Executor::hand_over(std::unique_ptr<const Plan> before, std::unique_ptr<Realized> realized_before, const HandOverOptions& options) {
  // A plan replaced before its first frame (two edits between frames) has no images of its own
  // results: they come from the plan before it, which gets back what it handed over. Its running
  // results are those it was handed.
  std::unique_ptr<const Plan> results_plan;
  std::unique_ptr<Realized> results_realized;
  if (realized_before && realized_before->run.frame_index == 0 && carried_.realized) {
    for (const ImageMove& move : carried_.images) {
      if (move.handed) swap_image(*carried_.realized, move.from, *realized_before, move.to);
    }
    results_plan = std::move(carried_.plan);
    results_realized = std::move(carried_.realized);
  }
  carried_ = {};
  std::vector<ResultIdentity> parked;
  for (const RunningResult& r : parked_running_) parked.push_back(r.running_id);
  const PlanRecord running_from{before.get(), realized_before ? &realized_before->run : nullptr,
                                realized_before ? &realized_before->shader_files : nullptr};
  const PlanRecord results_from =
      results_plan ? PlanRecord{results_plan.get(), &results_realized->run, &results_realized->shader_files} : running_from;
  const HandOver h = plan_hand_over(running_from, results_from, parked, *plan_, options);

  Realized& real = *realized_;
  std::vector<bool> parked_taken(parked_running_.size(), false);
  for (size_t i = 0; i < plan_->passes.size(); ++i) {
    if (const auto j = h.continues[i]) {
      real.passes[i]->continue_from(*realized_before->passes[*j]);
      real.run.passes[i] = realized_before->run.passes[*j];
    } else if (const auto k = h.continues_parked[i]) {
      real.passes[i]->continue_from(*parked_running_[*k].pass);
      real.run.passes[i] = parked_running_[*k].state;
      parked_taken[*k] = true;
    }
  }
  if (h.clear_parked) {
    parked_running_.clear();
  } else {
    for (size_t k = parked_taken.size(); k-- > 0;) {
      if (parked_taken[k]) parked_running_.erase(parked_running_.begin() + static_cast<std::ptrdiff_t>(k));
    }
  }
  for (size_t j : h.parks) {
    parked_running_.push_back({*before->passes[j].running_id, std::move(realized_before->passes[j]), realized_before->run.passes[j]});
  }
  constexpr size_t kParkedRunning = 8;  // a few plans' worth: the viewer's still plan comes back after its while_moving plan
  if (parked_running_.size() > kParkedRunning) {
    parked_running_.erase(parked_running_.begin(), parked_running_.end() - static_cast<std::ptrdiff_t>(kParkedRunning));
  }

  const PlanRecord& from = results_from;
  Realized* from_realized = results_plan ? results_realized.get() : realized_before.get();
  for (size_t i = 0; i < plan_->passes.size(); ++i) {
    const auto j = h.takes_result[i];
    if (!j) continue;
    real.run.passes[i].started_from = from.state->passes[*j].started_from;
    real.run.passes[i].frames = from.state->passes[*j].frames;
    for (auto& slot : real.counter_slots) {
      if (slot.pass != i) continue;
      for (const auto& old : from_realized->counter_slots) {
        if (old.pass == *j && old.name == slot.name) slot.value = old.value;
      }
    }
  }
  for (const ImageMove& move : h.images) {
    if (move.handed) swap_image(*from_realized, move.from, real, move.to);
  }
  real.run.standing = h.standing;
  if (h.images.empty()) return;
  carried_.images = h.images;
  carried_.plan = results_plan ? std::move(results_plan) : std::move(before);
  carried_.realized = results_realized ? std::move(results_realized) : std::move(realized_before);
}

void Executor::swap_image(Realized& a, uint32_t ia, Realized& b, uint32_t ib) {
  std::swap(a.images[ia], b.images[ib]);
  std::swap(a.dedicated[ia], b.dedicated[ib]);
}

bool Executor::picture_standing() const {
  return realized_ && realized_->run.standing.has_value();
}

std::set<std::filesystem::path> Executor::shader_files() const {
  std::set<std::filesystem::path> files;
  if (realized_) {
    for (const auto& pass_files : realized_->shader_files) files.insert(pass_files.begin(), pass_files.end());
  }
  return files;
}

void Executor::set_frame_timeout(double seconds, double first_frame_seconds) {
  frame_timeout_s_ = seconds;
  first_frame_timeout_s_ = std::max(seconds, first_frame_seconds);
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

namespace {

// More layers than colour channels (a point light's six cube faces): the layers side by side, each
// single-channel image's value in red, green and blue.
io::ImageData layer_strip(const PlannedResource& res, const uint8_t* bytes) {
  if (res.format != Format::r32f && res.format != Format::d32f) {
    throw InputError("'" + res.name + "' has " + std::to_string(res.layers) + " layers of " + format_info(res.format).name +
                     ", which read back only as r32f or d32f");
  }
  io::ImageData image;
  image.width = res.width * res.layers;
  image.height = res.height;
  image.rgba.assign(size_t{image.width} * image.height * 4, 1.0f);
  for (uint32_t layer = 0; layer < res.layers; ++layer) {
    for (uint32_t y = 0; y < res.height; ++y) {
      for (uint32_t x = 0; x < res.width; ++x) {
        float v = 0;
        std::memcpy(&v, bytes + ((size_t{layer} * res.height + y) * res.width + x) * 4, 4);
        float* out = &image.rgba[(size_t{y} * image.width + layer * res.width + x) * 4];
        out[0] = out[1] = out[2] = v;
      }
    }
  }
  return image;
}

}  // namespace

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
  const auto* bytes = static_cast<const uint8_t*>(rb->buffer.mapped);
  if (res.layers > 4) return layer_strip(res, bytes);
  io::ImageData image;
  image.width = res.width;
  image.height = res.height;
  const size_t texels = size_t{res.width} * res.height;
  image.rgba.assign(texels * 4, 0.0f);
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
      case Format::rg32ui:
      case Format::rgba32ui:
        out[2] = 0;
        out[3] = 1;
        for (int c = 0; c < (res.format == Format::rg32ui ? 2 : 4); ++c) {
          uint32_t v;
          std::memcpy(&v, in + 4 * c, 4);
          out[c] = static_cast<float>(v);
        }
        break;
    }
  }
  image.display_encoded = res.format == Format::rgba8 || res.format == Format::rgba8_srgb;
  return image;
}

}  // namespace caustica::graph
