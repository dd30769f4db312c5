#pragma once
// The run policy: the one place that decides, for a frame, which passes run, which keep their
// results, which start over, and which part of the plan the frame is (docs/interactive.md, "The
// run policy"). It is pure: from the plan, each pass's run state, the scene parts' keys and the
// frame's request to a FrameDecision; the executor records what it decides and nothing else
// decides. Every rule has a CPU test (tests/run_policy_test.cpp).
//
// A plan change is the other half: plan_hand_over() says, from the plan before, the new plan and the
// caller's options, what goes over (running results continued, results carried, images handed or
// copied, a picture left standing) and what is invalidated.
#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "graph/frame_info.h"
#include "graph/plan.h"

namespace caustica::graph {

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

// The scene as a frame sees it: the content key of each part (kSceneParts: geometry, lights,
// camera). A pass compares only the parts it depends on (masked), so a part it does not follow has
// no key at all rather than a stand-in value; of the lights, only those it follows
// (PlannedPass::lights: a per-light instance follows its own light).
struct SceneKeys {
  std::array<std::optional<uint64_t>, 3> parts;
  std::vector<uint64_t> lights;  // each light's key; parts[1] is theirs together
  SceneKeys masked(uint32_t depends, uint32_t lights_followed = kAllLights) const;
  bool operator==(const SceneKeys&) const = default;
};

// What the policy decided for one pass, and why.
enum class PassRun {
  start_over,      // runs from scratch: it has no result yet, or a scene part it depends on changed
  run,             // runs on: it follows the frame (a jittered grid, a running mean)
  keep,            // skipped: its result stands, nothing it depends on changed since it ran
  outside_part,    // skipped: not in this frame's part (a refine or display frame, a display step)
  waits_for_step,  // skipped: the picture of the plan before stands until its display step
};
bool runs(PassRun run);
const char* pass_run_name(PassRun run);

// A pass as the frames so far left it: what the policy reads and the executor keeps.
struct PassRunState {
  // The scene (the parts the pass depends on) its result started from; none: it has no result.
  std::optional<SceneKeys> started_from;
  FrameInfo frames;                         // index and since_reset as the pass last saw them
  std::optional<SceneKeys> last_run_scene;  // every part's keys the frame it last ran (PassContext::scene_unchanged_since_last_run)
  bool converging = false;                  // PassContext::still_converging, as it last ran
  std::optional<uint64_t> frames_held;      // PassContext::holds_frames, as it last ran
};

// The whole run state of a realized plan.
struct RunState {
  std::vector<PassRunState> passes;  // by plan order
  uint64_t frame_index = 0;          // the next frame
  // While the outputs hold the picture of the plan before (HandOver::standing): the
  // scene that picture was drawn for.
  std::optional<SceneKeys> standing;
  std::optional<SceneKeys> last_scene;  // the scene of the last frame run
  // Plan::jitters_camera: the scene when the jitter sequence last restarted, and the frames since.
  std::optional<SceneKeys> jitter_scene;
  uint64_t jittered_frames = 0;
  // Per history resource: the scene (the parts its source depends on) when it last restarted.
  std::map<uint32_t, SceneKeys> history_scene;
};
RunState initial_run_state(const Plan& plan);

struct FrameRequest {
  FramePart part = FramePart::whole;
  DisplayStep step;
};

struct FrameDecision {
  FramePart part = FramePart::whole;  // what the frame runs (a request the plan cannot honour runs whole)
  std::vector<PassRun> passes;        // by plan order
  // Plan::jitters_camera: the camera's offset in its pixel this frame, and whether the sequence
  // starts over (the first frame after any change of the scene is a fresh render's).
  bool jitters = false;
  uint64_t jitter_frame = 0;
  // Per used history resource: true when it restarts from zeros, false when it copies its source.
  std::map<uint32_t, bool> history_restarts;
};

// `scene`: none when the plan draws no scene.
FrameDecision decide_frame(const Plan& plan, const RunState& state, const std::optional<SceneKeys>& scene, FrameRequest request);

// The state as the passes are about to be recorded: a pass starting over sees since_reset 0, every
// pass sees this frame's index and jitter.
void begin_frame(const Plan& plan, RunState& state, const FrameDecision& decision, const std::optional<SceneKeys>& scene,
                 glm::vec2 camera_jitter);
// What the frame shows: the frames since the scene last changed that the picture stands on (a
// display frame shows the running results as the last refining frame left them), and the frames
// the running means hold (the fewest where several; 0: none).
struct FrameAccount {
  uint64_t since_reset = 0;
  uint64_t accumulated = 0;
};
// After the passes were recorded: what the next decision reads.
FrameAccount end_frame(const Plan& plan, RunState& state, const FrameDecision& decision, const std::optional<SceneKeys>& scene);

// ---- A plan change ---------------------------------------------------------------------------------

struct HandOverOptions {
  // Nothing goes over and every pass of the new plan starts over (shaders edited on disk, unknown
  // which): Executor::configure with an invalidation.
  bool start_over = false;
  // These shader files (and includes) were saved: the passes set up with one of them, and those that
  // read what such a pass writes, start over; the others go on.
  std::set<std::filesystem::path> edited_shaders;
  // A change of quality values at rest (the viewer's while_still values): where the new plan
  // refines apart, the plan before's picture stands until the new showing passes have run, its
  // images handed over by name to those that carried none. Not for an edit of what the picture
  // shows, which is to be seen at once.
  bool picture_may_stand = false;
};

// A realized plan as the hand-over sees it.
struct PlanRecord {
  const Plan* plan = nullptr;
  const RunState* state = nullptr;
  const std::vector<std::vector<std::filesystem::path>>* shader_files = nullptr;  // per pass
};

struct ImageMove {
  uint32_t from = 0, to = 0;  // resource in the plan before -> in the new plan
  bool handed = false;        // the image itself goes over (both plans describe it alike, in memory of its own); else copied
  bool operator==(const ImageMove&) const = default;
};

struct HandOver {
  // Per pass of the new plan: the pass of the plan before whose running result it continues
  // (Pass::continue_from, its run state), or the parked result (by index) it continues.
  std::vector<std::optional<size_t>> continues;
  std::vector<std::optional<size_t>> continues_parked;
  // Per pass of the new plan: the pass of the plan before whose result (images) it takes over.
  std::vector<std::optional<size_t>> takes_result;
  std::vector<ImageMove> images;  // the carried results' images, then the standing picture's
  // Every output holds the plan before's picture, drawn for this scene: RunState::standing.
  std::optional<SceneKeys> standing;
  bool clear_parked = false;  // start over, or a shader saved: no parked result is to be trusted
  // Per pass of the plan before: invalidated (its shader saved, or it reads what such a pass wrote).
  std::vector<bool> stale;
  // The plan before's running results not continued: parked for a later plan.
  std::vector<size_t> parks;
};

// `running_from`: where running results come from (the plan before, which may never have run and
// then holds what it was handed). `results_from`: where images come from (the plan before, or the
// one before it where the plan before never ran). `parked`: the running identities of results parked
// from older plans. Both plans reuse unchanged passes or nothing goes over.
HandOver plan_hand_over(const PlanRecord& running_from, const PlanRecord& results_from, const std::vector<ResultIdentity>& parked,
                        const Plan& after, const HandOverOptions& options);

}  // namespace caustica::graph
