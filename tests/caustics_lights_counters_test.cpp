// Caustics on the device: directional lights, the counters every method reports, and the photon
// memory bound (batching, its peak, and a set-up that fails without breaking the running plan).
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <glm/gtc/constants.hpp>

#include "caustics_common.h"
#include "reference/image_metrics.h"
#include "reference/photon_reference.h"

using namespace caustica;
using namespace caustica::test::caustic_tests;

// A plan whose set-up fails (a shader saved with an error, as the viewer's hot reload meets it)
// throws with the shader's file and line and leaves the running plan whole: the viewer keeps the
// last good shaders this way. A graph the compiler refuses (a grid too large for its memory bound)
// leaves it whole too.
TEST(Caustics, AFailedSetUpKeepsTheRunningPlan) {
  const auto root = std::filesystem::temp_directory_path() / ("caustica_setup_" + std::to_string(::getpid()));
  std::filesystem::remove_all(root);
  std::filesystem::create_directories(root);
  std::filesystem::copy(data_dir() / "shaders", root / "shaders", std::filesystem::copy_options::recursive);
  vk::Context vk{{"", true, false}};
  shader::ShaderCompiler shaders{root / "shaders"};
  graph::Executor executor{vk, shaders, passes::builtin_registry()};
  executor.set_scene(load("sphere_plane"));
  auto graph = graph::load_graph_file((data_dir() / "graphs/caustics_adaptive.json").string());
  graph::apply_overrides(graph, {"grid=1024"});
  executor.configure(graph, 160, 90, {.retained = {"lit", "caustics"}});
  const graph::FrameResult first = executor.run_frame(true);
  const auto compiled = executor.compile_count();
  std::ofstream(root / "shaders/core/tonemap.comp", std::ios::app) << "\nnot glsl;\n";
  try {
    executor.configure(graph, 160, 90, {.retained = {"lit", "caustics"}, .hand_over = {.start_over = true}});
    ADD_FAILURE() << "a shader with an error was set up";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("tonemap.comp:"), std::string::npos) << e.what();
  }
  auto too_large = graph;
  graph::apply_overrides(too_large, {"grid=65536", "photon_memory_mib=1"});
  EXPECT_THROW(executor.configure(too_large, 160, 90, {.retained = {"lit", "caustics"}}), InputError);
  EXPECT_EQ(executor.compile_count(), compiled);
  const graph::FrameResult again = executor.run_frame(true);
  EXPECT_EQ(again.counters.at("photons.processed"), first.counters.at("photons.processed"));
  EXPECT_NEAR(again.counters.at("caustic.flux"), first.counters.at("caustic.flux"), 1e-4 * first.counters.at("caustic.flux"));
  EXPECT_EQ(vk.validation_messages(), 0u);
  std::filesystem::remove_all(root);
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
  for (const char* counter :
       {"photons.processed", "photons.splatted", "photons.converged", "photons.dropped_tir", "photons.dropped_miss"}) {
    EXPECT_EQ(one.counters.at(counter), many.counters.at(counter)) << counter;
  }
  EXPECT_GT(one.counters.at("caustic.flux"), 0.0);
  EXPECT_LT(test::relative_difference(map_many, map_one), 1e-5);
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

// Every caustic method reports the same counters, under the names the trace and --stats show.
TEST(Caustics, EveryMethodReportsEveryCounter) {
  Engine e;
  auto scene = load("sphere_plane");
  for (const char* graph :
       {"caustics_regular", "caustics_hierarchical", "caustics_adaptive_maxlevel", "caustics_adaptive_maxerror", "caustics_adaptive"}) {
    auto frame = e.render(graph, scene, {"grid=256"});
    for (const char* counter : {"photons.processed", "photons.processed.level0", "photons.splatted", "photons.dropped_miss",
                                "photons.dropped_tir", "photons.converged", "photons.batches", "photons.peak_bytes", "caustic.flux"}) {
      EXPECT_EQ(frame.counters.count(counter), 1u) << graph << " " << counter;
    }
    EXPECT_GT(frame.counters.at("photons.processed"), 0.0) << graph;
    EXPECT_GE(frame.counters.at("photons.batches"), 1.0) << graph;
  }
}

// A directional light casts caustics through an orthographic light map (scenes/sphere_sun.json,
// the ball lens under parallel light): the flux entering the sphere is the irradiance times its
// cross section, every entering photon is splatted or reported dropped, the ray-query tracer's map
// matches the photon reference's, and the floor outside the ball's shadow gets E cos / pi.
TEST(Caustics, DirectionalLightsCastCausticsThroughAnOrthographicMap) {
  Engine e;
  auto scene = load("sphere_sun");
  const double irradiance = static_cast<double>(scene->lights.front().intensity);
  auto frame = e.render("caustics_regular", scene, {"fresnel=false", "grid=1024"});
  const double in = frame.counters.at("caustic.flux_entering"), splatted = frame.counters.at("caustic.flux"),
               dropped = frame.counters.at("caustic.flux_dropped");
  std::printf("directional: entering %.4f (pi R^2 E = %.4f), splatted %.4f, dropped %.4f\n", in, glm::pi<double>() * irradiance, splatted,
              dropped);
  EXPECT_NEAR(in, glm::pi<double>() * irradiance, 0.015 * in);
  EXPECT_NEAR(splatted + dropped, in, 1e-3 * in);

  reference::PhotonOptions options;
  options.photons = 20'000'000;
  options.fresnel = false;
  const auto reference = reference::trace_photon_reference(*scene, options);
  e.render("caustics_raytraced", scene, {"fresnel=false", "grid=1024"});
  const auto exact = reference::compare_images(e.executor.read_image("caustics"), reference.caustic_map, 1.5);
  std::printf("directional: ray-query map against the reference: energy %.4f, relative L1 %.4f\n", exact.energy_ratio, exact.relative_l1);
  EXPECT_NEAR(exact.energy_ratio, 1.0, 0.02);
  EXPECT_LT(exact.relative_l1, 0.1);

  // Lit floor at the image's bottom centre (in front of the ball, outside its shadow): albedo 0.8
  // times ambient sky plus E cos(0) / pi, the light straight above.
  const io::ImageData lit = e.executor.read_image("lit");
  const float* p = &lit.rgba[(size_t{kHeight - 4} * kWidth + kWidth / 2) * 4];
  const double expected = 0.8 * (static_cast<double>(scene->ambient * scene->sky.g) + irradiance / glm::pi<double>());
  EXPECT_NEAR(static_cast<double>(p[1]), expected, 0.01 * expected);
}
