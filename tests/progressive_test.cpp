// Progressive caustics (graphs/caustics_progressive.json): a jittered photon grid averaged over
// frames by an accumulate pass, and the history's reset rules.
#include <gtest/gtest.h>

#include "reference/image_metrics.h"
#include "reference/photon_reference.h"
#include "scene_engine.h"

namespace caustica {
namespace {

using test::load_bundled_scene;
using test::relative_difference;
using test::SceneEngine;

// A small light map and photon grid keep each frame to milliseconds on lavapipe.
const std::vector<std::string> kSmall = {"caustic_size=128", "light_size=256", "shadow_size=256"};

std::vector<std::string> with(std::vector<std::string> sets, const std::vector<std::string>& more) {
  sets.insert(sets.end(), more.begin(), more.end());
  return sets;
}

// Runs `frames` frames of the graph on `scene` and returns the caustic map the lighting saw. The
// plan is set up anew (a fresh mean) unless `go_on`, which keeps it and its history.
io::ImageData accumulated(SceneEngine& e, std::shared_ptr<const scene::Scene> scene, const std::vector<std::string>& sets, uint32_t frames,
                          double* counted = nullptr, bool go_on = false) {
  auto graph = graph::load_graph_file((data_dir() / "graphs/caustics_progressive.json").string());
  graph::apply_overrides(graph, sets);
  e.executor.set_scene(std::move(scene));
  if (!go_on) e.executor.invalidate();
  e.executor.configure(graph, e.width, e.height, {"caustics"});
  graph::FrameResult last;
  for (uint32_t f = 0; f < frames; ++f) last = e.executor.run_frame(f + 1 == frames);
  if (counted) *counted = last.counters.at("accumulate.frames");
  return e.executor.read_image("caustics");
}

// 16 frames of a 128^2 grid against one frame of the 512^2 grid (the same photon count): the mean
// must come far closer to it than any single frame, and only because the grid moves: with the
// jitter off every frame repeats the first.
TEST(Progressive, JitteredMapsAverageToTheMapOfAFinerGrid) {
  SceneEngine e;
  auto scene = load_bundled_scene("sphere_plane");
  e.render("caustics_regular", scene, with(kSmall, {"grid=512"}), {"caustics"});
  const io::ImageData reference = e.executor.read_image("caustics");
  const double one = relative_difference(accumulated(e, scene, with(kSmall, {"grid=128"}), 1), reference);
  double frames = 0;
  const double mean = relative_difference(accumulated(e, scene, with(kSmall, {"grid=128"}), 16, &frames), reference);
  const double unjittered = relative_difference(accumulated(e, scene, with(kSmall, {"grid=128", "jitter=false"}), 16), reference);
  std::printf("against the 512^2 map: one 128^2 frame %.4f, the mean of 16 jittered %.4f, of 16 unjittered %.4f\n", one, mean, unjittered);
  EXPECT_EQ(frames, 16.0);
  EXPECT_LT(mean, 0.35 * one);
  EXPECT_GT(unjittered, 0.9 * one);
}

// The mean survives a camera move (the map is in the light's space) and restarts when the light
// moves, its first frame then equal to a fresh render of the new state; max_frames holds it still.
TEST(Progressive, ALightChangeRestartsTheMeanAndACameraMoveDoesNot) {
  SceneEngine e;
  auto scene = load_bundled_scene("sphere_plane");
  const auto sets = with(kSmall, {"grid=64"});
  double frames = 0;
  accumulated(e, scene, sets, 8, &frames);
  EXPECT_EQ(frames, 8.0);

  auto moved_camera = std::make_shared<scene::Scene>(*scene);
  moved_camera->camera.position += glm::vec3(0.5f, 0.2f, 0.0f);
  accumulated(e, moved_camera, sets, 1, &frames, true);
  EXPECT_EQ(frames, 9.0) << "a camera move reset the light-space mean";

  auto moved_light = std::make_shared<scene::Scene>(*moved_camera);
  moved_light->lights[0].view.position += glm::vec3(0.3f, 0.0f, 0.0f);
  const io::ImageData after_move = accumulated(e, moved_light, sets, 1, &frames, true);
  EXPECT_EQ(frames, 1.0) << "a light move kept the old mean";
  SceneEngine fresh;
  EXPECT_LT(relative_difference(after_move, accumulated(fresh, moved_light, sets, 1)), 1e-6);

  accumulated(e, moved_light, with(sets, {"max_frames=3"}), 5, &frames);
  EXPECT_EQ(frames, 3.0);
}

// Still frames converge to the exact caustic only where each frame's photons are exact: with
// distance=ray_query the mean of 16 jittered 64^2 frames comes far closer to the photon reference
// than one frame, while the image-space d_V/d_N estimate, averaged as long, keeps its own bias.
// Against 4e6 reference photons, after the chart's blur (docs/accuracy.md); when this was written:
// one exact frame 0.423, the mean of 16 0.131, 16 image-space frames 0.335 (a doubled error of the
// mean fails both bounds; with the jitter off the mean is one frame's map, 0.423, and fails).
TEST(Progressive, ExactPhotonsAccumulateTowardTheExactCaustic) {
  SceneEngine e;
  ASSERT_TRUE(e.vk.ray_queries().available) << "lavapipe 25 has ray queries; this device lacks " << e.vk.ray_queries().missing;
  auto scene = load_bundled_scene("bunny_plane");
  reference::PhotonOptions options;
  options.photons = 4'000'000;
  options.map_size = 128;
  const io::ImageData exact = reference::trace_photon_reference(*scene, options).caustic_map;
  auto error = [&](const io::ImageData& map) { return reference::compare_images(map, exact, 1.5).relative_l1; };
  const auto traced = with(kSmall, {"grid=64", "distance=ray_query"});
  const double one = error(accumulated(e, scene, traced, 1));
  const double mean = error(accumulated(e, scene, traced, 16));
  const double image_space = error(accumulated(e, scene, with(kSmall, {"grid=64", "distance=dv_dn"}), 16));
  std::printf("bunny against the photon reference: one exact 64^2 frame %.4f, the mean of 16 %.4f; 16 image-space (d_V/d_N) frames %.4f\n",
              one, mean, image_space);
  EXPECT_LT(mean, 0.6 * one);
  EXPECT_LT(mean, 0.5 * image_space);
}

// The same frames give the same mean in another run (a GPU's atomics may add a texel's photons in
// another order: equal to float rounding).
TEST(Progressive, FramesRepeatRunToRun) {
  auto scene = load_bundled_scene("sphere_plane");
  const auto sets = with(kSmall, {"grid=64"});
  SceneEngine a, b;
  const io::ImageData first = accumulated(a, scene, sets, 8);
  EXPECT_LT(relative_difference(accumulated(b, scene, sets, 8), first), 1e-6);
}

// With reuse on (the viewer's setting), a frame runs only the passes whose scene parts changed:
// after a camera move those that see the camera, after a light move the light's passes too, with
// nothing changed none; and each such frame is the picture a fresh render of that state gives. The
// skipped caustic pass's counters are reported as it last set them.
TEST(Progressive, UnchangedPassesAreSkippedAndFramesStayThoseOfAFreshRender) {
  SceneEngine e;
  e.executor.set_reuse_unchanged_passes(true);
  auto graph = graph::load_graph_file((data_dir() / "graphs/caustics_adaptive.json").string());
  graph::apply_overrides(graph, with(kSmall, {"grid=256"}));
  std::set<std::string> ran;
  auto frame = [&](SceneEngine& engine, std::shared_ptr<const scene::Scene> scene) {
    engine.executor.set_scene(std::move(scene));
    engine.executor.configure(graph, engine.width, engine.height, {"caustics"});
    const graph::FrameResult result = engine.executor.run_frame(true);
    ran.clear();
    for (const auto& pass : result.passes) {
      if (pass.ran) ran.insert(pass.name);
    }
    return result;
  };
  // A fresh engine (without reuse) renders each state for comparison.
  auto expect_fresh = [&](const std::shared_ptr<const scene::Scene>& scene, const char* state) {
    SceneEngine fresh;
    const std::set<std::string> ran_here = ran;
    frame(fresh, scene);
    for (const char* image : {"ldr", "caustics"}) {
      EXPECT_LT(relative_difference(e.executor.read_image(image), fresh.executor.read_image(image)), 1e-6) << image << " after " << state;
    }
    ran = ran_here;
  };
  auto scene = load_bundled_scene("sphere_plane");
  const graph::FrameResult first = frame(e, scene);
  EXPECT_EQ(ran.size(), first.passes.size()) << "the first frame skipped a pass";

  auto moved_camera = std::make_shared<scene::Scene>(*scene);
  moved_camera->camera.position += glm::vec3(0.5f, 0.2f, 0.0f);
  frame(e, moved_camera);
  EXPECT_EQ(ran, (std::set<std::string>{"gbuffer", "lighting", "refraction", "tonemap"})) << "after a camera move";
  expect_fresh(moved_camera, "a camera move");

  auto moved_light = std::make_shared<scene::Scene>(*moved_camera);
  moved_light->lights[0].view.position += glm::vec3(0.3f, 0.0f, 0.0f);
  const graph::FrameResult lit = frame(e, moved_light);
  EXPECT_EQ(ran.size(), first.passes.size() - 1) << "after a light move";
  EXPECT_EQ(ran.count("gbuffer"), 0u) << "the G-buffer does not see the light";
  expect_fresh(moved_light, "a light move");

  const graph::FrameResult still = frame(e, moved_light);
  EXPECT_TRUE(ran.empty()) << "a frame with nothing changed ran " << *ran.begin();
  expect_fresh(moved_light, "a frame with nothing changed");
  EXPECT_GT(lit.counters.at("caustic.flux"), 0.0);
  EXPECT_EQ(still.counters.at("caustic.flux"), lit.counters.at("caustic.flux"));
}

}  // namespace
}  // namespace caustica
