// Caustics on the device (lavapipe, validation on; any message fails): energy bookkeeping against
// the exact flux into the ball lens, and n = 1, where the caustic must exactly replace the shadow.
#include <gtest/gtest.h>

#include <cmath>
#include <glm/gtc/constants.hpp>

#include "builtin_passes.h"
#include "core/paths.h"
#include "graph/executor.h"

using namespace caustica;

namespace {

constexpr uint32_t kWidth = 320, kHeight = 180;

struct Engine {
  vk::Context vk{{"", true, false}};
  shader::ShaderCompiler shaders{data_dir() / "shaders"};
  graph::Executor executor{vk, shaders, passes::builtin_registry()};

  graph::FrameResult render(const std::string& graph_name, std::shared_ptr<const scene::Scene> scene, const std::vector<std::string>& sets) {
    auto graph = graph::load_graph_file((data_dir() / "graphs" / (graph_name + ".json")).string());
    graph::apply_overrides(graph, sets);
    executor.set_scene(std::move(scene));
    executor.configure(graph, kWidth, kHeight, {"lit"});
    return executor.run_frame(true);
  }
  ~Engine() { EXPECT_EQ(vk.validation_messages(), 0u); }
};

std::shared_ptr<scene::Scene> load(const std::string& name) {
  return std::make_shared<scene::Scene>(scene::load_scene_file((data_dir() / "scenes" / (name + ".json")).string()));
}

}  // namespace

// The ball lens lit by a spot light at distance D from its centre: the flux entering the sphere is
// the intensity times the solid angle of the sphere, 2 pi (1 - sqrt(1 - R^2 / D^2)). Without
// Fresnel or absorption every entering photon is either splatted or reported dropped.
TEST(Caustics, RegularMapConservesTheFluxEnteringTheBallLens) {
  Engine e;
  auto scene = load("sphere_plane");
  const auto& light = scene->lights[0];
  const auto& ball = scene->objects.back();
  const double distance = static_cast<double>(glm::length(ball.center() - light.view.position)), radius = 1.0;
  const double entering = static_cast<double>(light.intensity) * glm::two_pi<double>() * (1.0 - std::sqrt(1.0 - radius * radius / (distance * distance)));
  for (const char* distance_mode : {"dv", "dv_dn"}) {
    auto frame = e.render("caustics_regular", scene, {"fresnel=false", "grid=1024", std::string("distance=") + distance_mode});
    const double in = frame.counters.at("caustic.flux_entering"), splatted = frame.counters.at("caustic.flux"),
                 dropped = frame.counters.at("caustic.flux_dropped");
    std::printf("%-6s entering %.4f (exact %.4f), splatted %.4f (%.1f%%), dropped %.4f, photons %.0f processed, %.0f splatted, %.0f TIR\n",
                distance_mode, in, entering, splatted, 100.0 * splatted / in, dropped, frame.counters.at("photons.processed"),
                frame.counters.at("photons.splatted"), frame.counters.at("photons.dropped_tir"));
    EXPECT_NEAR(in, entering, 0.01 * entering) << distance_mode;  // the silhouette sampled by 1024^2 photons
    EXPECT_NEAR(splatted + dropped, in, 1e-3 * in) << distance_mode;
    EXPECT_LE(splatted, in) << distance_mode;
    EXPECT_EQ(frame.counters.at("photons.processed"), 1024.0 * 1024.0);
  }
}

// n = 1: the refractor bends nothing, so on the floor the caustic plus the shadowed direct light
// must equal the direct light of the scene without the sphere (ORACLES.md).
TEST(Caustics, IndexOneMakesTheCausticFillTheShadowExactly) {
  Engine e;
  auto invisible = load("sphere_plane");
  invisible->objects.back().material.ior = 1.0f;
  auto without = load("sphere_plane");
  without->objects.pop_back();
  e.render("caustics_regular", invisible, {"fresnel=false", "grid=2048", "caustic_size=512"});
  const io::ImageData with_caustic = e.executor.read_image("lit");
  e.render("caustics_regular", without, {});
  const io::ImageData direct = e.executor.read_image("lit");
  // "lit" has no refractor in it (the G-buffer holds opaque geometry only): every pixel compares.
  double diff = 0, total = 0;
  size_t pixels = 0, off = 0;
  for (size_t i = 0; i < size_t{kWidth} * kHeight; ++i) {
    const float a = with_caustic.rgba[i * 4 + 1], b = direct.rgba[i * 4 + 1];
    diff += static_cast<double>(std::abs(a - b));
    total += static_cast<double>(b);
    ++pixels;
    if (std::abs(a - b) > 0.05f * b + 0.01f) ++off;
  }
  std::printf("n = 1: mean relative difference %.4f, %zu of %zu pixels off by more than 5%%\n", diff / total, off, pixels);
  EXPECT_LT(diff / total, 0.01);
  EXPECT_LT(static_cast<double>(off), 0.01 * static_cast<double>(pixels));
}
