#pragma once
// The executor's Vulkan side of a plan, shared by the files that implement Executor and the pass
// interfaces (PassSetup, PassContext). Not for anything outside engine/graph.
#include <array>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "graph/executor.h"
#include "graph/run_policy.h"
#include "vk/buffer.h"
#include "vk/owned.h"

namespace caustica::graph {

inline constexpr uint32_t kMaxCounters = 256;

struct Executor::RealImage {
  vk::OwnedImage image;
  vk::OwnedImageView view;                      // every layer: 2D, or 2D array where it has more than one
  vk::OwnedImageView array_view;                // a one-layer image as a 2D array (a shader's array of light maps)
  std::vector<vk::OwnedImageView> layer_views;  // a layered image's layers, each 2D (render targets)
};

struct Executor::RealBuffer {
  vk::OwnedBuffer buffer;
};

struct Executor::Realized {
  std::vector<vk::OwnedMemory> blocks;
  std::vector<vk::OwnedMemory> dedicated;  // by resource index: a persistent resource's own allocation
  std::vector<RealImage> images;           // by resource index (empty for buffers and unused resources)
  std::vector<RealBuffer> buffers;         // by resource index
  struct Readback {
    uint32_t resource;
    vk::Buffer buffer;
    uint64_t bytes = 0;
  };
  std::vector<Readback> readbacks;
  std::vector<std::unique_ptr<Pass>> passes;
  // Each pass counts in slots of its own, so that a counter several passes count under one name
  // sums what each last counted, whichever of them ran this frame.
  struct CounterSlot {
    std::string name;
    size_t pass = 0;
    bool is_sum = false;
    double value = 0;  // as its pass last left it
  };
  std::vector<CounterSlot> counter_slots;
  std::map<uint32_t, double> host_counters;  // by slot, set while recording this frame (PassContext::set_counter)
  vk::Buffer counters;                       // host-visible, uint32 each
  // Host-visible, a uint32 per pass set to 1 once the pass has finished this frame: what a frame
  // that did not finish says about where it stopped. Timestamps cannot say it: lavapipe's
  // vkGetQueryPoolResults waits for the frame even without VK_QUERY_RESULT_WAIT_BIT.
  vk::Buffer finished;
  vk::OwnedSampler linear;
  vk::OwnedSampler nearest;
  vk::OwnedCommandPool pool;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  vk::OwnedFence fence;
  vk::OwnedQueryPool queries;
  uint32_t query_count = 0;
  bool read_back_done = false;
  // What the run policy reads and updates (run_policy.h), and this frame's scene.
  RunState run;
  std::optional<SceneKeys> scene_now;
  size_t recording_pass = 0;
  const nlohmann::json* recording_params = nullptr;  // the pass being recorded's parameters for this frame
  std::vector<nlohmann::json> frame_params;          // per pass with PlannedPass::frame_params
  // Per pass: the shader files (and includes) it was set up with.
  std::vector<std::vector<std::filesystem::path>> shader_files;
};

// ---- Shared by the executor's files (executor_record.cpp) --------------------------------------

VkImageAspectFlags aspect_of(Format format);
// A barrier on all of `res`'s image `image`.
VkImageMemoryBarrier2 whole_image_barrier(VkImage image, const PlannedResource& res, VkPipelineStageFlags2 src_stages,
                                          VkAccessFlags2 src_access, VkPipelineStageFlags2 dst_stages, VkAccessFlags2 dst_access,
                                          VkImageLayout old_layout, VkImageLayout new_layout);
void pipeline_barrier(VkCommandBuffer cmd, const std::vector<VkImageMemoryBarrier2>& images,
                      const std::vector<VkBufferMemoryBarrier2>& buffers = {});
// Copies every mip level and layer of `res`'s image `from` (in TRANSFER_SRC_OPTIMAL) to `to` (in
// TRANSFER_DST_OPTIMAL), an image of the same description.
void copy_whole_image(VkCommandBuffer cmd, const PlannedResource& res, VkImage from, VkImage to);
// A frame starts its kept images from the layout the last frame left them in
// (compiler_dependencies.cpp): before the first frame, that layout.
std::vector<PlannedBarrier> kept_images_to_final_layouts(const Plan& plan);
// executor_realize.cpp
VkImageCreateInfo image_info(const PlannedResource& r);
VkBufferCreateInfo buffer_info(const PlannedResource& r);

}  // namespace caustica::graph
