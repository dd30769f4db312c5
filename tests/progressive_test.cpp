// Progressive caustics (graphs/caustics_progressive.json): a jittered photon grid averaged over
// frames by an accumulate pass, and the history's reset rules.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <set>

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

// Runs `frames` frames of the graph (caustics_progressive unless named) on `scene` and returns the
// caustic map the lighting saw (or the first of `outputs`, all of which the plan keeps). The plan is
// set up anew (a fresh mean) unless `go_on`, which keeps it and its history.
io::ImageData accumulated(SceneEngine& e, std::shared_ptr<const scene::Scene> scene, const std::vector<std::string>& sets, uint32_t frames,
                          double* counted = nullptr, bool go_on = false, const std::string& graph_name = "caustics_progressive",
                          const std::vector<std::string>& outputs = {"caustics"}) {
  auto graph = graph::load_graph_file((data_dir() / "graphs" / (graph_name + ".json")).string());
  graph::apply_overrides(graph, sets);
  e.executor.set_scene(std::move(scene));
  if (!go_on) e.next.start_over = true;
  e.configure(graph, e.width, e.height, {outputs.begin(), outputs.end()});
  graph::FrameResult last;
  for (uint32_t f = 0; f < frames; ++f) last = e.executor.run_frame(f + 1 == frames);
  if (counted) *counted = last.counters.at("accumulate#0.frames");
  return e.executor.read_image(outputs.front());
}

// caustics_progressive with `sets` applied.
graph::GraphDesc progressive_graph(const std::vector<std::string>& sets) {
  auto graph = graph::load_graph_file((data_dir() / "graphs/caustics_progressive.json").string());
  graph::apply_overrides(graph, sets);
  return graph;
}

// A showing pass's number among the plan's (PlannedPass::showing): where a display step starts with it.
size_t showing_number(const graph::Plan& plan, const std::string& pass) {
  return std::find_if(plan.passes.begin(), plan.passes.end(), [&](const auto& p) { return p.name == pass; })->showing;
}

// One frame, or the part of one asked for: the part it ran and the passes that ran, in order.
std::pair<graph::FramePart, std::vector<std::string>> run_part(graph::Executor& executor, graph::FramePart part, bool read_back = false,
                                                               graph::DisplayStep step = {}) {
  const graph::FrameResult frame = executor.run_frame(read_back, {part, step});
  std::vector<std::string> ran;
  for (const auto& pass : frame.passes) {
    if (pass.ran()) ran.push_back(pass.name);
  }
  return {frame.part, ran};
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

// The adaptive traversal accumulated (graphs/caustics_adaptive_progressive.json) on the ball lens,
// every cluster refined to the last level (converge_from beyond the grids), so that a finer grid is
// the same traversal's limit rather than another convergence: the photons of its last level land
// with a finer spread and splat into finer levels.
const std::vector<std::string> kAdaptive = with(kSmall, {"converge_from=65536"});
io::ImageData adaptive_accumulated(SceneEngine& e, std::shared_ptr<const scene::Scene> scene, const std::vector<std::string>& sets,
                                   uint32_t frames) {
  return accumulated(e, std::move(scene), with(kAdaptive, sets), frames, nullptr, false, "caustics_adaptive_progressive");
}
io::ImageData adaptive_map(SceneEngine& e, std::shared_ptr<const scene::Scene> scene, uint32_t grid) {
  e.render("caustics_adaptive", std::move(scene), with(kAdaptive, {"grid=" + std::to_string(grid)}), {"caustics"});
  return e.executor.read_image("caustics");
}

// The jittered adaptive traversal's frames average toward the map of a grid 16 times finer: 32
// frames of a 128^2 grid must come far closer to the 2048^2 map than one frame, and only because the
// grid moves (with the jitter off every frame repeats the first, and the shrinking kernel alone
// changes little).
TEST(Progressive, JitteredAdaptiveMapsAverageToTheMapOfAFinerGrid) {
  SceneEngine e;
  auto scene = load_bundled_scene("sphere_plane");
  const io::ImageData fine = adaptive_map(e, scene, 2048);
  const double one = relative_difference(adaptive_accumulated(e, scene, {"grid=128"}, 1), fine);
  const double mean = relative_difference(adaptive_accumulated(e, scene, {"grid=128"}, 32), fine);
  const double unjittered = relative_difference(adaptive_accumulated(e, scene, {"grid=128", "jitter=false"}, 32), fine);
  std::printf("against the 2048^2 adaptive map: one 128^2 frame %.4f, the mean of 32 jittered %.4f, of 32 unjittered %.4f\n", one, mean,
              unjittered);
  EXPECT_LT(mean, 0.6 * one);
  EXPECT_GT(unjittered, 0.9 * one);
}

// Knaus and Zwicker's shrinking kernel: after 32 frames the mean of splats that shrink (alpha 2/3)
// is sharper, so nearer the finer grid's map, than the mean of splats that keep their first size
// (alpha 1), while the shrinking keeps every photon's power: the two means hold the same flux, to
// the float atomics' order, though their texels differ.
TEST(Progressive, AShrinkingKernelSharpensTheAdaptiveMeanAndKeepsItsEnergy) {
  SceneEngine e;
  auto scene = load_bundled_scene("sphere_plane");
  const io::ImageData fine = adaptive_map(e, scene, 2048);
  const io::ImageData shrunk = adaptive_accumulated(e, scene, {"grid=128"}, 32);
  const io::ImageData kept = adaptive_accumulated(e, scene, {"grid=128", "kernel_alpha=1"}, 32);
  const double shrunk_error = relative_difference(shrunk, fine), kept_error = relative_difference(kept, fine);
  std::printf("32 frames of 128^2 against the 2048^2 adaptive map: shrinking %.4f, kept %.4f; flux %.6f and %.6f\n", shrunk_error,
              kept_error, test::map_flux(shrunk), test::map_flux(kept));
  EXPECT_LT(shrunk_error, 0.95 * kept_error);
  EXPECT_NEAR(test::map_flux(shrunk), test::map_flux(kept), 1e-5 * test::map_flux(kept));
}

// Knaus and Zwicker's radius shrinks smoothly, but a splat level's texels only halve: a shrunk
// splat between two levels takes one of them at random, so that its mean squared width is the shrunk
// one. On frame 3 (two frames since the reset: r / r_0 = 0.745 at alpha 2/3), the splats above the
// finest level must have (r / r_0)^2 of the unshrunk frame's flux-weighted squared width; the
// finest level's cannot shrink. The same photons land alike at either alpha, and their random
// choices put it within a few hundredths (0.537 against 0.556 when this was written; rounded up
// to the next level, as before, most footprints of a whole number of texels stayed: 0.900).
TEST(Progressive, ASplatShrunkBetweenTwoLevelsHasTheShrunkMeanSquaredWidth) {
  SceneEngine e;
  auto scene = load_bundled_scene("sphere_plane");
  const uint32_t levels = 4;
  auto fluxes = [&](const std::string& alpha) {
    const auto sets = with(kAdaptive, {"grid=256", "caustic_size=256", "splat_levels=" + std::to_string(levels), "kernel_alpha=" + alpha});
    const io::ImageData atlas = accumulated(e, scene, sets, 3, nullptr, false, "caustics_adaptive_progressive", {"caustic_levels"});
    double outside = 0;
    return test::level_fluxes(atlas, 256, levels, &outside);
  };
  const std::vector<double> kept = fluxes("1"), shrunk = fluxes("0.6666667");
  // Knaus and Zwicker's product for two frames, (alpha / 1) ((1 + alpha) / 2).
  const double alpha = 2.0 / 3.0, scale_squared = alpha * (1.0 + alpha) / 2.0;
  double kept_width = 0, shrunk_width = 0, kept_flux = 0, shrunk_flux = 0;
  for (uint32_t level = 0; level < levels; ++level) {
    const double squared_width = double(1u << (2 * level));
    kept_width += kept[level] * squared_width;
    shrunk_width += shrunk[level] * squared_width;
    kept_flux += kept[level];
    shrunk_flux += shrunk[level];
    std::printf("level %u: flux %.5f kept, %.5f shrunk\n", level, kept[level], shrunk[level]);
  }
  // The finest level's splats stay; those above it (kept_width - kept[0]) shrink.
  const double ratio = (shrunk_width - kept[0]) / (kept_width - kept[0]);
  std::printf("squared width above the finest level: shrunk / kept %.4f, (r / r_0)^2 %.4f\n", ratio, scale_squared);
  EXPECT_GT(kept_flux - kept[0], 0.2 * kept_flux) << "too few splats above the finest level to tell";
  EXPECT_NEAR(ratio, scale_squared, 0.1 * scale_squared);
  EXPECT_NEAR(shrunk_flux, kept_flux, 1e-5 * kept_flux);
}

// The same with the default hybrid traversal, whose clusters converge from converge_from on and
// spread their power over a box: the shrunk boxes keep that power too, on the bunny.
TEST(Progressive, ShrunkConvergedClustersKeepTheirPower) {
  SceneEngine e;
  auto scene = load_bundled_scene("glass_bunny");
  const auto sets = with(kSmall, {"grid=512", "converge_from=256"});
  auto mean = [&](const std::string& alpha) {
    return accumulated(e, scene, with(sets, {"kernel_alpha=" + alpha}), 16, nullptr, false, "caustics_adaptive_progressive");
  };
  const io::ImageData shrunk = mean("0.6666667"), kept = mean("1");
  std::printf("16 hybrid frames of 512^2 on the bunny: flux %.6f shrinking, %.6f kept; the maps %.4f apart\n", test::map_flux(shrunk),
              test::map_flux(kept), relative_difference(shrunk, kept));
  EXPECT_GT(relative_difference(shrunk, kept), 0.01) << "the kernel did not shrink";
  EXPECT_NEAR(test::map_flux(shrunk), test::map_flux(kept), 1e-5 * test::map_flux(kept));
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
  scene::move_light(*moved_light, 0, glm::vec3(0.3f, 0.0f, 0.0f));
  const io::ImageData after_move = accumulated(e, moved_light, sets, 1, &frames, true);
  EXPECT_EQ(frames, 1.0) << "a light move kept the old mean";
  SceneEngine fresh;
  EXPECT_LT(relative_difference(after_move, accumulated(fresh, moved_light, sets, 1)), 1e-6);

  accumulated(e, moved_light, with(sets, {"max_frames=3"}), 5, &frames);
  EXPECT_EQ(frames, 3.0);
  // What a frame says the still view has gathered (the viewer's "mean of N frames") stops there too.
  const auto held = progressive_graph(with(sets, {"max_frames=3"}));
  e.next.start_over = true;
  e.configure(held, e.width, e.height);
  std::vector<uint64_t> gathered;
  for (int f = 0; f < 5; ++f) gathered.push_back(e.executor.run_frame(false).accumulated);
  EXPECT_EQ(gathered, (std::vector<uint64_t>{1, 2, 3, 3, 3}));
}

// Still frames converge to the exact caustic only where each frame's photons are exact: with
// distance=ray_query the mean of 16 jittered 64^2 frames comes far closer to the photon reference
// than one frame, while the image-space d_V/d_N estimate, averaged as long, keeps its own bias.
// Against 4e6 reference photons, after the chart's blur (docs/accuracy.md); when this was written:
// one exact frame 0.423, the mean of 16 0.131, 16 image-space frames 0.335 (a doubled error of the
// mean fails both bounds; with the jitter off the mean is one frame's map, 0.423, and fails).
TEST(Progressive, ExactPhotonsAccumulateTowardTheExactCaustic) {
  SceneEngine e;
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
  e.reuse = true;
  auto graph = graph::load_graph_file((data_dir() / "graphs/caustics_adaptive.json").string());
  graph::apply_overrides(graph, with(kSmall, {"grid=256"}));
  std::set<std::string> ran;
  auto frame = [&](SceneEngine& engine, std::shared_ptr<const scene::Scene> scene) {
    engine.executor.set_scene(std::move(scene));
    engine.configure(graph, engine.width, engine.height, {"caustics"});
    const graph::FrameResult result = engine.executor.run_frame(true);
    ran.clear();
    for (const auto& pass : result.passes) {
      if (pass.ran()) ran.insert(pass.name);
    }
    return result;
  };
  // An engine without reuse runs every pass of every frame: each state as a fresh render gives it.
  SceneEngine fresh;
  auto expect_fresh = [&](const std::shared_ptr<const scene::Scene>& scene, const char* state) {
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
  scene::move_light(*moved_light, 0, glm::vec3(0.3f, 0.0f, 0.0f));
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

// The viewer at rest (FramePart): frames that only refine the mean, and now and then one that only
// shows it, give the pictures of whole frames: after 1 whole, 3 refining and a showing frame, the
// caustic map and the picture of 4 whole frames, and after 2 more refining and a showing one those
// of 6. With slices (a quarter of the grid a frame), a showing frame must not move the slice on.
TEST(Progressive, RefiningAndShowingFramesApartGiveTheWholeFramesPictures) {
  auto scene = load_bundled_scene("glass_bunny");
  const auto sets = with(kSmall, {"grid=64", "slice_side=2"});
  SceneEngine apart;
  apart.reuse = true;
  const auto graph = progressive_graph(sets);
  apart.executor.set_scene(scene);
  apart.configure(graph, apart.width, apart.height, {"caustics"});
  ASSERT_TRUE(apart.executor.plan().refines_apart);
  auto run = [&](graph::FramePart part, bool read_back = false) {
    const graph::FrameResult frame = apart.executor.run_frame(read_back, {part});
    std::set<std::string> ran;
    for (const auto& pass : frame.passes) {
      if (pass.ran()) ran.insert(pass.name);
    }
    return std::make_pair(frame, ran);
  };
  EXPECT_EQ(run(graph::FramePart::display).first.part, graph::FramePart::whole) << "a plan's first frame runs whole";
  for (int f = 0; f < 3; ++f) {
    const auto [frame, ran] = run(graph::FramePart::refine);
    EXPECT_EQ(frame.part, graph::FramePart::refine);
    EXPECT_EQ(ran, (std::set<std::string>{"caustics#0", "accumulate#0"})) << "the light's passes are reused, the camera's wait";
  }
  for (uint32_t frames : {4u, 6u}) {
    const auto [shown, ran] = run(graph::FramePart::display, true);
    EXPECT_EQ(ran, (std::set<std::string>{"lighting", "refraction", "tonemap"}));
    EXPECT_EQ(shown.frame.since_reset + 1, frames) << "the frames in the mean shown";
    EXPECT_TRUE(shown.converging) << "the mean goes on converging while it is only shown";
    EXPECT_EQ(shown.counters.at("accumulate#0.frames"), frames);
    SceneEngine whole;
    accumulated(whole, scene, sets, frames);
    for (const char* image : {"caustics", "ldr"}) {
      EXPECT_LT(relative_difference(apart.executor.read_image(image), whole.executor.read_image(image)), 1e-6)
          << image << " after " << frames << " frames";
    }
    for (int f = 0; f < 2; ++f) run(graph::FramePart::refine);
  }
  // A display frame in steps (each within a frame budget): the lighting alone, then the rest, read
  // what the step before left; the picture is that of 8 whole frames.
  const size_t after_lighting = showing_number(apart.executor.plan(), "lighting") + 1;
  auto step = [&](graph::DisplayStep display, bool read_back) {
    return run_part(apart.executor, graph::FramePart::display, read_back, display).second;
  };
  EXPECT_EQ(step({0, after_lighting}, false), std::vector<std::string>{"lighting"});
  EXPECT_EQ(step({after_lighting, SIZE_MAX}, true), (std::vector<std::string>{"refraction", "tonemap"}));
  {
    SceneEngine whole;
    accumulated(whole, scene, sets, 8);
    for (const char* image : {"caustics", "ldr"}) {
      EXPECT_LT(relative_difference(apart.executor.read_image(image), whole.executor.read_image(image)), 1e-6)
          << image << " shown in steps";
    }
  }
  // A light move runs the next frame whole: the mean restarts, as a fresh render's.
  auto moved_lights = scene->lights;
  moved_lights[0].view.position += glm::vec3(0.3f, 0.0f, 0.0f);
  apart.executor.set_view(scene->camera, moved_lights);
  EXPECT_EQ(run(graph::FramePart::refine).first.part, graph::FramePart::whole);
}

// A new plan (a frame-budget step's size, an edited parameter) takes over the results of the passes
// it did not change, as long as what they depend on holds: at another output size the light's
// passes do not run again, after an exposure edit only the tone map runs, and each such frame is
// the picture a fresh render of that state gives. After a start over (HandOverOptions) every pass runs again;
// after edited shaders (a saved shader) those set up with one of them and those downstream.
TEST(Progressive, ANewPlanCarriesOverTheResultsOfPassesItDidNotChange) {
  SceneEngine e;
  e.reuse = true;
  auto scene = load_bundled_scene("glass_bunny");
  e.executor.set_scene(scene);
  auto frame = [&](SceneEngine& engine, const std::vector<std::string>& sets, uint32_t width, uint32_t height) {
    auto graph = graph::load_graph_file((data_dir() / "graphs/caustics_adaptive.json").string());
    graph::apply_overrides(graph, with(kSmall, sets));
    engine.configure(graph, width, height, {"caustics"});
    std::set<std::string> ran;
    for (const auto& pass : engine.executor.run_frame(true).passes) {
      if (pass.ran()) ran.insert(pass.name);
    }
    return ran;
  };
  auto expect_fresh = [&](const std::vector<std::string>& sets, uint32_t width, uint32_t height, const char* state) {
    SceneEngine fresh;
    fresh.executor.set_scene(scene);
    frame(fresh, sets, width, height);
    for (const char* image : {"ldr", "caustics"}) {
      EXPECT_LT(relative_difference(e.executor.read_image(image), fresh.executor.read_image(image)), 1e-6) << image << " after " << state;
    }
  };
  const std::set<std::string> every = frame(e, {"grid=256"}, e.width, e.height);
  EXPECT_EQ(every.size(), e.executor.plan().passes.size());
  const std::set<std::string> camera_passes{"gbuffer", "lighting", "refraction", "tonemap"};
  EXPECT_EQ(frame(e, {"grid=256"}, e.width / 2, e.height / 2), camera_passes) << "at half the size";
  expect_fresh({"grid=256"}, e.width / 2, e.height / 2, "a new size");
  EXPECT_EQ(frame(e, {"grid=256", "exposure=2"}, e.width / 2, e.height / 2), std::set<std::string>{"tonemap"}) << "after an exposure edit";
  expect_fresh({"grid=256", "exposure=2"}, e.width / 2, e.height / 2, "an exposure edit");
  EXPECT_EQ(frame(e, {"grid=512", "exposure=2"}, e.width / 2, e.height / 2),
            (std::set<std::string>{"caustics#0", "lighting", "refraction", "tonemap"}))
      << "after a photon grid edit";
  expect_fresh({"grid=512", "exposure=2"}, e.width / 2, e.height / 2, "a photon grid edit");
  // A plan replaced before its first frame (two edits between frames) passes on what it was given.
  auto unrun = graph::load_graph_file((data_dir() / "graphs/caustics_adaptive.json").string());
  graph::apply_overrides(unrun, with(kSmall, {"grid=512", "exposure=3"}));
  e.configure(unrun, e.width, e.height, {"caustics"});
  EXPECT_EQ(frame(e, {"grid=512", "exposure=2"}, e.width, e.height), camera_passes) << "after a plan that never ran";
  expect_fresh({"grid=512", "exposure=2"}, e.width, e.height, "a plan that never ran");
  e.next.start_over = true;
  EXPECT_EQ(frame(e, {"grid=512", "exposure=2"}, e.width, e.height), every) << "after a start over";
  // A saved shader file (the viewer's hot reload): the passes set up with it run again, and those
  // that read what they write; the others keep their results.
  auto shader_file = [&](const std::string& name) {
    for (const auto& file : e.executor.shader_files()) {
      if (file.filename() == name) return file;
    }
    ADD_FAILURE() << name << " is not among the plan's shader files";
    return std::filesystem::path();
  };
  e.next.edited_shaders = {shader_file("tonemap.comp")};
  EXPECT_EQ(frame(e, {"grid=512", "exposure=2"}, e.width, e.height), std::set<std::string>{"tonemap"}) << "after the tone map's shader";
  e.next.edited_shaders = {shader_file("lighting.frag")};
  EXPECT_EQ(frame(e, {"grid=512", "exposure=2"}, e.width, e.height), (std::set<std::string>{"lighting", "refraction", "tonemap"}))
      << "after the lighting's shader";
  e.next.edited_shaders = {shader_file("adaptive_photons.comp")};
  EXPECT_EQ(frame(e, {"grid=512", "exposure=2"}, e.width, e.height),
            (std::set<std::string>{"caustics#0", "lighting", "refraction", "tonemap"}))
      << "after the adaptive photons' shader";
  expect_fresh({"grid=512", "exposure=2"}, e.width, e.height, "shader reloads");
}

// A running mean goes on into a new plan that changed neither it nor what it reads (an exposure
// edit, another output size) and into one that comes back after a plan in between that averaged
// something else (the viewer's while_moving plan during an orbit, the camera moved meanwhile): the
// caustic map is then the mean of all its frames, slices of the grid in sequence, as a render
// accumulating as many gives. A plan that changed what it reads, or a light move, starts it over.
TEST(Progressive, ARunningMeanGoesOnIntoANewPlanThatDidNotChangeIt) {
  SceneEngine e;
  e.reuse = true;
  auto scene = load_bundled_scene("sphere_plane");
  const auto sets = with(kSmall, {"grid=64", "slice_side=2"});
  auto run = [&](std::shared_ptr<const scene::Scene> state, const std::vector<std::string>& more, uint32_t frames, uint32_t divider = 1) {
    const auto graph = progressive_graph(with(sets, more));
    e.executor.set_scene(std::move(state));
    e.configure(graph, e.width / divider, e.height / divider, {"caustics"});
    graph::FrameResult last;
    for (uint32_t f = 0; f < frames; ++f) last = e.executor.run_frame(f + 1 == frames);
    return last.counters.at("accumulate#0.frames");
  };
  EXPECT_EQ(run(scene, {}, 3), 3.0);
  EXPECT_EQ(run(scene, {"exposure=2"}, 2, 2), 5.0) << "an exposure edit at half the size restarted the mean";
  auto moved_camera = std::make_shared<scene::Scene>(*scene);
  moved_camera->camera.position += glm::vec3(0.5f, 0.2f, 0.0f);
  EXPECT_EQ(run(moved_camera, {"distance=search"}, 2), 2.0) << "a plan averaging another source took the mean over";
  EXPECT_EQ(run(moved_camera, {}, 3), 8.0) << "the mean did not come back after a plan in between";
  SceneEngine fresh;
  EXPECT_LT(relative_difference(e.executor.read_image("caustics"), accumulated(fresh, moved_camera, sets, 8)), 1e-6)
      << "the mean carried through three plans is not 8 frames' mean";
  EXPECT_EQ(run(moved_camera, {"grid=128"}, 1), 1.0) << "a new photon grid kept the mean";
  EXPECT_EQ(run(moved_camera, {}, 1), 9.0) << "the 8 frames' mean did not come back after the grid's plan";
  auto moved_light = std::make_shared<scene::Scene>(*moved_camera);
  scene::move_light(*moved_light, 0, glm::vec3(0.3f, 0.0f, 0.0f));
  EXPECT_EQ(run(moved_light, {}, 1), 1.0) << "a light move kept the mean";
  e.next.start_over = true;
  EXPECT_EQ(run(moved_light, {}, 1), 1.0) << "a start over kept the mean";
}

// slice_side is sampling-only (ParamDecl::sampling_only): the mean of quarter grids and of
// sixteenth grids is the same grid's map, so a viewer that takes a cheaper slice at rest
// (editor::StillLevels) keeps its mean. 8 quarter frames (two whole grids, the jitter's first two
// points) and then 16 sixteenths (one more, at the third point, not again at the first, whose
// photons the quarters traced) are the mean of three whole jittered frames, each sixteenth
// weighing a quarter of a quarter (accumulate's weight, 1 / slice_side^2). With the sixteenths'
// run starting over at the first point it failed at 0.175; with every frame weighing 1, at 0.163.
TEST(Progressive, AMeanGoesOnWhenTheSliceChanges) {
  SceneEngine e;
  e.reuse = true;
  auto scene = load_bundled_scene("sphere_plane");
  const auto sets = with(kSmall, {"grid=128"});
  double frames = 0;
  accumulated(e, scene, with(sets, {"slice_side=2"}), 8, nullptr, true);
  const io::ImageData went_on = accumulated(e, scene, with(sets, {"slice_side=4"}), 16, &frames, true);
  EXPECT_EQ(frames, 24.0) << "the slice's change restarted the mean";
  SceneEngine fresh;
  const io::ImageData whole = accumulated(fresh, scene, with(sets, {"slice_side=1"}), 3);
  const double apart = relative_difference(went_on, whole);
  std::printf("8 quarters then 16 sixteenths against 3 whole frames: %.2e\n", apart);
  EXPECT_LT(apart, 1e-5);
  EXPECT_GT(relative_difference(accumulated(fresh, scene, with(sets, {"slice_side=1"}), 2), whole), 0.05)
      << "the check cannot tell two whole frames from three";
}

// A still level's step (editor::StillLevels: slice_side from a quarter to a ninth, sampling-only) makes
// a new plan whose showing passes show what the plan before's did: they are carried over with their
// pictures, so its first frame refines at once (it ran whole, about 0.3 s at 1280x720 on lavapipe)
// and the picture stands until the next display, which is then that of the same frames run whole.
// The images are handed over, not copied: the picture is the same image. An exposure edit with it
// changes what the tone map shows: that frame runs whole.
TEST(Progressive, AStillLevelsStepRefinesAtOnceItsPictureStanding) {
  auto scene = load_bundled_scene("glass_bunny");
  const auto sets = with(kSmall, {"grid=64"});
  auto graph_with = [&](const std::vector<std::string>& more) { return progressive_graph(with(sets, more)); };
  SceneEngine e;
  e.reuse = true;
  e.executor.set_scene(scene);
  e.configure(graph_with({"slice_side=2"}), e.width, e.height);
  auto run = [&](graph::FramePart part, bool read_back = false) { return run_part(e.executor, part, read_back); };
  run(graph::FramePart::whole);
  for (int f = 0; f < 3; ++f) run(graph::FramePart::refine);
  run(graph::FramePart::display, true);
  const io::ImageData shown = e.executor.read_image("ldr");
  const VkImage shown_in = e.executor.frame_image("ldr").image;
  for (int f = 0; f < 2; ++f) run(graph::FramePart::refine);

  e.configure(graph_with({"slice_side=3"}), e.width, e.height);
  const auto [part, ran] = run(graph::FramePart::refine, true);
  EXPECT_EQ(part, graph::FramePart::refine) << "the new level's first frame ran whole";
  EXPECT_EQ(ran, (std::vector<std::string>{"caustics#0", "accumulate#0"}));
  EXPECT_EQ(relative_difference(e.executor.read_image("ldr"), shown), 0.0) << "the picture did not stand";
  EXPECT_EQ(e.executor.frame_image("ldr").image, shown_in) << "the picture was copied, not handed over";
  EXPECT_EQ(run(graph::FramePart::display, true).second, (std::vector<std::string>{"lighting", "refraction", "tonemap"}));
  SceneEngine whole;
  whole.reuse = true;
  accumulated(whole, scene, with(sets, {"slice_side=2"}), 6, nullptr, true, "caustics_progressive", {"ldr"});
  const io::ImageData expected = accumulated(whole, scene, with(sets, {"slice_side=3"}), 1, nullptr, true, "caustics_progressive", {"ldr"});
  EXPECT_LT(relative_difference(e.executor.read_image("ldr"), expected), 1e-6) << "the display after the step";

  e.configure(graph_with({"slice_side=4", "exposure=2"}), e.width, e.height);
  EXPECT_EQ(run(graph::FramePart::refine).first, graph::FramePart::whole) << "a new exposure's picture waited";
}

// The viewer's quality values at rest (a graph's while_still values) change the caustic method, so
// the new plan's showing passes have nothing to carry over and its first frame ran whole (about 0.2
// s at 1280x720 on lavapipe, over the budget). Where the caller lets the picture stand
// (HandOverOptions::picture_may_stand), the plan before's picture is handed over and the new plan refines at once;
// a display, in steps, then shows the new mean, as a fresh render of it does. A step that would need
// a showing pass that has not run yet runs whole, as does a frame after the camera moved (the
// picture is of the old view), and a plan the caller did not let stand (an edit).
TEST(Progressive, AQualityChangeAtRestRefinesAtOnceThePictureBeforeStanding) {
  auto scene = load_bundled_scene("sphere_plane");
  const auto sets = with(kSmall, {"grid=64"});
  auto graph_with = [&](const std::vector<std::string>& more) { return progressive_graph(with(sets, more)); };
  SceneEngine e;
  e.reuse = true;
  e.executor.set_scene(scene);
  auto run = [&](graph::FramePart part, graph::DisplayStep step = {}) { return run_part(e.executor, part, true, step); };
  // Moving values, then the still ones: another photon path (the search), a quarter of the grid.
  const std::vector<std::string> still = {"distance=search", "slice_side=2"};
  e.configure(graph_with({}), e.width, e.height);
  run(graph::FramePart::whole);
  run(graph::FramePart::whole);
  const io::ImageData before = e.executor.read_image("ldr");
  const VkImage before_in = e.executor.frame_image("ldr").image;

  e.next.picture_may_stand = true;
  e.configure(graph_with(still), e.width, e.height);
  EXPECT_TRUE(e.executor.picture_standing());
  const auto [part, ran] = run(graph::FramePart::refine);
  EXPECT_EQ(part, graph::FramePart::refine) << "the still plan's first frame ran whole";
  EXPECT_EQ(ran, (std::vector<std::string>{"caustics#0", "accumulate#0"}));
  EXPECT_EQ(relative_difference(e.executor.read_image("ldr"), before), 0.0) << "the picture before did not stand";
  EXPECT_EQ(e.executor.frame_image("ldr").image, before_in) << "the picture was copied, not handed over";
  const size_t refraction = showing_number(e.executor.plan(), "refraction");
  EXPECT_EQ(run(graph::FramePart::display, {0, refraction}).second, (std::vector<std::string>{"lighting"}));
  EXPECT_TRUE(e.executor.picture_standing()) << "the picture gave way before the display's last step";
  EXPECT_EQ(relative_difference(e.executor.read_image("ldr"), before), 0.0) << "a step before the last changed the picture";
  EXPECT_EQ(run(graph::FramePart::display, {refraction, SIZE_MAX}).second, (std::vector<std::string>{"refraction", "tonemap"}));
  EXPECT_FALSE(e.executor.picture_standing());
  SceneEngine fresh;
  fresh.reuse = true;
  const io::ImageData expected = accumulated(fresh, scene, with(sets, still), 1, nullptr, true, "caustics_progressive", {"ldr"});
  EXPECT_LT(relative_difference(e.executor.read_image("ldr"), expected), 1e-6) << "the display of the still plan's mean";
  EXPECT_GT(relative_difference(before, expected), 1e-3) << "the check cannot tell the two plans' pictures apart";

  // A display step after one the new plan has not run cannot wait: whole.
  e.next.picture_may_stand = true;
  e.configure(graph_with({"distance=dv_dn", "slice_side=2"}), e.width, e.height);
  EXPECT_EQ(run(graph::FramePart::display, {refraction, SIZE_MAX}).first, graph::FramePart::whole) << "refraction ran without its lighting";
  // The camera moved since the picture was drawn: whole.
  e.next.picture_may_stand = true;
  e.configure(graph_with(still), e.width, e.height);
  auto moved = std::make_shared<scene::Scene>(*scene);
  moved->camera.position += glm::vec3(0.2f, 0.1f, 0.0f);
  e.executor.set_view(moved->camera, moved->lights);
  EXPECT_EQ(run(graph::FramePart::refine).first, graph::FramePart::whole) << "the picture of the old view stood";
  // Not let stand (an edit of what the picture shows): whole.
  e.configure(graph_with({"distance=dv_dn", "slice_side=2"}), e.width, e.height);
  EXPECT_FALSE(e.executor.picture_standing());
  EXPECT_EQ(run(graph::FramePart::refine).first, graph::FramePart::whole);
}

// At rest a single refractor's surfaces (refraction_layers' front and back) are drawn once: the
// frames after, which refract a new background (the converging caustic) from the same camera, keep
// them (refraction.surfaces_drawn 0) and show the picture a fresh render of as many frames shows
// (drawn every frame); a camera move draws them again (kept across it, the picture is 0.0062 off),
// a light move does not, and its picture is a fresh render's.
TEST(Progressive, ASingleLayersSurfacesAreKeptWhileTheCameraStandsStill) {
  SceneEngine e;
  e.reuse = true;
  auto scene = load_bundled_scene("sphere_plane");
  const auto sets = with(kSmall, {"grid=64"});
  const auto graph = progressive_graph(sets);
  auto run = [&](SceneEngine& engine, std::shared_ptr<const scene::Scene> state, uint32_t frames, std::vector<double>* drawn) {
    engine.executor.set_scene(std::move(state));
    engine.configure(graph, engine.width, engine.height, {"ldr"});
    for (uint32_t f = 0; f < frames; ++f) {
      const graph::FrameResult result = engine.executor.run_frame(f + 1 == frames);
      if (drawn) drawn->push_back(result.counters.at("refraction.surfaces_drawn"));
    }
    return engine.executor.read_image("ldr");
  };
  std::vector<double> drawn;
  const io::ImageData rested = run(e, scene, 4, &drawn);
  EXPECT_EQ(drawn, (std::vector<double>{1, 0, 0, 0}));
  SceneEngine fresh;
  EXPECT_LT(relative_difference(rested, run(fresh, scene, 4, nullptr)), 1e-6) << "the kept surfaces refract another picture";

  auto moved = std::make_shared<scene::Scene>(*scene);
  moved->camera.position += glm::vec3(0.4f, 0.3f, 0.0f);
  drawn.clear();
  const io::ImageData after_move = run(e, moved, 1, &drawn);
  EXPECT_EQ(drawn, (std::vector<double>{1})) << "a camera move kept the surfaces";
  // The caustic mean went on through the move (it is in the light's space): 5 frames' from there.
  SceneEngine fresh_moved;
  EXPECT_LT(relative_difference(after_move, run(fresh_moved, moved, 5, nullptr)), 1e-6);

  // A light move leaves them (they follow the camera and the geometry alone); the mean restarts.
  auto lit_elsewhere = std::make_shared<scene::Scene>(*moved);
  scene::move_light(*lit_elsewhere, 0, glm::vec3(0.3f, 0.0f, 0.0f));
  drawn.clear();
  const io::ImageData after_light = run(e, lit_elsewhere, 1, &drawn);
  EXPECT_EQ(drawn, (std::vector<double>{0})) << "a light move drew the surfaces again";
  SceneEngine fresh_lit;
  EXPECT_LT(relative_difference(after_light, run(fresh_lit, lit_elsewhere, 1, nullptr)), 1e-6) << "the picture after a light move";
}

// caustics_progressive with its lighting fed each frame's own caustic map, and the lit image
// averaged over frames by a temporal_mean pass that reads its last result through a history input
// (lit_mean@previous).
graph::GraphDesc camera_mean_graph(const std::vector<std::string>& sets) {
  const auto path = data_dir() / "graphs/caustics_progressive.json";
  nlohmann::json graph = nlohmann::json::parse(std::ifstream(path));
  graph["resources"]["lit_mean"] = {{"type", "image"}, {"format", "rgba32f"}};
  for (auto& pass : graph["passes"]) {
    if (pass["name"] == "lighting") pass["inputs"]["caustics"] = "caustics_frame";
  }
  graph["outputs"].push_back("lit_mean");
  graph["passes"].push_back({{"name", "camera_mean"},
                             {"type", "temporal_mean"},
                             {"inputs", {{"current", "lit"}, {"previous", "lit_mean@previous"}}},
                             {"outputs", {{"average", "lit_mean"}}}});
  auto desc = graph::load_graph(JsonDocument::parse(graph.dump(2), path.string()));
  graph::apply_overrides(desc, sets);
  return desc;
}

// A history input carries a pass's result into the next frame: the camera-space mean of the lit
// images of 8 jittered caustic maps equals the lighting of the light-space mean of those maps (the
// lighting is linear in the caustic map; the lit image is rgba16f, so to its rounding), where any
// one frame is far from it (with the history read as zeros every frame, the mean is an eighth of
// one frame). A camera move and a light move each restart it (the lit image depends on both): the
// mean is then that frame's image, after a light move a fresh render's.
TEST(Progressive, AHistoryInputAveragesTheCameraImageAndRestartsWithIt) {
  SceneEngine e;
  auto scene = load_bundled_scene("sphere_plane");
  const auto sets = with(kSmall, {"grid=64"});
  const graph::GraphDesc averaged = camera_mean_graph(sets);
  auto run = [&](SceneEngine& engine, std::shared_ptr<const scene::Scene> state, uint32_t frames, bool go_on, double* counted = nullptr) {
    engine.executor.set_scene(std::move(state));
    if (!go_on) engine.next.start_over = true;
    engine.configure(averaged, engine.width, engine.height, {"lit_mean", "lit"});
    graph::FrameResult last;
    for (uint32_t f = 0; f < frames; ++f) last = engine.executor.run_frame(f + 1 == frames);
    if (counted) *counted = last.counters.at("camera_mean.frames");
    return engine.executor.read_image("lit_mean");
  };
  double frames = 0;
  const io::ImageData mean = run(e, scene, 8, false, &frames);
  EXPECT_EQ(frames, 8.0);
  const io::ImageData last_frame = e.executor.read_image("lit");

  SceneEngine light_space;
  const auto graph = progressive_graph(sets);
  light_space.executor.set_scene(scene);
  light_space.configure(graph, light_space.width, light_space.height, {"lit"});
  for (uint32_t f = 0; f < 8; ++f) light_space.executor.run_frame(f == 7);
  const io::ImageData lit_of_mean = light_space.executor.read_image("lit");
  const double averaged_gap = relative_difference(mean, lit_of_mean), one_frame_gap = relative_difference(last_frame, lit_of_mean);
  std::printf("sphere_plane, 8 frames: the camera-space mean %.2e from the lighting of the light-space mean, one frame %.2e\n",
              averaged_gap, one_frame_gap);
  EXPECT_LT(averaged_gap, 2e-3);
  EXPECT_GT(one_frame_gap, 10 * averaged_gap);

  auto moved_camera = std::make_shared<scene::Scene>(*scene);
  moved_camera->camera.position += glm::vec3(0.5f, 0.2f, 0.0f);
  const io::ImageData after_camera = run(e, moved_camera, 1, true, &frames);
  EXPECT_EQ(frames, 1.0) << "a camera move kept the camera image's mean";
  // (The caustic map's grid goes on moving: a camera move keeps light-space history.)
  EXPECT_LT(relative_difference(after_camera, e.executor.read_image("lit")), 1e-6) << "the mean after a camera move is not this frame";
  run(e, moved_camera, 2, true, &frames);
  EXPECT_EQ(frames, 3.0);

  auto moved_light = std::make_shared<scene::Scene>(*moved_camera);
  scene::move_light(*moved_light, 0, glm::vec3(0.3f, 0.0f, 0.0f));
  const io::ImageData after_light = run(e, moved_light, 1, true, &frames);
  EXPECT_EQ(frames, 1.0) << "a light move kept the camera image's mean";
  SceneEngine fresh;
  EXPECT_LT(relative_difference(after_light, run(fresh, moved_light, 1, false)), 1e-6);
}

// A sliced grid (slice_side 2): each frame traces a quarter of the grid's photons, each with four
// times its power, another quarter each frame, so the mean of 4 frames is the whole grid's map (the
// same photons: exact paths draw their random numbers per photon), where any one frame is far from
// it; so for the image-space and the exact photons. Jittered, each run of 4 slices is one frame of
// the whole grid, the jitter moving from run to run: 8 sliced frames average to 2 whole ones. (With
// the jitter moving every frame, each cell's points would be every fourth of the R2 sequence,
// which covers a cell poorly: the mean of 32 such frames of the bunny was 0.144 from the
// reference where 8 whole frames were 0.122.)
TEST(Progressive, SlicedFramesTraceTheWholeGridOnce) {
  SceneEngine e;
  auto scene = load_bundled_scene("sphere_plane");
  for (const char* distance : {"distance=dv_dn", "distance=ray_query"}) {
    const auto sets = with(kSmall, {"grid=128", "jitter=false", distance});
    const io::ImageData whole = accumulated(e, scene, with(sets, {"slice_side=1"}), 1);
    const double one_slice = relative_difference(accumulated(e, scene, with(sets, {"slice_side=2"}), 1), whole);
    double frames = 0;
    const double four_slices = relative_difference(accumulated(e, scene, with(sets, {"slice_side=2"}), 4, &frames), whole);
    std::printf("%s: against the whole grid's map, one quarter slice %.4f, the mean of four %.2e\n", distance, one_slice, four_slices);
    EXPECT_EQ(frames, 4.0);
    EXPECT_LT(four_slices, 1e-5) << distance;
    EXPECT_GT(one_slice, 0.1) << distance;
  }
  const auto jittered = with(kSmall, {"grid=128", "jitter=true"});
  const io::ImageData two_whole = accumulated(e, scene, with(jittered, {"slice_side=1"}), 2);
  EXPECT_LT(relative_difference(accumulated(e, scene, with(jittered, {"slice_side=2"}), 8), two_whole), 1e-5);
  EXPECT_GT(relative_difference(accumulated(e, scene, with(jittered, {"slice_side=1"}), 1), two_whole), 0.05)
      << "the check cannot tell one jitter from two";
}

// A parameter that the pass reads every frame may be an expression of the frame block: a photon grid
// growing with the frames since the last reset gives on frame k the map of a fresh render with grid
// 64 (k + 1), and the exposure on frame k the picture of exposure k + 0.5 (the lighting reads each
// frame's own map here); a light move restarts the grid's count (the caustic pass depends on the
// light) and not the exposure's frame index.
TEST(Progressive, PerFrameParametersFollowTheFrameBlock) {
  auto graph_with = [](const nlohmann::json& grid, const nlohmann::json& exposure) {
    const auto path = data_dir() / "graphs/caustics_progressive.json";
    nlohmann::json file = nlohmann::json::parse(std::ifstream(path));
    for (auto& pass : file["passes"]) {
      if (pass["name"] == "caustics") pass["params"]["grid"] = grid;
      if (pass["name"] == "tonemap") pass["params"]["exposure"] = exposure;
      if (pass["name"] == "lighting") pass["inputs"]["caustics"] = "caustics_frame";
    }
    auto desc = graph::load_graph(JsonDocument::parse(file.dump(2), path.string()));
    graph::apply_overrides(desc, with(kSmall, {"jitter=false"}));
    return desc;
  };
  SceneEngine e;
  auto scene = load_bundled_scene("sphere_plane");
  e.executor.set_scene(scene);
  e.configure(graph_with("64 * (1 + frame.since_reset)", "0.5 + frame.index"), e.width, e.height, {"caustics_frame"});
  auto check = [&](std::shared_ptr<const scene::Scene> state, int grid, double exposure, const char* frame) {
    e.executor.set_scene(state);
    e.executor.run_frame(true);
    SceneEngine fresh;
    fresh.render(graph_with(grid, exposure), state, {"caustics_frame"});
    EXPECT_LT(relative_difference(e.executor.read_image("caustics_frame"), fresh.executor.read_image("caustics_frame")), 1e-6)
        << frame << ": not the map of grid " << grid;
    EXPECT_LT(relative_difference(e.executor.read_image("ldr"), fresh.executor.read_image("ldr")), 1e-6)
        << frame << ": not the picture of exposure " << exposure;
  };
  check(scene, 64, 0.5, "frame 0");
  check(scene, 128, 1.5, "frame 1");
  check(scene, 192, 2.5, "frame 2");
  auto moved_light = std::make_shared<scene::Scene>(*scene);
  scene::move_light(*moved_light, 0, glm::vec3(0.3f, 0.0f, 0.0f));
  check(moved_light, 64, 3.5, "frame 3, the light moved");
}

// A per-frame expression that stops being a number on a later frame (a division by a count that
// reached zero) is bad input named where it is, not a value kept silently from an earlier frame.
TEST(Progressive, APerFrameExpressionThatTurnsNonFiniteIsNamed) {
  const auto path = data_dir() / "graphs/caustics_progressive.json";
  nlohmann::json file = nlohmann::json::parse(std::ifstream(path));
  for (auto& pass : file["passes"]) {
    if (pass["name"] == "tonemap") pass["params"]["exposure"] = "1 / (2 - frame.index)";
  }
  auto graph = graph::load_graph(JsonDocument::parse(file.dump(2), path.string()));
  graph::apply_overrides(graph, with(kSmall, {"grid=64"}));
  SceneEngine e;
  e.executor.set_scene(load_bundled_scene("sphere_plane"));
  e.configure(graph, e.width, e.height);
  e.executor.run_frame(false);
  e.executor.run_frame(false);
  try {
    e.executor.run_frame(false);
    ADD_FAILURE() << "frame 2's exposure is 1 / 0";
  } catch (const InputError& error) {
    const std::string message = error.what();
    for (const char* part : {"caustics_progressive.json", "/passes/8", "tonemap", "exposure", "division by zero", "frame 2"})
      EXPECT_NE(message.find(part), std::string::npos) << part << " missing from: " << message;
  }
}

// Two passes that count under one name add up whichever of them ran: with reuse, a caustic map
// that does not follow the frame is kept on the second frame while the jittered one runs, and
// photons.processed still counts both (the kept one as it last counted), not the running one alone.
TEST(Progressive, ACounterOfTwoPassesSumsWhatEachLastCountedWhenOneIsKept) {
  const auto path = data_dir() / "graphs/caustics_progressive.json";
  nlohmann::json file = nlohmann::json::parse(std::ifstream(path));
  nlohmann::json kept;
  for (const auto& pass : file["passes"]) {
    if (pass["name"] == "caustics") kept = pass;
  }
  kept["name"] = "kept_caustics";
  kept["params"]["jitter"] = false;
  kept["outputs"]["caustic_map"] = "kept_map";
  file["resources"]["kept_map"] = file["resources"]["caustics_frame"];
  file["passes"].push_back(kept);
  auto graph = graph::load_graph(JsonDocument::parse(file.dump(2), path.string()));
  graph::apply_overrides(graph, with(kSmall, {"grid=64", "jitter=true"}));
  SceneEngine e;
  e.reuse = true;
  e.executor.set_scene(load_bundled_scene("sphere_plane"));
  e.configure(graph, e.width, e.height, {"kept_map"});
  const graph::FrameResult first = e.executor.run_frame(false);
  const graph::FrameResult second = e.executor.run_frame(false);
  auto ran = [](const graph::FrameResult& frame, const std::string& name) {
    const auto pass = std::find_if(frame.passes.begin(), frame.passes.end(), [&](const auto& p) { return p.name == name; });
    EXPECT_NE(pass, frame.passes.end()) << name << " is not in the plan";
    return pass != frame.passes.end() && pass->ran();
  };
  ASSERT_TRUE(ran(second, "caustics#0"));  // the scene's one light's instances
  ASSERT_FALSE(ran(second, "kept_caustics#0"));
  EXPECT_EQ(first.counters.at("photons.processed"), 2.0 * 64 * 64);
  EXPECT_EQ(second.counters.at("photons.processed"), 2.0 * 64 * 64);
}

// A still camera's frames moved within their pixels and averaged (refraction_deferred's
// still_mean) antialias the picture: after 16 frames the mean comes far closer to the same view
// rendered at four times the size and box-filtered down (what a uniform spread over the pixel
// averages to) than the first frame, which is unmoved and equal to the refracted image, on the
// pixels that an edge crosses (their 4x4 block in the large render is not flat; elsewhere both
// differ from it only by what the size itself changes); a camera move restarts it. With the jitter
// off, the mean stays the first frame and the test fails.
TEST(Progressive, AStillCamerasJitteredFramesAverageToASupersampledPicture) {
  auto scene = load_bundled_scene("sphere_plane");
  auto graph = graph::load_graph_file((data_dir() / "graphs/refraction_deferred.json").string());
  graph::apply_overrides(graph, {"shadow_size=256"});
  SceneEngine big;
  big.width *= 4;
  big.height *= 4;
  big.render(graph, scene, {"refracted"});
  const io::ImageData fine = big.executor.read_image("refracted");
  const uint32_t width = fine.width / 4, height = fine.height / 4;
  std::vector<float> supersampled(size_t{width} * height * 3, 0.0f), low(supersampled.size(), 1e30f), high(supersampled.size(), -1e30f);
  for (uint32_t y = 0; y < fine.height; ++y) {
    for (uint32_t x = 0; x < fine.width; ++x) {
      for (uint32_t c = 0; c < 3; ++c) {
        const size_t at = ((y / 4) * width + x / 4) * 3 + c;
        const float v = fine.rgba[(size_t{y} * fine.width + x) * 4 + c];
        supersampled[at] += v / 16.0f;
        low[at] = std::min(low[at], v);
        high[at] = std::max(high[at], v);
      }
    }
  }
  // Relative L1 over the edge pixels' channels.
  size_t edges = 0;
  auto edge_gap = [&](const io::ImageData& image) {
    double difference = 0, total = 0;
    edges = 0;
    for (size_t i = 0; i < supersampled.size(); ++i) {
      if (high[i] - low[i] < 0.1f) continue;
      ++edges;
      difference += std::abs(static_cast<double>(image.rgba[i / 3 * 4 + i % 3]) - static_cast<double>(supersampled[i]));
      total += std::abs(static_cast<double>(supersampled[i]));
    }
    return difference / std::max(total, 1e-30);
  };

  SceneEngine e;
  e.executor.set_scene(scene);
  e.configure(graph, e.width, e.height, {"refracted", "still_mean"});
  const graph::FrameResult first = e.executor.run_frame(true);
  EXPECT_EQ(first.frame.index, 0u);
  const io::ImageData one = e.executor.read_image("still_mean");
  EXPECT_LT(relative_difference(one, e.executor.read_image("refracted")), 1e-6) << "the first frame is not the unmoved image";
  graph::FrameResult last;
  for (int f = 1; f < 16; ++f) last = e.executor.run_frame(f == 15);
  EXPECT_EQ(last.counters.at("still_mean.frames"), 16.0);
  const double one_gap = edge_gap(one), mean_gap = edge_gap(e.executor.read_image("still_mean"));
  std::printf(
      "sphere_plane 320x180 against 1280x720 box-filtered, on %zu edge pixel channels: the first frame %.4f, the mean of 16 jittered "
      "frames %.4f\n",
      edges, one_gap, mean_gap);
  EXPECT_GT(edges, 300u);
  EXPECT_LT(mean_gap, 0.6 * one_gap);

  scene::View moved = scene->camera;
  moved.position += glm::vec3(0.2f, 0.1f, 0.0f);
  e.executor.set_view(moved, scene->lights);
  const graph::FrameResult after_move = e.executor.run_frame(true);
  EXPECT_EQ(after_move.counters.at("still_mean.frames"), 1.0);
  EXPECT_LT(relative_difference(e.executor.read_image("still_mean"), e.executor.read_image("refracted")), 1e-6)
      << "the first frame after a move is not the unmoved image";
}

}  // namespace
}  // namespace caustica
