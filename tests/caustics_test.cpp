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
    executor.configure(graph, kWidth, kHeight, {"lit", "caustics"});
    return executor.run_frame(true);
  }
  ~Engine() { EXPECT_EQ(vk.validation_messages(), 0u); }
};

std::shared_ptr<scene::Scene> load(const std::string& name) {
  return std::make_shared<scene::Scene>(scene::load_scene_file((data_dir() / "scenes" / (name + ".json")).string()));
}

// The exact flux a spot light sends into a sphere (ORACLES.md's ball lens): intensity times the
// sphere's solid angle seen from the light.
double flux_into_ball(const scene::Scene& scene) {
  const auto& light = scene.lights[0];
  const auto& ball = scene.objects.back();
  const double distance = static_cast<double>(glm::length(ball.center() - light.view.position));
  const double radius = 0.5 * static_cast<double>(ball.bounds_max.y - ball.bounds_min.y);
  return static_cast<double>(light.intensity) * glm::two_pi<double>() * (1.0 - std::sqrt(1.0 - radius * radius / (distance * distance)));
}

const char* kAdaptiveGraphs[] = {"caustics_adaptive_maxlevel", "caustics_adaptive_maxerror", "caustics_adaptive"};

}  // namespace

// The ball lens lit by a spot light at distance D from its centre: the flux entering the sphere is
// the intensity times the solid angle of the sphere, 2 pi (1 - sqrt(1 - R^2 / D^2)). Without
// Fresnel or absorption every entering photon is either splatted or reported dropped.
TEST(Caustics, RegularMapConservesTheFluxEnteringTheBallLens) {
  Engine e;
  auto scene = load("sphere_plane");
  const double entering = flux_into_ball(*scene);
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

// Every adaptive criterion on the ball lens at 2048^2: the flux of the photons that meet the sphere
// within 1.5% of the exact value (the 64 x 64 start drops clusters whose four photons all miss,
// so a little of the silhouette is lost, never gained); splatted plus dropped equals it; the
// flux that lands matches the regular map's within 1%; and fewer photons than the regular grid.
TEST(Caustics, AdaptiveMapsKeepTheEnergyWithFewerPhotons) {
  Engine e;
  auto scene = load("sphere_plane");
  const double exact = flux_into_ball(*scene);
  auto regular = e.render("caustics_regular", scene, {"fresnel=false", "grid=2048"});
  for (const char* graph : kAdaptiveGraphs) {
    auto frame = e.render(graph, scene, {"fresnel=false", "grid=2048"});
    const double in = frame.counters.at("caustic.flux_entering"), splatted = frame.counters.at("caustic.flux"),
                 dropped = frame.counters.at("caustic.flux_dropped"), processed = frame.counters.at("photons.processed");
    std::printf("%-28s entering %.4f (exact %.4f), splatted %.4f (regular %.4f), processed %.0f (regular %.0f, %.1f%%), converged %.0f\n", graph,
                in, exact, splatted, regular.counters.at("caustic.flux"), processed, regular.counters.at("photons.processed"),
                100.0 * processed / regular.counters.at("photons.processed"), frame.counters.at("photons.converged"));
    EXPECT_NEAR(in, exact, 0.015 * exact) << graph;
    EXPECT_LE(in, exact * 1.001) << graph;
    EXPECT_NEAR(splatted + dropped, in, 1e-3 * in) << graph;
    EXPECT_NEAR(splatted, regular.counters.at("caustic.flux"), 0.01 * regular.counters.at("caustic.flux")) << graph;
    EXPECT_LT(processed, regular.counters.at("photons.processed")) << graph;
    EXPECT_EQ(frame.counters.at("photons.overflow"), 0.0) << graph;
  }
}

// Batching changes the order photons are processed in, nothing else: the same photons, the same
// caustic map up to float rounding of the atomic sums.
TEST(Caustics, BatchedEqualsUnbatched) {
  Engine e;
  auto scene = load("sphere_plane");
  auto one = e.render("caustics_adaptive", scene, {"grid=2048", "photon_memory_mib=64"});
  const io::ImageData map_one = e.executor.read_image("caustics");
  auto many = e.render("caustics_adaptive", scene, {"grid=2048", "photon_memory_mib=1"});
  const io::ImageData map_many = e.executor.read_image("caustics");
  EXPECT_EQ(one.counters.at("photons.batches"), 1.0);
  EXPECT_GT(many.counters.at("photons.batches"), 4.0);
  for (const char* counter : {"photons.processed", "photons.splatted", "photons.converged", "photons.dropped_tir", "photons.dropped_miss"}) {
    EXPECT_EQ(one.counters.at(counter), many.counters.at(counter)) << counter;
  }
  double difference = 0, total = 0;
  for (size_t i = 0; i < map_one.rgba.size(); i += 4) {
    difference += static_cast<double>(std::abs(map_one.rgba[i] - map_many.rgba[i]));
    total += static_cast<double>(map_one.rgba[i]);
  }
  EXPECT_GT(total, 0.0);
  EXPECT_LT(difference / total, 1e-5);
}

// An effective grid of 16384^2 within a 16 MiB bound: batches, and a peak below the bound.
TEST(Caustics, PeakPhotonMemoryStaysUnderTheLimit) {
  Engine e;
  auto frame = e.render("caustics_adaptive", load("sphere_plane"), {"grid=16384", "photon_memory_mib=16"});
  std::printf("16384^2: %.0f batches, peak %.0f bytes, %.0f photons processed\n", frame.counters.at("photons.batches"),
              frame.counters.at("photons.peak_bytes"), frame.counters.at("photons.processed"));
  EXPECT_GT(frame.counters.at("photons.batches"), 1.0);
  EXPECT_LE(frame.counters.at("photons.peak_bytes"), 16.0 * 1024 * 1024);
  EXPECT_GT(frame.counters.at("photons.peak_bytes"), 0.0);
  EXPECT_EQ(frame.counters.at("photons.overflow"), 0.0);
  EXPECT_GT(frame.counters.at("photons.processed.level8"), 0.0);  // 64 * 2^8 = 16384: the last level ran
}

// The hierarchical traversal skips only clusters the coverage pyramid shows free of refractors, so
// it traces exactly the photons of the regular grid that meet a refractor, and no others.
TEST(Caustics, HierarchicalTracesExactlyTheRegularGridsRefractorPhotons) {
  Engine e;
  auto scene = load("sphere_plane");
  auto regular = e.render("caustics_regular", scene, {"grid=2048"});
  auto hierarchical = e.render("caustics_hierarchical", scene, {"grid=2048"});
  EXPECT_EQ(hierarchical.counters.at("photons.splatted"), regular.counters.at("photons.splatted"));
  EXPECT_EQ(hierarchical.counters.at("photons.dropped_tir"), regular.counters.at("photons.dropped_tir"));
  EXPECT_NEAR(hierarchical.counters.at("caustic.flux"), regular.counters.at("caustic.flux"), 1e-4 * regular.counters.at("caustic.flux"));
  EXPECT_LT(hierarchical.counters.at("photons.processed"), 0.25 * regular.counters.at("photons.processed"));
}
