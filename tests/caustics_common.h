#pragma once
// Shared by the caustics_*_test.cpp files (one binary, caustics_test): the engine that renders the lit
// image and the caustic map at kWidth x kHeight, bundled scenes, and the ball lens's exact flux.
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "ball_lens.h"
#include "scene_engine.h"

namespace caustica::test::caustic_tests {

inline constexpr uint32_t kWidth = 320, kHeight = 180;

// SceneEngine renders at kWidth x kHeight (320 x 180).
struct Engine : test::SceneEngine {
  graph::FrameResult render(const std::string& graph_name, std::shared_ptr<const scene::Scene> scene,
                            const std::vector<std::string>& sets) {
    return SceneEngine::render(graph_name, std::move(scene), sets, {"lit", "caustics"});
  }
};

inline std::shared_ptr<scene::Scene> load(const std::string& name) {
  return test::load_bundled_scene(name);
}

using test::flux_into_ball;

// The flux per channel a caustic map lands on the floor under each half of tests/data/gltf's
// two-part panes (make_textured.py: 1.6 square, 1 above the floor, the halves split at x = 0),
// the -x half first; away from the halves' seam and edges.
inline std::array<glm::dvec3, 2> flux_under_pane_halves(const scene::Scene& scene, const io::ImageData& map) {
  std::array<glm::dvec3, 2> flux{glm::dvec3(0.0), glm::dvec3(0.0)};
  test::for_each_floor_point(scene, map, [&](const glm::dvec3& floor, const glm::dvec3& rgb) {
    if (std::abs(floor.z) > 0.9 || std::abs(floor.x) < 0.1 || std::abs(floor.x) > 0.9) return;
    flux[floor.x < 0.0 ? 0 : 1] += rgb;
  });
  return flux;
}

}  // namespace caustica::test::caustic_tests
