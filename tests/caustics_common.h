#pragma once
// Shared by the caustics_*_test.cpp files (one binary, caustics_test): the engine that renders the lit
// image and the caustic map at kWidth x kHeight, bundled scenes, and the ball lens's exact flux.
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

}  // namespace caustica::test::caustic_tests
