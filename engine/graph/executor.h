#pragma once
// Turns a Plan into Vulkan objects (shared memory blocks with aliased resources, one allocation per
// persistent resource, pass objects) and records and submits frames. Recompiles only when the graph
// or the output size changes.
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
#include "io/image_io.h"

namespace caustica::graph {

struct PassTiming {
  std::string name;
  double gpu_ms = 0;
  double cpu_ms = 0;
  double gpu_start_ms = 0;  // from the frame's first timestamp
  double cpu_start_ms = 0;  // from the start of recording
  // False when the pass was skipped: a plan that reuses unchanged passes, and nothing it depends
  // on changed since it last ran (its barriers were recorded, its work not).
  bool ran = true;
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

// Which passes a frame runs. In a plan that refines apart (Plan::refines_apart), a refine frame runs
// the passes that move its running results (PlannedPass::refines) and a display frame the others,
// which show those results as they stand: a still view spends most frames refining and shows the
// result every so often. Elsewhere, and when a pass outside the part has something new to work on
// (a change of a scene part it depends on), a frame runs whole.
enum class FramePart { whole, refine, display };
// A display frame may show in steps, each within a frame budget: it runs only the showing passes
// numbered [first, last) among those that do not refine, in plan order; the picture changes when
// the step with the pass that writes the output has run. The passes before a step keep their
// results in a plan that refines apart, so that the next step reads them.
struct DisplayStep {
  size_t first = 0;
  size_t last = SIZE_MAX;
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

class Executor {
 public:
  Executor(vk::Context& vk, shader::ShaderCompiler& shaders, const PassRegistry& registry);
  ~Executor();

  // Options for compile_graph() on this device: its limits and its memory requirements.
  CompileOptions compile_options(uint32_t width, uint32_t height) const;

  // Compiles `graph` at this size unless the same graph was compiled at the same size already.
  // Returns true when it compiled.
  bool configure(const GraphDesc& graph, uint32_t width, uint32_t height, const std::set<std::string>& retained = {},
                 uint64_t memory_limit_bytes = CompileOptions{}.memory_limit_bytes);

  // Plans compiled from now on keep what passes that do not depend on the frame write, and
  // run_frame() skips such a pass while nothing it depends on changed since it last ran
  // (CompileOptions::reuse_unchanged_passes): for the viewer and the editor. Off by default, so
  // that rendering and benchmarks run and time every pass every frame.
  void set_reuse_unchanged_passes(bool reuse) { reuse_unchanged_passes_ = reuse; }

  // The scene that passes draw; kept across configure() calls. Uploads it now.
  void set_scene(std::shared_ptr<const scene::Scene> scene);
  const scene::GpuScene* scene() const { return scene_.get(); }
  // The scene set last seen with another camera or other lights (as many): kept on the device as it
  // is and not copied (set_scene() uploads everything again). After set_scene().
  void set_view(const scene::View& camera, std::vector<scene::Light> lights);

  // Records, submits and waits for one frame. With read_back, outputs and retained resources are
  // copied out and can be read with read_image().
  FrameResult run_frame(bool read_back, FramePart part = FramePart::whole, DisplayStep step = {});

  io::ImageData read_image(const std::string& resource) const;
  // The image stays valid until the next configure() that compiles; the next run_frame() may
  // overwrite it. Throws InputError for an image that is neither an output nor retained.
  FrameImage frame_image(const std::string& resource) const;
  const Plan& plan() const { return *plan_; }
  uint32_t compile_count() const { return compile_count_; }
  // Makes the next configure() compile and set up every pass again even if nothing it is given
  // changed, and run every pass on its first frame: for shaders edited on disk. A configure() that
  // throws keeps the previous plan running.
  void invalidate() {
    configured_key_.clear();
    carry_results_ = false;
  }
  // As invalidate(), for these shader files (and includes) saved: only the passes set up with one
  // of them, and those that read what they write, run again; the others keep their results.
  void invalidate(const std::set<std::filesystem::path>& edited_shaders) {
    configured_key_.clear();
    edited_shaders_.insert(edited_shaders.begin(), edited_shaders.end());
  }
  // Every shader file (and include) the plan's passes were set up with: what a reload watches.
  std::set<std::filesystem::path> shader_files() const;
  // Lets the next configure()'s plan, where it refines apart, show the plan before's picture until
  // its own showing passes have run: the images those passes did not carry over (PlannedPass::
  // showing_key) are handed over by name from the plan before, and its frames may refine, or show in
  // steps, before those passes run, for as long as the scene is the one that picture was drawn for
  // (else the frame runs whole). For the viewer's change of quality values at rest (a graph's
  // while_still values), whose picture is one of the same view; not for an edit of what the picture
  // shows, which is to be seen at once.
  void let_picture_stand() { picture_may_stand_ = true; }
  // The plan's outputs still hold the picture of a plan before (let_picture_stand).
  bool picture_standing() const;

 private:
  friend class PassSetup;
  friend class PassContext;
  struct RealImage;
  struct RealBuffer;
  struct Realized;

  void realize(Plan plan, bool picture_may_stand);
  void realize_passes_and_resources();
  void record_barriers(VkCommandBuffer cmd, const std::vector<PlannedBarrier>& barriers) const;
  // Before a frame's passes: each used history resource gets its source as the last frame left it,
  // or zeros on the plan's first frame and after a change of a scene part it depends on.
  void record_history(VkCommandBuffer cmd);
  // A new plan that reuses unchanged passes takes over the results of the passes whose result key
  // (PlannedPass::result_key) the plan before had and which ran there: their images are copied in
  // on its first frame (record_carried) and they are not run again until what they depend on
  // changes; in a plan that refines apart, so are the showing passes' whose showing key
  // (PlannedPass::showing_key) the plan before had. An image that both plans describe alike, in
  // memory of its own, is handed over instead of copied. The plan before is kept until then.
  void carry_results(std::unique_ptr<const Plan> before, std::unique_ptr<Realized> realized_before, bool picture_may_stand);
  // let_picture_stand: hands the plan before's images over to the showing passes of the new plan
  // that carried none, and marks the picture standing where every output has one.
  void stand_picture(const Plan& before, Realized& realized_before);
  // Swaps resource `ia`'s image and memory in `a` with resource `ib`'s in `b`.
  static void swap_image(Realized& a, uint32_t ia, Realized& b, uint32_t ib);
  void record_carried(VkCommandBuffer cmd);
  // The passes of the plan before (or of a plan parked since) set up with a saved shader file, or
  // reading what such a pass writes: they compute anew.
  std::vector<bool> stale_passes(const Plan& plan, const Realized& realized, const std::set<std::filesystem::path>& edited) const;
  // The refining passes of the new plan continue the running results (PlannedPass::running_key) of
  // the plan before or of a plan parked since; the plan before's others are parked, a few plans'
  // worth: the viewer's still plan comes back after its while_moving plan.
  void carry_running_results(const Plan& before, Realized& realized_before, const std::vector<bool>& stale);

  vk::Context& vk_;
  shader::ShaderCompiler& shaders_;
  const PassRegistry& registry_;
  std::unique_ptr<const Plan> plan_;
  std::unique_ptr<Realized> realized_;
  std::unique_ptr<scene::GpuScene> scene_;
  std::string configured_key_;
  uint32_t compile_count_ = 0;
  bool reuse_unchanged_passes_ = false;
  bool carry_results_ = true;  // until invalidate()
  bool picture_may_stand_ = false;                  // for the next configure() (let_picture_stand)
  std::set<std::filesystem::path> edited_shaders_;  // until the next plan, invalidate(files)
  // What the new plan's first frame copies in (record_carried): the plan before, kept until then.
  struct Carried {
    std::unique_ptr<const Plan> plan;
    std::unique_ptr<Realized> realized;
    std::vector<std::pair<uint32_t, uint32_t>> images;  // resource in `plan` -> in plan_, copied
    std::vector<std::pair<uint32_t, uint32_t>> handed;  // the same, the image itself handed over (swapped)
    // Whether an image of `plan` goes over already, or one of plan_ is already given one.
    bool carries_from(uint32_t from) const;
    bool carries_to(uint32_t to) const;
  } carried_;
  // A refining pass as a replaced plan left it: what carry_running_results hands on.
  struct RunningResult {
    uint64_t running_key = 0;
    std::unique_ptr<Pass> pass;
    std::optional<uint64_t> reset_key;
    FrameInfo frames;
    bool converging = false;
  };
  std::vector<RunningResult> parked_running_;  // oldest first
};

}  // namespace caustica::graph
