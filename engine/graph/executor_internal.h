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
#include "vk/buffer.h"
#include "vk/owned.h"

namespace caustica::graph {

inline constexpr uint32_t kMaxCounters = 256;

struct Executor::RealImage {
  vk::OwnedImage image;
  vk::OwnedImageView view;
};

struct Executor::RealBuffer {
  vk::OwnedBuffer buffer;
};

struct Executor::Realized {
  std::vector<vk::OwnedMemory> blocks;
  std::vector<vk::OwnedMemory> dedicated;  // by resource index: a persistent resource's own allocation
  std::vector<RealImage> images;    // by resource index (empty for buffers and unused resources)
  std::vector<RealBuffer> buffers;  // by resource index
  struct Readback {
    uint32_t resource;
    vk::Buffer buffer;
    uint64_t bytes = 0;
  };
  std::vector<Readback> readbacks;
  std::vector<std::unique_ptr<Pass>> passes;
  std::vector<std::string> counter_names;
  std::vector<bool> counter_is_sum;
  std::map<std::string, std::string> counter_passes;
  std::map<uint32_t, double> host_counters;  // set while recording this frame (PassContext::set_counter)
  // Per pass, as it last ran: whether it would change with more frames (PassContext::still_converging),
  // and the frames its running result holds where it said (PassContext::holds_frames).
  std::vector<bool> converging;
  std::vector<std::optional<uint64_t>> frames_held;
  size_t recording_pass = 0;
  vk::Buffer counters;                       // host-visible, uint32 each
  vk::OwnedSampler linear;
  vk::OwnedSampler nearest;
  vk::OwnedCommandPool pool;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  vk::OwnedFence fence;
  vk::OwnedQueryPool queries;
  uint32_t query_count = 0;
  bool read_back_done = false;
  uint64_t frame_index = 0;  // the next frame to run
  // Per pass: its frames since the scene parts it depends on last changed (FrameInfo), and their
  // key then (a pass that reuses is skipped while it holds); each counter's last value, reported
  // again while its pass is skipped.
  std::vector<FrameInfo> pass_frames;
  std::vector<std::optional<uint64_t>> reset_keys;
  // This frame's key of each scene part (kSceneParts), and per pass, those of the frame it last ran
  // in (PassContext::scene_unchanged_since_last_run).
  std::array<uint64_t, 3> parts_now{};
  std::vector<std::optional<std::array<uint64_t, 3>>> parts_at_last_run;
  // While the outputs hold a picture of the plan before (Executor::let_picture_stand): the scene
  // parts it was drawn for.
  std::optional<std::array<uint64_t, 3>> standing;
  std::map<uint32_t, uint64_t> history_keys;  // per history resource: the key of its scene parts at its last restart
  std::optional<uint64_t> jitter_key;  // the scene's key when it last changed (Plan::jitters_camera)
  uint64_t jittered_frames = 0;        // since then
  const FrameInfo* recording = nullptr;  // the pass being recorded's
  const nlohmann::json* recording_params = nullptr;  // and its parameters for this frame
  std::vector<nlohmann::json> frame_params;          // per pass with PlannedPass::frame_params
  std::map<std::string, double> last_counters;
  // Per pass: the shader files (and includes) it was set up with.
  std::vector<std::vector<std::filesystem::path>> shader_files;
};

}  // namespace caustica::graph
