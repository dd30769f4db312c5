// Benchmarks for the frame-graph core, run by hand; results go to docs/benchmarks.md.
//   bench_core compile      compile time of synthetic chains of 10, 100 and 1000 passes (CPU only)
//   bench_core overhead     executor CPU time per frame against the same passes recorded by hand
//   bench_core memory       transient memory with and without aliasing for every bundled graph
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <tuple>
#include <vector>

#include "builtin_passes.h"
#include "core/paths.h"
#include "graph/executor.h"
#include "scene_draw.h"
#include "vk/pipeline.h"

using namespace caustica;
using Clock = std::chrono::steady_clock;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

graph::GraphDesc chain(int passes) {
  nlohmann::json resources = nlohmann::json::object(), list = nlohmann::json::array();
  resources["r0"] = {{"type", "image"}, {"format", "rgba16f"}};
  list.push_back({{"name", "p0"}, {"type", "pattern"}, {"outputs", {{"color", "r0"}}}});
  for (int i = 1; i < passes - 1; ++i) {
    std::string in = "r" + std::to_string(i - 1), out = "r" + std::to_string(i);
    resources[out] = {{"type", "image"}, {"format", "rgba16f"}};
    list.push_back({{"name", "p" + std::to_string(i)}, {"type", "box_blur"}, {"inputs", {{"source", in}}}, {"outputs", {{"target", out}}}});
  }
  resources["out"] = {{"type", "image"}, {"format", "rgba8"}};
  list.push_back({{"name", "tonemap"},
                  {"type", "tonemap"},
                  {"inputs", {{"source", "r" + std::to_string(passes - 2)}}},
                  {"outputs", {{"target", "out"}}}});
  nlohmann::json g = {{"name", "chain"}, {"resources", resources}, {"passes", list}, {"outputs", {"out"}}};
  return graph::load_graph(JsonDocument::parse(g.dump(), "chain" + std::to_string(passes) + ".json"));
}

void bench_compile() {
  std::printf("| passes | compile (median of 9) | per pass |\n|---|---|---|\n");
  for (int n : {10, 100, 1000}) {
    graph::GraphDesc g = chain(n);
    graph::CompileOptions options;
    options.output_width = 1280;
    options.output_height = 720;
    options.memory_limit_bytes = ~0ull;
    std::vector<double> ms;
    for (int i = 0; i < 9; ++i) {
      auto t = Clock::now();
      graph::Plan plan = graph::compile_graph(g, passes::builtin_registry(), options);
      ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t).count());
      if (plan.passes.size() != static_cast<size_t>(n)) std::abort();
    }
    std::printf("| %d | %.3f ms | %.2f us |\n", n, median(ms), median(ms) * 1000.0 / n);
  }
}

// The chain of bench_overhead recorded by hand: the same shaders, pipelines, push constants and
// dispatches, images allocated one by one, barriers written out, no labels and no timestamps. It
// is the baseline the executor's recording cost is measured against.
class HandChain {
 public:
  HandChain(vk::Context& vk, shader::ShaderCompiler& shaders, int passes, uint32_t width, uint32_t height)
      : vk_(vk), width_(width), height_(height) {
    for (int i = 0; i < passes - 1; ++i)
      add_image(VK_FORMAT_R16G16B16A16_SFLOAT,
                VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT);
    add_image(VK_FORMAT_R8G8B8A8_UNORM, VK_IMAGE_USAGE_STORAGE_BIT);
    const shader::ReflectedShader vertex = shaders.compile_reflected("common/fullscreen.vert");
    const shader::ReflectedShader pattern = shaders.compile_reflected("core/pattern.frag");
    const shader::ReflectedShader blur = shaders.compile_reflected("core/box_blur.comp", {{"OUT_FORMAT", "rgba16f"}});
    const shader::ReflectedShader tonemap = shaders.compile_reflected("core/tonemap.comp");
    pattern_ = vk::make_fullscreen_pipeline(
        vk,
        vk::reflected_desc("pattern", "pattern",
                           {{"common/fullscreen.vert", &vertex.reflection}, {"core/pattern.frag", &pattern.reflection}}),
        vertex.spirv, pattern.spirv, {VK_FORMAT_R16G16B16A16_SFLOAT});
    blur_ =
        vk::make_compute_pipeline(vk, vk::reflected_desc("box_blur", "box_blur", {{"core/box_blur.comp", &blur.reflection}}), blur.spirv);
    tonemap_ = vk::make_compute_pipeline(vk, vk::reflected_desc("tonemap", "tonemap", {{"core/tonemap.comp", &tonemap.reflection}}),
                                         tonemap.spirv);
    VkBufferCreateInfo buffer_info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    buffer_info.size = 1024;
    buffer_info.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    VkBuffer buffer = VK_NULL_HANDLE;
    vk::check(vkCreateBuffer(vk.device(), &buffer_info, nullptr, &buffer), "vkCreateBuffer");
    counters_ = vk::OwnedBuffer(vk, buffer);
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(vk.device(), buffer, &req);
    memory_.push_back(vk.allocate(req, 0, "counters"));
    vk::check(vkBindBufferMemory(vk.device(), buffer, memory_.back().get(), 0), "vkBindBufferMemory");
    VkSamplerCreateInfo sampler_info{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    VkSampler sampler = VK_NULL_HANDLE;
    vk::check(vkCreateSampler(vk.device(), &sampler_info, nullptr, &sampler), "vkCreateSampler");
    sampler_ = vk::OwnedSampler(vk, sampler);
    vk::FrameCommands commands = vk::make_frame_commands(vk);
    pool_ = std::move(commands.pool);
    cmd_ = commands.cmd;
    fence_ = std::move(commands.fence);
  }

  // Returns the CPU milliseconds from command-buffer reset to the return of vkQueueSubmit2.
  double run_frame() {
    const auto start = Clock::now();
    const uint64_t submission = vk_.begin_submission();
    vk::check(vkResetCommandBuffer(cmd_, 0), "vkResetCommandBuffer");
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    vk::check(vkBeginCommandBuffer(cmd_, &begin), "vkBeginCommandBuffer");
    vkCmdFillBuffer(cmd_, counters_.get(), 0, VK_WHOLE_SIZE, 0);
    barrier(VK_NULL_HANDLE, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
            VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
            VK_IMAGE_LAYOUT_UNDEFINED);

    barrier(images_[0].get(), VK_PIPELINE_STAGE_2_NONE, 0, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
            VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    const VkExtent2D extent{width_, height_};
    VkRenderingAttachmentInfo color{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    color.imageView = views_[0].get();
    color.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    color.loadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    VkRenderingInfo rendering{VK_STRUCTURE_TYPE_RENDERING_INFO};
    rendering.renderArea = {{0, 0}, extent};
    rendering.layerCount = 1;
    rendering.colorAttachmentCount = 1;
    rendering.pColorAttachments = &color;
    vkCmdBeginRendering(cmd_, &rendering);
    VkViewport viewport{0, 0, static_cast<float>(width_), static_cast<float>(height_), 0, 1};
    VkRect2D scissor{{0, 0}, extent};
    vkCmdSetViewport(cmd_, 0, 1, &viewport);
    vkCmdSetScissor(cmd_, 0, 1, &scissor);
    vkCmdBindPipeline(cmd_, VK_PIPELINE_BIND_POINT_GRAPHICS, pattern_.pipeline.get());
    const float pattern_params[7] = {static_cast<float>(width_), static_cast<float>(height_), 0.7f, 0.3f, 4.0f, 6.0f, 0.08f};
    vkCmdPushConstants(cmd_, pattern_.layout.get(), pattern_.stages, 0, sizeof(pattern_params), pattern_params);
    vkCmdDraw(cmd_, 3, 1, 0, 0);
    vkCmdEndRendering(cmd_);

    for (size_t i = 1; i < images_.size(); ++i) {
      const bool last = i + 1 == images_.size();
      const VkPipelineStageFlags2 src_stage =
          i == 1 ? VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT : VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
      const VkAccessFlags2 src_access = i == 1 ? VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT : VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;
      barrier(images_[i - 1].get(), src_stage, src_access, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT,
              i == 1 ? VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL : VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
      barrier(images_[i].get(), VK_PIPELINE_STAGE_2_NONE, 0, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
              VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL);
      const vk::Pipeline& pipeline = last ? tonemap_ : blur_;
      vkCmdBindPipeline(cmd_, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.pipeline.get());
      vk::DescriptorWriter writer;
      writer.image("source", views_[i - 1].get(), sampler_.get()).image("target", views_[i].get());
      if (last) writer.buffer("Counters", counters_.get());
      writer.push(vk_, cmd_, pipeline);
      const int32_t size[2] = {static_cast<int32_t>(width_), static_cast<int32_t>(height_)};
      if (last) {
        const struct {
          int32_t size[2];
          float exposure;
          uint32_t counter;
        } params{{size[0], size[1]}, 1.0f, 0};
        vkCmdPushConstants(cmd_, pipeline.layout.get(), pipeline.stages, 0, sizeof(params), &params);
      } else {
        const int32_t params[5] = {size[0], size[1], 1, 0, 2};  // the chain's blurs: axis x, radius 2
        vkCmdPushConstants(cmd_, pipeline.layout.get(), pipeline.stages, 0, sizeof(params), params);
      }
      vkCmdDispatch(cmd_, (width_ + 7) / 8, (height_ + 7) / 8, 1);
    }
    vk::check(vkEndCommandBuffer(cmd_), "vkEndCommandBuffer");
    VkCommandBufferSubmitInfo cmd_submit{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
    cmd_submit.commandBuffer = cmd_;
    VkSubmitInfo2 submit{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
    submit.commandBufferInfoCount = 1;
    submit.pCommandBufferInfos = &cmd_submit;
    vk::check(vkQueueSubmit2(vk_.queue(), 1, &submit, fence_.get()), "vkQueueSubmit2");
    const double cpu_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    VkFence fence = fence_.get();
    vk::check(vkWaitForFences(vk_.device(), 1, &fence, VK_TRUE, ~0ull), "vkWaitForFences");
    vk::check(vkResetFences(vk_.device(), 1, &fence), "vkResetFences");
    vk_.retire(submission);
    return cpu_ms;
  }

 private:
  void add_image(VkFormat format, VkImageUsageFlags usage) {
    VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    info.imageType = VK_IMAGE_TYPE_2D;
    info.format = format;
    info.extent = {width_, height_, 1};
    info.mipLevels = info.arrayLayers = 1;
    info.samples = VK_SAMPLE_COUNT_1_BIT;
    info.usage = usage;
    VkImage image = VK_NULL_HANDLE;
    vk::check(vkCreateImage(vk_.device(), &info, nullptr, &image), "vkCreateImage");
    images_.emplace_back(vk_, image);
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(vk_.device(), image, &req);
    memory_.push_back(vk_.allocate(req, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, "hand image"));
    vk::check(vkBindImageMemory(vk_.device(), image, memory_.back().get(), 0), "vkBindImageMemory");
    VkImageViewCreateInfo view_info{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    view_info.image = image;
    view_info.viewType = VK_IMAGE_VIEW_TYPE_2D;
    view_info.format = format;
    view_info.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    VkImageView view = VK_NULL_HANDLE;
    vk::check(vkCreateImageView(vk_.device(), &view_info, nullptr, &view), "vkCreateImageView");
    views_.emplace_back(vk_, view);
  }

  // One barrier on an image, or a global memory barrier when image is null.
  void barrier(VkImage image, VkPipelineStageFlags2 src_stage, VkAccessFlags2 src_access, VkPipelineStageFlags2 dst_stage,
               VkAccessFlags2 dst_access, VkImageLayout old_layout, VkImageLayout new_layout) {
    if (image == VK_NULL_HANDLE)
      passes::memory_barrier(cmd_, src_stage, src_access, dst_stage, dst_access);
    else
      passes::image_barrier(cmd_, image, VK_IMAGE_ASPECT_COLOR_BIT, old_layout, new_layout, src_stage, src_access, dst_stage, dst_access);
  }

  vk::Context& vk_;
  uint32_t width_, height_;
  std::vector<vk::OwnedMemory> memory_;
  std::vector<vk::OwnedImage> images_;
  std::vector<vk::OwnedImageView> views_;
  vk::OwnedBuffer counters_;
  vk::OwnedSampler sampler_;
  vk::Pipeline pattern_, blur_, tonemap_;
  vk::OwnedCommandPool pool_;
  VkCommandBuffer cmd_ = VK_NULL_HANDLE;
  vk::OwnedFence fence_;
};

void bench_overhead(bool validate) {
  // Recording cost per frame (reset to the return of vkQueueSubmit2) of the executor against
  // HandChain, for the same chain. At 8x8 the GPU work is negligible and the figures are pure CPU
  // recording cost; at 1280x720 the executor's extra cost is set against a real frame's wall time.
  vk::Context vk({"", validate, false});
  shader::ShaderCompiler& shaders = shader::process_shader_compiler();
  std::printf(
      "| chain | size | executor: record+submit | by hand: record+submit | extra per frame | frame wall time (executor) | extra / wall "
      "|\n");
  std::printf("|---|---|---|---|---|---|---|\n");
  for (auto [passes, width, height] : {std::tuple{4, 1280u, 720u}, std::tuple{10, 1280u, 720u}, std::tuple{100, 8u, 8u}}) {
    graph::Executor executor(vk, shaders, passes::builtin_registry());
    executor.configure(chain(passes), width, height, {.memory_limit_bytes = ~0ull});
    HandChain hand(vk, shaders, passes, width, height);
    for (int i = 0; i < 5; ++i) {
      executor.run_frame(false);
      hand.run_frame();
    }
    std::vector<double> graph_ms, hand_ms, wall_ms;
    for (int i = 0; i < 31; ++i) {  // interleaved so that machine noise hits both alike
      const auto start = Clock::now();
      graph_ms.push_back(executor.run_frame(false).cpu_ms);
      wall_ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
      hand_ms.push_back(hand.run_frame());
    }
    const double g = median(graph_ms), h = median(hand_ms), w = median(wall_ms);
    std::printf("| %d passes | %ux%u | %.3f ms | %.3f ms | %.3f ms | %.2f ms | %.2f%% |\n", passes, width, height, g, h, g - h, w,
                100.0 * (g - h) / w);
  }
  if (validate && vk.validation_messages() != 0) {
    std::fprintf(stderr, "validation reported %u messages\n", vk.validation_messages());
    std::exit(3);
  }
}

void bench_memory() {
  std::printf(
      "| graph | transient, unaliased | transient, aliased | aliased / unaliased | lifetime bound | aliased / bound |\n"
      "|---|---|---|---|---|---|\n");
  for (const auto& entry : std::filesystem::directory_iterator(data_dir() / "graphs")) {
    if (entry.path().extension() != ".json" || entry.path().filename() == "schema.json") continue;
    graph::GraphDesc g = graph::load_graph_file(entry.path().string());
    graph::CompileOptions options;
    options.output_width = 1280;
    options.output_height = 720;
    options.scene_values = graph::typical_scene_values();
    graph::Plan plan = graph::compile_graph(g, passes::builtin_registry(), options);
    const double mib = 1048576.0, a = static_cast<double>(plan.transient_bytes_aliased) / mib,
                 u = static_cast<double>(plan.transient_bytes_unaliased) / mib,
                 bound = static_cast<double>(plan.transient_bytes_lifetime_bound) / mib;
    std::printf("| %s | %.1f MiB | %.1f MiB | %.3f | %.1f MiB (%.3f) | %.3f |\n", entry.path().filename().c_str(), u, a,
                u > 0 ? a / u : 0.0, bound, u > 0 ? bound / u : 0.0, bound > 0 ? a / bound : 0.0);
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::string what = argc > 1 ? argv[1] : "";
  if (what == "compile")
    bench_compile();
  else if (what == "overhead")
    bench_overhead(argc > 2 && std::string(argv[2]) == "--validate");
  else if (what == "memory")
    bench_memory();
  else {
    std::fprintf(stderr, "usage: bench_core compile | overhead [--validate] | memory\n");
    return 2;
  }
  return 0;
}
