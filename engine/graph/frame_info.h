#pragma once
#include <glm/vec2.hpp>

#include <cstdint>

namespace caustica::graph {

// Which frame is being recorded, as a pass sees it: its index since the plan was set up, and the
// frames since any scene part the pass depends on (PlannedPass::depends: geometry, lights, camera,
// directly or through its inputs) last changed, or the plan was set up. Passes that vary from
// frame to frame (a jittered photon grid) and passes that keep history (accumulate) follow
// since_reset, so that the first frame after such a change is the first frame of a fresh render,
// and a change they do not depend on (the camera, for light-space history) keeps their history.
struct FrameInfo {
  uint64_t index = 0;
  uint64_t since_reset = 0;
  // Where in its pixel this frame's camera looks, in pixels from the centre: zero unless the plan
  // jitters the camera (Plan::jitters_camera), and then zero on the first frame after the scene
  // (camera, lights, geometry) changed.
  glm::vec2 camera_jitter{0.0f};
};

}  // namespace caustica::graph
