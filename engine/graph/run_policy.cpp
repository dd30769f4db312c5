#include "graph/run_policy.h"

#include <algorithm>

namespace caustica::graph {

SceneKeys SceneKeys::masked(uint32_t depends, uint32_t lights_followed) const {
  SceneKeys kept;
  for (size_t k = 0; k < kSceneParts.size(); ++k) {
    if (depends & kSceneParts[k]) kept.parts[k] = parts[k];
  }
  // Some lights only: the key of those (a light added or removed recompiles the plan).
  if ((depends & kDependsOnLights) && parts[1] && lights_followed != kAllLights && !lights.empty()) {
    uint64_t key = 0xcbf29ce484222325ull;
    for (size_t i = 0; i < lights.size() && i < 32; ++i) {
      if (lights_followed >> i & 1u) key = (key ^ lights[i]) * 0x100000001b3ull;
    }
    kept.parts[1] = key;
  }
  return kept;
}

bool runs(PassRun run) {
  return run == PassRun::start_over || run == PassRun::run;
}

const char* pass_run_name(PassRun run) {
  switch (run) {
    case PassRun::start_over: return "start over";
    case PassRun::run: return "run";
    case PassRun::keep: return "keep";
    case PassRun::outside_part: return "outside the frame's part";
    case PassRun::waits_for_step: return "waits for its display step";
  }
  return "?";
}

RunState initial_run_state(const Plan& plan) {
  RunState state;
  state.passes.resize(plan.passes.size());
  return state;
}

namespace {

bool in_part(const PlannedPass& pass, FramePart part, DisplayStep step) {
  if (part == FramePart::whole) return true;
  if (part == FramePart::refine) return pass.refines;
  return !pass.refines && pass.showing >= step.first && pass.showing < step.last;
}

bool keeps_history(const PlannedResource& r) {
  return r.previous_of != kNoResource && r.used();
}

}  // namespace

FrameDecision decide_frame(const Plan& plan, const RunState& state, const std::optional<SceneKeys>& scene_keys, FrameRequest request) {
  const SceneKeys scene = scene_keys.value_or(SceneKeys{});
  FrameDecision decision;
  decision.part = plan.refines_apart ? request.part : FramePart::whole;
  // Something new to work on: no result yet, or a scene part the pass depends on changed since its
  // result started.
  const auto has_new_work = [&](size_t i) {
    return state.passes[i].started_from != scene.masked(plan.passes[i].depends, plan.passes[i].lights);
  };
  // While the picture of the plan before stands for this scene, a showing pass that has not run yet
  // waits for its display step; one that a step would need before it has to run now.
  const bool picture_stands = state.standing == scene;
  const auto waits = [&](size_t i) {
    const PlannedPass& pass = plan.passes[i];
    return picture_stands && !state.passes[i].started_from && !pass.refines &&
           (decision.part == FramePart::refine || pass.showing >= request.step.last);
  };
  // A frame apart runs whole when a pass outside its part has something new to work on: the part's
  // passes would read what no longer fits the scene.
  for (size_t i = 0; i < plan.passes.size() && decision.part != FramePart::whole; ++i) {
    if (!in_part(plan.passes[i], decision.part, request.step) && has_new_work(i) && !waits(i)) decision.part = FramePart::whole;
  }
  decision.passes.resize(plan.passes.size());
  for (size_t i = 0; i < plan.passes.size(); ++i) {
    const PlannedPass& pass = plan.passes[i];
    if (!in_part(pass, decision.part, request.step))
      decision.passes[i] = waits(i) ? PassRun::waits_for_step : PassRun::outside_part;
    else if (has_new_work(i))
      decision.passes[i] = PassRun::start_over;
    else
      decision.passes[i] = pass.reusable(plan.reuses_unchanged_passes) ? PassRun::keep : PassRun::run;
  }
  // Counted from the scene's last change (the camera, a light, the geometry), so that the first
  // frame after any change is a fresh render's; a display frame shows and does not move it.
  decision.jitters = scene_keys && plan.jitters_camera && decision.part != FramePart::display;
  if (decision.jitters) decision.jitter_frame = state.jitter_scene == scene ? state.jittered_frames : 0;
  // A history resource restarts when what its source depends on changed (a camera move leaves
  // light-space history), and on its first frame.
  for (uint32_t h = 0; h < plan.resources.size(); ++h) {
    if (!keeps_history(plan.resources[h])) continue;
    const auto last = state.history_scene.find(h);
    decision.history_restarts[h] = last == state.history_scene.end() || last->second != scene.masked(plan.resources[h].history_depends);
  }
  return decision;
}

void begin_frame(const Plan& plan, RunState& state, const FrameDecision& decision, const std::optional<SceneKeys>& scene_keys,
                 glm::vec2 camera_jitter) {
  const SceneKeys scene = scene_keys.value_or(SceneKeys{});
  for (size_t i = 0; i < plan.passes.size(); ++i) {
    PassRunState& pass = state.passes[i];
    pass.frames.index = state.frame_index;
    pass.frames.camera_jitter = camera_jitter;
    if (decision.passes[i] == PassRun::start_over) {
      pass.started_from = scene.masked(plan.passes[i].depends, plan.passes[i].lights);
      pass.frames.since_reset = 0;
    }
    if (runs(decision.passes[i])) {
      pass.converging = false;
      pass.frames_held.reset();
    }
  }
  if (decision.jitters) {
    state.jitter_scene = scene;
    state.jittered_frames = decision.jitter_frame + 1;
  }
  for (const auto& [h, restart] : decision.history_restarts) state.history_scene[h] = scene.masked(plan.resources[h].history_depends);
}

FrameAccount end_frame(const Plan& plan, RunState& state, const FrameDecision& decision, const std::optional<SceneKeys>& scene_keys) {
  const SceneKeys scene = scene_keys.value_or(SceneKeys{});
  FrameAccount account{state.frame_index, 0};
  for (size_t i = 0; i < plan.passes.size(); ++i) {
    PassRunState& pass = state.passes[i];
    const PlannedPass& planned = plan.passes[i];
    if (runs(decision.passes[i])) pass.last_run_scene = scene;
    // A display frame shows the running results as the last refining frame left them.
    if (decision.part == FramePart::whole || planned.refines) {
      const uint64_t shown =
          decision.part == FramePart::display && pass.frames.since_reset > 0 ? pass.frames.since_reset - 1 : pass.frames.since_reset;
      account.since_reset = std::min(account.since_reset, shown);
    }
    // A pass outside the frame's part stays where it was: the next frame it runs is its next one (a
    // slice of a photon grid, a jitter).
    const bool in_frame = decision.passes[i] != PassRun::outside_part && decision.passes[i] != PassRun::waits_for_step;
    if (in_frame) ++pass.frames.since_reset;
    if (planned.decl && planned.decl->accumulates) {
      const uint64_t held = pass.frames_held ? std::min(*pass.frames_held, pass.frames.since_reset) : pass.frames.since_reset;
      account.accumulated = account.accumulated == 0 ? held : std::min(account.accumulated, held);
    }
  }
  // Every pass has a result of this plan's: the picture is its own.
  if (state.standing &&
      std::all_of(state.passes.begin(), state.passes.end(), [](const PassRunState& p) { return p.started_from.has_value(); }))
    state.standing.reset();
  state.last_scene = scene;
  ++state.frame_index;
  return account;
}

}  // namespace caustica::graph
