// The run policy on the CPU (engine/graph/run_policy.h): every rule that decides whether a pass
// runs, keeps its result, starts over or waits, and what a plan change hands over, on plans made
// by hand, without a device. progressive_test and view_test check that the executor obeys it.
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "graph/run_policy.h"

namespace caustica::graph {
namespace {

constexpr uint32_t kLight = kDependsOnGeometry | kDependsOnLights;  // a light's view
constexpr uint32_t kCamera = kDependsOnGeometry | kDependsOnCamera;

// A plan made by hand: each pass writes one image of its own (and reads those named), so that
// what the hand-over moves can be seen.
struct TestPlan {
  Plan plan;
  std::vector<std::shared_ptr<PassTypeDecl>> decls;

  explicit TestPlan(bool reuses = true, bool refines_apart = false) {
    plan.reuses_unchanged_passes = reuses;
    plan.refines_apart = refines_apart;
  }
  // Returns the pass's index. Its image is resource `name`'s, persistent unless `transient`.
  size_t pass(const std::string& name, uint32_t depends, std::vector<std::string> reads = {}, bool refines = false,
              bool accumulates = false, ResourceKind kind = ResourceKind::image) {
    auto decl = std::make_shared<PassTypeDecl>();
    decl->type = "t_" + name;
    decl->accumulates = accumulates;
    decl->ports.push_back({"out", PortAccess::write, kind, PortUsage::storage, {}, false, "", ""});
    PlannedPass p;
    p.name = name;
    p.decl = decl.get();
    p.depends = depends;
    p.refines = refines;
    p.ports["out"] = resource(name, kind);
    for (size_t k = 0; k < reads.size(); ++k) {
      const std::string port = "in" + std::to_string(k);
      decl->ports.push_back({port, PortAccess::read, ResourceKind::image, PortUsage::sampled, {}, false, "", ""});
      p.ports[port] = static_cast<uint32_t>(plan.find_resource(reads[k]));
    }
    if (!refines)
      p.showing = static_cast<uint32_t>(std::count_if(plan.passes.begin(), plan.passes.end(), [](const auto& q) { return !q.refines; }));
    if (p.reusable(plan.reuses_unchanged_passes)) p.result_id = ResultIdentity(name, {});
    if (refines) p.running_id = ResultIdentity(name, {});
    decls.push_back(decl);
    plan.passes.push_back(p);
    return plan.passes.size() - 1;
  }
  uint32_t resource(const std::string& name, ResourceKind kind) {
    PlannedResource r;
    r.name = name;
    r.kind = kind;
    r.format = Format::rgba16f;
    r.width = r.height = 8;
    r.transient = false;
    r.first_use = static_cast<uint32_t>(plan.passes.size());
    plan.resources.push_back(r);
    return static_cast<uint32_t>(plan.resources.size() - 1);
  }
  void output(const std::string& name) { plan.outputs.push_back(static_cast<uint32_t>(plan.find_resource(name))); }
};

SceneKeys scene(uint64_t geometry, uint64_t lights, uint64_t camera) {
  return SceneKeys{{geometry, lights, camera}};
}

// One frame: decide, then the state as the executor leaves it.
FrameDecision frame(const Plan& plan, RunState& state, const SceneKeys& keys, FrameRequest request = {}, FrameAccount* account = nullptr) {
  const FrameDecision d = decide_frame(plan, state, keys, request);
  begin_frame(plan, state, d, keys, {});
  const FrameAccount a = end_frame(plan, state, d, keys);
  if (account) *account = a;
  return d;
}

using R = PassRun;

// The viewer's default graph in small: a light's pass, a camera pass that reads it, and one that
// follows the frame (a jittered pass).
TestPlan light_camera_frame(bool reuses = true) {
  TestPlan t(reuses);
  t.pass("shadow", kLight);
  t.pass("gbuffer", kCamera, {"shadow"});
  t.pass("jittered", kCamera | kDependsOnFrame, {"gbuffer"});
  t.output("jittered");
  return t;
}

TEST(RunPolicy, APlansFirstFrameStartsEveryPassOver) {
  const TestPlan t = light_camera_frame();
  RunState state = initial_run_state(t.plan);
  const FrameDecision d = frame(t.plan, state, scene(1, 1, 1));
  EXPECT_EQ(d.part, FramePart::whole);
  EXPECT_EQ(d.passes, (std::vector<PassRun>{R::start_over, R::start_over, R::start_over}));
}

TEST(RunPolicy, APassKeepsItsResultWhileWhatItDependsOnStandsAndOneThatFollowsTheFrameRunsOn) {
  const TestPlan t = light_camera_frame();
  RunState state = initial_run_state(t.plan);
  frame(t.plan, state, scene(1, 1, 1));
  EXPECT_EQ(frame(t.plan, state, scene(1, 1, 1)).passes, (std::vector<PassRun>{R::keep, R::keep, R::run}));
}

TEST(RunPolicy, AChangeStartsOverThePassesThatDependOnThePartAndNoOthers) {
  const TestPlan t = light_camera_frame();
  RunState state = initial_run_state(t.plan);
  frame(t.plan, state, scene(1, 1, 1));
  EXPECT_EQ(frame(t.plan, state, scene(1, 1, 2)).passes, (std::vector<PassRun>{R::keep, R::start_over, R::start_over}))
      << "a camera move leaves the light's pass";
  EXPECT_EQ(frame(t.plan, state, scene(1, 2, 2)).passes, (std::vector<PassRun>{R::start_over, R::keep, R::run}))
      << "a light move starts over what depends on the lights alone";
  EXPECT_EQ(frame(t.plan, state, scene(3, 2, 2)).passes, (std::vector<PassRun>{R::start_over, R::start_over, R::start_over}));
}

// Per-light passes (graph/per_light.h) follow their own light: moving light 1 starts over its
// shadow and what reads every light's, and leaves light 0's.
TEST(RunPolicy, MovingOneLightStartsOverOnlyThePassesThatFollowIt) {
  TestPlan t;
  const size_t shadow0 = t.pass("shadow#0", kLight);
  const size_t shadow1 = t.pass("shadow#1", kLight);
  t.plan.passes[shadow0].lights = 1u << 0;
  t.plan.passes[shadow1].lights = 1u << 1;
  t.pass("lighting", kCamera | kDependsOnLights, {"shadow#0", "shadow#1"});
  t.output("lighting");
  RunState state = initial_run_state(t.plan);
  auto keys = [](uint64_t light0, uint64_t light1, uint64_t camera) {
    SceneKeys k = scene(1, light0 * 31 + light1, camera);
    k.lights = {light0, light1};
    return k;
  };
  frame(t.plan, state, keys(1, 1, 1));
  EXPECT_EQ(frame(t.plan, state, keys(1, 2, 1)).passes, (std::vector<PassRun>{R::keep, R::start_over, R::start_over})) << "light 1 moved";
  EXPECT_EQ(frame(t.plan, state, keys(3, 2, 1)).passes, (std::vector<PassRun>{R::start_over, R::keep, R::start_over})) << "light 0 moved";
  EXPECT_EQ(frame(t.plan, state, keys(3, 2, 4)).passes, (std::vector<PassRun>{R::keep, R::keep, R::start_over})) << "the camera moved";
}

TEST(RunPolicy, APlanThatDoesNotReuseRunsEveryPassEveryFrame) {
  const TestPlan t = light_camera_frame(false);
  RunState state = initial_run_state(t.plan);
  frame(t.plan, state, scene(1, 1, 1));
  EXPECT_EQ(frame(t.plan, state, scene(1, 1, 1)).passes, (std::vector<PassRun>{R::run, R::run, R::run}));
}

TEST(RunPolicy, WithoutASceneAPassStartsOverOnlyOnItsFirstFrame) {
  const TestPlan t = light_camera_frame();
  RunState state = initial_run_state(t.plan);
  EXPECT_EQ(decide_frame(t.plan, state, std::nullopt, {}).passes[0], R::start_over);
  const FrameDecision d = decide_frame(t.plan, state, std::nullopt, {});
  begin_frame(t.plan, state, d, std::nullopt, {});
  end_frame(t.plan, state, d, std::nullopt);
  EXPECT_EQ(decide_frame(t.plan, state, std::nullopt, {}).passes, (std::vector<PassRun>{R::keep, R::keep, R::run}));
}

// caustics_progressive in small: photons (light, follows the frame) into a running mean, shown by
// lighting and a tone map.
TestPlan progressive() {
  TestPlan t(true, true);
  t.pass("photons", kLight | kDependsOnFrame, {}, true);
  t.pass("mean", kLight | kDependsOnFrame, {"photons"}, true, true);
  t.pass("gbuffer", kCamera);
  t.pass("lighting", kCamera | kDependsOnLights | kDependsOnFrame, {"gbuffer", "mean"});
  t.pass("tonemap", kCamera | kDependsOnLights | kDependsOnFrame, {"lighting"});
  t.output("tonemap");
  return t;
}

TEST(RunPolicy, ARefineFrameRunsTheRefiningPassesAndADisplayStepItsShowingPasses) {
  const TestPlan t = progressive();
  RunState state = initial_run_state(t.plan);
  frame(t.plan, state, scene(1, 1, 1));
  FrameDecision d = frame(t.plan, state, scene(1, 1, 1), {FramePart::refine});
  EXPECT_EQ(d.part, FramePart::refine);
  EXPECT_EQ(d.passes, (std::vector<PassRun>{R::run, R::run, R::outside_part, R::outside_part, R::outside_part}));
  // Showing passes are numbered in plan order: gbuffer 0, lighting 1, tonemap 2.
  d = frame(t.plan, state, scene(1, 1, 1), {FramePart::display, {0, 2}});
  EXPECT_EQ(d.passes, (std::vector<PassRun>{R::outside_part, R::outside_part, R::keep, R::run, R::outside_part}));
  d = frame(t.plan, state, scene(1, 1, 1), {FramePart::display, {2, SIZE_MAX}});
  EXPECT_EQ(d.passes, (std::vector<PassRun>{R::outside_part, R::outside_part, R::outside_part, R::outside_part, R::run}));
}

TEST(RunPolicy, AFrameApartRunsWholeWhenAPassOutsideItHasNewWorkOrThePlanDoesNotRefineApart) {
  const TestPlan t = progressive();
  RunState state = initial_run_state(t.plan);
  EXPECT_EQ(frame(t.plan, state, scene(1, 1, 1), {FramePart::refine}).part, FramePart::whole) << "nothing has a result yet";
  EXPECT_EQ(frame(t.plan, state, scene(1, 1, 1), {FramePart::refine}).part, FramePart::refine);
  EXPECT_EQ(frame(t.plan, state, scene(1, 1, 2), {FramePart::refine}).part, FramePart::whole)
      << "the camera moved: the picture must follow";
  TestPlan together = progressive();
  together.plan.refines_apart = false;
  RunState s2 = initial_run_state(together.plan);
  frame(together.plan, s2, scene(1, 1, 1));
  EXPECT_EQ(frame(together.plan, s2, scene(1, 1, 1), {FramePart::refine}).part, FramePart::whole);
}

TEST(RunPolicy, WhileAPictureStandsShowingPassesWithoutAResultWaitForTheirStep) {
  const TestPlan t = progressive();
  RunState state = initial_run_state(t.plan);
  // As a hand-over leaves it: the refining passes continued, the showing ones have nothing yet.
  for (size_t i : {0, 1}) state.passes[i].started_from = scene(1, 1, 1).masked(t.plan.passes[i].depends);
  state.standing = scene(1, 1, 1);
  FrameDecision d = frame(t.plan, state, scene(1, 1, 1), {FramePart::refine});
  EXPECT_EQ(d.part, FramePart::refine);
  EXPECT_EQ(d.passes[3], R::waits_for_step);
  EXPECT_TRUE(state.standing.has_value());
  d = decide_frame(t.plan, state, scene(1, 1, 1), {FramePart::display, {0, 1}});
  EXPECT_EQ(d.part, FramePart::display) << "a step whose passes come before the waiting ones";
  d = decide_frame(t.plan, state, scene(1, 1, 1), {FramePart::display, {1, 2}});
  EXPECT_EQ(d.part, FramePart::whole) << "a step after one not run: the gbuffer has no result";
  EXPECT_EQ(decide_frame(t.plan, state, scene(1, 1, 2), {FramePart::refine}).part, FramePart::whole) << "the picture was of another view";
  frame(t.plan, state, scene(1, 1, 1), {FramePart::display, {0, SIZE_MAX}});
  EXPECT_FALSE(state.standing.has_value()) << "every pass has a result: the picture is the plan's own";
}

TEST(RunPolicy, APassCountsTheFramesOfItsPartSinceItStartedOver) {
  const TestPlan t = progressive();
  RunState state = initial_run_state(t.plan);
  frame(t.plan, state, scene(1, 1, 1));
  frame(t.plan, state, scene(1, 1, 1), {FramePart::refine});
  frame(t.plan, state, scene(1, 1, 1), {FramePart::refine});
  EXPECT_EQ(state.passes[1].frames.since_reset, 3u) << "the mean ran three frames";
  EXPECT_EQ(state.passes[3].frames.since_reset, 1u) << "lighting, outside the refine frames, stays where it was";
  const FrameDecision d = decide_frame(t.plan, state, scene(1, 2, 1), {});
  begin_frame(t.plan, state, d, scene(1, 2, 1), {});
  EXPECT_EQ(state.passes[1].frames.since_reset, 0u) << "a light move: the mean starts over and sees frame 0";
  EXPECT_EQ(state.passes[2].frames.since_reset, 1u) << "the gbuffer kept its result";
}

TEST(RunPolicy, AFrameAccountsTheFramesItsPictureStandsOnAndTheMeansHold) {
  const TestPlan t = progressive();
  RunState state = initial_run_state(t.plan);
  FrameAccount a;
  frame(t.plan, state, scene(1, 1, 1), {}, &a);
  EXPECT_EQ(a.since_reset, 0u);
  EXPECT_EQ(a.accumulated, 1u);
  frame(t.plan, state, scene(1, 1, 1), {FramePart::refine}, &a);
  frame(t.plan, state, scene(1, 1, 1), {FramePart::refine}, &a);
  EXPECT_EQ(a.accumulated, 3u);
  frame(t.plan, state, scene(1, 1, 1), {FramePart::display}, &a);
  EXPECT_EQ(a.since_reset, 2u) << "a display shows the running results as the last refining frame left them";
  EXPECT_EQ(a.accumulated, 3u);
  state.passes[1].frames_held = 2;  // a mean held at its max_frames
  frame(t.plan, state, scene(1, 1, 1), {FramePart::display}, &a);
  EXPECT_EQ(a.accumulated, 2u);
}

TEST(RunPolicy, TheCameraJitterRestartsWithAnySceneChangeAndADisplayFrameDoesNotMoveIt) {
  TestPlan t = progressive();
  t.plan.jitters_camera = true;
  RunState state = initial_run_state(t.plan);
  EXPECT_EQ(frame(t.plan, state, scene(1, 1, 1)).jitter_frame, 0u);
  EXPECT_EQ(frame(t.plan, state, scene(1, 1, 1), {FramePart::refine}).jitter_frame, 1u);
  EXPECT_FALSE(frame(t.plan, state, scene(1, 1, 1), {FramePart::display}).jitters);
  EXPECT_EQ(frame(t.plan, state, scene(1, 1, 1), {FramePart::refine}).jitter_frame, 2u);
  EXPECT_EQ(frame(t.plan, state, scene(1, 1, 2)).jitter_frame, 0u) << "a camera move";
  EXPECT_FALSE(decide_frame(t.plan, state, std::nullopt, {}).jitters) << "no scene, no camera to jitter";
}

TEST(RunPolicy, AHistoryRestartsWhenWhatItsSourceDependsOnChanges) {
  TestPlan t = light_camera_frame();
  PlannedResource history = t.plan.resources[0];
  history.name = "shadow@previous";
  history.previous_of = 0;
  history.history_depends = kLight;
  t.plan.resources.push_back(history);
  const uint32_t h = static_cast<uint32_t>(t.plan.resources.size() - 1);
  RunState state = initial_run_state(t.plan);
  EXPECT_TRUE(frame(t.plan, state, scene(1, 1, 1)).history_restarts.at(h));
  EXPECT_FALSE(frame(t.plan, state, scene(1, 1, 2)).history_restarts.at(h)) << "a camera move leaves light-space history";
  EXPECT_TRUE(frame(t.plan, state, scene(1, 2, 2)).history_restarts.at(h));
}

// ---- The hand-over ---------------------------------------------------------------------------------

struct Ran {
  RunState state;
  std::vector<std::vector<std::filesystem::path>> files;
  PlanRecord record(const Plan& plan) const { return {&plan, &state, &files}; }
};
Ran ran(const Plan& plan, uint64_t frames = 1) {
  Ran r{initial_run_state(plan), std::vector<std::vector<std::filesystem::path>>(plan.passes.size())};
  for (uint64_t f = 0; f < frames; ++f) frame(plan, r.state, scene(1, 1, 1));
  return r;
}

TEST(RunHandOver, APassWithAnEqualResultIdentityTakesItsImagesHandedWhereAlikeElseCopied) {
  TestPlan before = light_camera_frame(), after = light_camera_frame();
  after.plan.resources[1].width = 16;  // the gbuffer's image at another size
  after.plan.passes[1].result_id = ResultIdentity("gbuffer", {});
  const Ran r = ran(before.plan);
  const HandOver h = plan_hand_over(r.record(before.plan), r.record(before.plan), {}, after.plan, {});
  EXPECT_EQ(h.takes_result[0], 0u);
  EXPECT_EQ(h.takes_result[1], 1u);
  EXPECT_FALSE(h.takes_result[2]) << "a pass that follows the frame has no result to take";
  EXPECT_EQ(h.images, (std::vector<ImageMove>{{0, 0, true}, {1, 1, false}}));
  after.plan.passes[0].result_id = ResultIdentity("shadow", {ResultIdentity("another input", {})});
  EXPECT_FALSE(plan_hand_over(r.record(before.plan), r.record(before.plan), {}, after.plan, {}).takes_result[0])
      << "an identity that differs in what it reads";
}

TEST(RunHandOver, AResultInABufferIsComputedAgain) {
  TestPlan before(true), after(true);
  for (TestPlan* t : {&before, &after}) t->pass("lists", kLight, {}, false, false, ResourceKind::buffer);
  const Ran r = ran(before.plan);
  const HandOver h = plan_hand_over(r.record(before.plan), r.record(before.plan), {}, after.plan, {});
  EXPECT_FALSE(h.takes_result[0]);
  EXPECT_TRUE(h.images.empty());
}

TEST(RunHandOver, NothingGoesOverWhereAPlanDoesNotReuseOrTheBeforeNeverRan) {
  const TestPlan before = light_camera_frame(), after = light_camera_frame(), not_reusing = light_camera_frame(false);
  const Ran r = ran(before.plan);
  EXPECT_TRUE(plan_hand_over(r.record(before.plan), r.record(before.plan), {}, not_reusing.plan, {}).images.empty());
  // A plan that never ran holds no images of its own, even for a pass whose run state it was handed.
  Ran unrun = ran(before.plan, 0);
  unrun.state.passes[0].started_from = scene(1, 1, 1).masked(kLight);
  EXPECT_TRUE(plan_hand_over(unrun.record(before.plan), unrun.record(before.plan), {}, after.plan, {}).images.empty());
}

TEST(RunHandOver, RunningResultsContinueFromThePlanBeforeOrAParkedOneAndTheRestIsParked) {
  const TestPlan before = progressive(), after = progressive();
  TestPlan other = progressive();
  other.plan.passes[1].running_id = ResultIdentity("another mean", {});
  const Ran r = ran(before.plan, 3);
  HandOver h = plan_hand_over(r.record(before.plan), r.record(before.plan), {}, after.plan, {});
  EXPECT_EQ(h.continues[0], 0u);
  EXPECT_EQ(h.continues[1], 1u);
  EXPECT_TRUE(h.parks.empty());
  h = plan_hand_over(r.record(before.plan), r.record(before.plan), {ResultIdentity("another mean", {})}, other.plan, {});
  EXPECT_EQ(h.continues_parked[1], 0u) << "the mean a plan before left, parked";
  EXPECT_EQ(h.parks, (std::vector<size_t>{1})) << "the plan before's mean waits for a plan that continues it";
}

TEST(RunHandOver, StartingOverHandsNothingAndForgetsWhatIsParked) {
  const TestPlan before = progressive(), after = progressive();
  const Ran r = ran(before.plan, 2);
  const HandOver h =
      plan_hand_over(r.record(before.plan), r.record(before.plan), {ResultIdentity("photons", {})}, after.plan, {.start_over = true});
  EXPECT_TRUE(h.clear_parked);
  EXPECT_FALSE(h.continues[0] || h.continues_parked[0] || h.takes_result[2]);
  EXPECT_TRUE(h.images.empty());
}

TEST(RunHandOver, ASavedShaderInvalidatesItsPassesAndThoseThatReadWhatTheyWrite) {
  const TestPlan before = light_camera_frame(), after = light_camera_frame();
  Ran r = ran(before.plan);
  r.files[0] = {"shaders/shadow.frag"};
  const HandOver h =
      plan_hand_over(r.record(before.plan), r.record(before.plan), {}, after.plan, {.edited_shaders = {"shaders/shadow.frag"}});
  EXPECT_EQ(h.stale, (std::vector<bool>{true, true, true}));
  EXPECT_FALSE(h.takes_result[0] || h.takes_result[1]);
  EXPECT_TRUE(h.clear_parked);
  r.files[0] = {"shaders/unrelated.frag"};
  EXPECT_EQ(plan_hand_over(r.record(before.plan), r.record(before.plan), {}, after.plan, {.edited_shaders = {"shaders/other.glsl"}})
                .takes_result[0],
            0u);
}

TEST(RunHandOver, AQualityChangeAtRestLeavesThePictureStandingWhereEveryOutputIsCovered) {
  const TestPlan before = progressive();
  TestPlan after = progressive();  // other while_still values: the showing passes have nothing to carry
  const Ran r = ran(before.plan, 2);
  HandOver h = plan_hand_over(r.record(before.plan), r.record(before.plan), {}, after.plan, {});
  EXPECT_FALSE(h.standing) << "not asked";
  h = plan_hand_over(r.record(before.plan), r.record(before.plan), {}, after.plan, {.picture_may_stand = true});
  ASSERT_TRUE(h.standing);
  EXPECT_EQ(*h.standing, scene(1, 1, 1)) << "the scene the picture was drawn for";
  EXPECT_TRUE(std::find(h.images.begin(), h.images.end(), ImageMove{4, 4, true}) != h.images.end()) << "the output handed by name";
  after.plan.resources[4].width = 4;  // the output at another size: no picture of the plan before can stand for it
  EXPECT_FALSE(plan_hand_over(r.record(before.plan), r.record(before.plan), {}, after.plan, {.picture_may_stand = true}).standing);
}

TEST(RunHandOver, APlanReplacedBeforeItRanPassesOnThePlanBeforeItsResults) {
  const TestPlan oldest = light_camera_frame(), unrun = light_camera_frame(), after = light_camera_frame();
  const Ran ran_oldest = ran(oldest.plan), never = ran(unrun.plan, 0);
  const HandOver h = plan_hand_over(never.record(unrun.plan), ran_oldest.record(oldest.plan), {}, after.plan, {});
  EXPECT_EQ(h.takes_result[0], 0u);
  EXPECT_FALSE(h.images.empty());
}

TEST(ResultIdentity, IsEqualOnlyForTheSameDescriptionsAndInputsAllTheWayDown) {
  const ResultIdentity a("lighting", {ResultIdentity("gbuffer", {}), ResultIdentity("shadow", {})});
  EXPECT_EQ(a, ResultIdentity("lighting", {ResultIdentity("gbuffer", {}), ResultIdentity("shadow", {})})) << "built apart";
  EXPECT_FALSE(a == ResultIdentity("lighting", {ResultIdentity("gbuffer", {}), ResultIdentity("shadow 2", {})}));
  EXPECT_FALSE(a == ResultIdentity("lighting", {ResultIdentity("shadow", {}), ResultIdentity("gbuffer", {})})) << "order matters";
  EXPECT_FALSE(a == ResultIdentity("lighting", {ResultIdentity("gbuffer", {})}));
  EXPECT_FALSE(ResultIdentity("ab", {}) == ResultIdentity("a", {ResultIdentity("b", {})}));
  // Equal hashes are then confirmed by comparing the descriptions and inputs themselves: that path
  // is taken by every equal pair above, and a 64-bit collision to exercise its refusal is not at hand.
}

}  // namespace
}  // namespace caustica::graph
