#pragma once
// Turns a Plan into Vulkan objects (shared memory blocks with aliased resources, one allocation per
// persistent resource, pass objects) and records and submits frames. Recompiles only when the graph
// or the output size changes.
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "graph/compiler.h"
#include "graph/pass.h"
#include "graph/run_policy.h"
#include "io/image_io.h"

namespace caustica::graph {

struct PassTiming {
  std::string name;
  double gpu_ms = 0;
  double cpu_ms = 0;
  double gpu_start_ms = 0;  // from the frame's first timestamp
  double cpu_start_ms = 0;  // from the start of recording
  // What the run policy decided for it, and why (run_policy.h). A skipped pass had its barriers
  // recorded, its work not.
  PassRun run = PassRun::start_over;
  bool ran() const { return runs(run); }
};

// An output or retained image as the last frame left it, for commands recorded after the frame in
// another submission (the viewer copies the output into its window this way). Such commands leave
// it in `layout`: a plan that reuses passes starts the next frame from it.
struct FrameImage {
  VkImage image = VK_NULL_HANDLE;
  VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;
  Format format = Format::rgba8;
  VkExtent2D extent{};
};

struct FrameResult {
  std::vector<PassTiming> passes;
  double gpu_ms = 0;                                  // first to last timestamp of the frame, barriers included
  double cpu_ms = 0;                                  // recording and submission
  std::map<std::string, double> counters;             // counts are whole numbers; sums (caustic.flux) are floats
  std::map<std::string, std::string> counter_passes;  // counter -> the pass that set it up
  FrameInfo frame;                                    // the frame this was; since_reset: since anything a pass depends on last changed
  bool converging = false;            // a pass would change with more frames (PassContext::still_converging), as it last ran
  FramePart part = FramePart::whole;  // what the frame ran
  // The frames the plan's running means have run since their reset, this one included (the fewest
  // where several; a mean held at its max_frames counts the frames it holds, PassContext::holds_frames):
  // what a still view has gathered. 0: none.
  uint64_t accumulated = 0;
};

struct ConfigureOptions {
  std::set<std::string> retained;  // resources kept whole to the end of the frame (--dump)
  uint64_t memory_limit_bytes = CompileOptions{}.memory_limit_bytes;
  // Keep what passes that do not depend on the frame write, and skip such a pass while nothing it
  // depends on changed since it last ran (CompileOptions::reuse_unchanged_passes): for the viewer
  // and the editor. Off by default, so that rendering and benchmarks run and time every pass.
  bool reuse_unchanged_passes = false;
  // What the plan before may hand the new one (run_policy.h). start_over or edited shaders compile
  // again even where nothing else changed.
  HandOverOptions hand_over;
  // The tracer asked for (--tracer); unset: CAUSTICA_TRACER's, else the device's choice
  // (CompileOptions::tracer).
  std::optional<Tracer> tracer;
};

class Executor {
 public:
  Executor(vk::Context& vk, shader::ShaderCompiler& shaders, const PassRegistry& registry);
  ~Executor();

  // Options for compile_graph() on this device: its limits and its memory requirements.
  CompileOptions compile_options(uint32_t width, uint32_t height) const;

  // Compiles `graph` at this size unless the same graph was compiled at the same size with the
  // same options already (and nothing asks to start over). Returns true when it compiled. The new
  // plan takes over what the plan before hands it (plan_hand_over, options.hand_over). A configure
  // that throws keeps the previous plan running.
  bool configure(const GraphDesc& graph, uint32_t width, uint32_t height, const ConfigureOptions& options = {});

  // The scene that passes draw; kept across configure() calls. Uploads it now.
  void set_scene(std::shared_ptr<const scene::Scene> scene);
  const scene::GpuScene* scene() const { return scene_.get(); }
  // The scene set last seen with another camera or other lights (as many): kept on the device as it
  // is and not copied (set_scene() uploads everything again). After set_scene().
  void set_view(const scene::View& camera, std::vector<scene::Light> lights);

  // Records, submits and waits for one frame. With read_back, outputs and retained resources are
  // copied out and can be read with read_image().
  FrameResult run_frame(bool read_back, FrameRequest request = {});
  // How long a frame may take before run_frame() throws FrameTimeout naming the pass that was
  // running: `seconds` for every frame but a plan's first, which gets the longer of it and
  // `first_frame_seconds` (lavapipe compiles each pipeline with LLVM when it first runs: the
  // ray-query kernels from a cold shader cache took more than two minutes).
  void set_frame_timeout(double seconds, double first_frame_seconds = kFirstFrameTimeoutSeconds);
  static constexpr double kFrameTimeoutSeconds = 120, kFirstFrameTimeoutSeconds = 900;

  io::ImageData read_image(const std::string& resource) const;
  // The image stays valid until the next configure() that compiles; the next run_frame() may
  // overwrite it. Throws InputError for an image that is neither an output nor retained.
  FrameImage frame_image(const std::string& resource) const;
  const Plan& plan() const { return *plan_; }
  uint32_t compile_count() const { return compile_count_; }
  // Every shader file (and include) the plan's passes were set up with: what a reload watches.
  std::set<std::filesystem::path> shader_files() const;
  // The plan's outputs still hold the picture of a plan before (HandOverOptions::picture_may_stand).
  bool picture_standing() const;

 private:
  // The structures of the plan's tracer for the scene (built once per scene).
  void build_tracer_structures(const Plan& plan);
  friend class PassSetup;
  friend class PassContext;
  struct RealImage;
  struct RealBuffer;
  struct Realized;

  void realize(Plan plan, const HandOverOptions& options);
  void realize_passes_and_resources();
  // The new plan takes over what plan_hand_over says: running results continued, results' images
  // handed or kept to be copied in on its first frame (record_carried), a picture left standing.
  // The plan before is kept until that frame.
  void hand_over(std::unique_ptr<const Plan> before, std::unique_ptr<Realized> realized_before, const HandOverOptions& options);
  // Swaps resource `ia`'s image and memory in `a` with resource `ib`'s in `b`.
  static void swap_image(Realized& a, uint32_t ia, Realized& b, uint32_t ib);

  // executor_record.cpp: what a frame records besides its passes.
  void record_barriers(VkCommandBuffer cmd, const std::vector<PlannedBarrier>& barriers) const;
  // Before a frame's passes: each used history resource gets its source as the last frame left it,
  // or zeros where the run policy restarts it.
  void record_history(VkCommandBuffer cmd, const FrameDecision& decision);
  void record_carried(VkCommandBuffer cmd);
  void record_read_back(VkCommandBuffer cmd);

  // executor_frame.cpp: a frame's steps.
  std::optional<SceneKeys> scene_keys() const;
  // The passes as decided, with their timestamps (two for each, the second a dummy).
  void record_passes(VkCommandBuffer cmd, const FrameDecision& decision, std::chrono::steady_clock::time_point frame_start,
                     FrameResult& result, std::vector<std::pair<uint32_t, uint32_t>>& stamps, uint32_t& next_query);
  void submit_and_wait(const FrameDecision& decision);
  [[noreturn]] void throw_frame_timeout(const FrameDecision& decision, double limit_s) const;
  void collect_counters(const FrameDecision& decision, FrameResult& result);

  vk::Context& vk_;
  shader::ShaderCompiler& shaders_;
  const PassRegistry& registry_;
  std::unique_ptr<const Plan> plan_;
  std::unique_ptr<Realized> realized_;
  std::unique_ptr<scene::GpuScene> scene_;
  std::string configured_key_;
  uint32_t compile_count_ = 0;
  double frame_timeout_s_ = kFrameTimeoutSeconds, first_frame_timeout_s_ = kFirstFrameTimeoutSeconds;
  // What the new plan's first frame copies in (record_carried): the plan before, kept until then.
  struct Carried {
    std::unique_ptr<const Plan> plan;
    std::unique_ptr<Realized> realized;
    std::vector<ImageMove> images;  // resource in `plan` -> in plan_, copied or handed
  } carried_;
  // A refining pass as a replaced plan left it: what the hand-over of a later plan may continue.
  struct RunningResult {
    ResultIdentity running_id;
    std::unique_ptr<Pass> pass;
    PassRunState state;
  };
  std::vector<RunningResult> parked_running_;  // oldest first
};

}  // namespace caustica::graph
