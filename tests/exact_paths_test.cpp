// Exact light paths, validation on, by the device's tracer (ray queries where it has them, else the
// compute tracer; docs/exact_paths.md): the photon tracer against docs/oracles.md's ball lens (with
// each tracer the device has), its flux bookkeeping, the hybrid's re-trace reasons, and camera
// refraction (exact and hybrid) against the ray-traced reference. The two tracers against each
// other are in tracer_test.cpp.
#include <gtest/gtest.h>

#include <cstdio>

#include <filesystem>

#include "ball_lens.h"
#include "reference/image_metrics.h"
#include "reference/photon_reference.h"
#include "reference/refraction_reference.h"
#include "scene_engine.h"

using namespace caustica;

namespace {

double sum_of(const graph::FrameResult& frame, std::initializer_list<const char*> names) {
  double total = 0;
  for (const char* name : names) total += frame.counters.at(name);
  return total;
}

}  // namespace

// Without Fresnel, every photon that enters a sphere leaves it (docs/oracles.md): the exact tracer must
// land the whole entering flux, at the radii the analytic lens gives. The cumulative fraction of
// the entering flux inside r = 0.05 .. 0.5 R on the floor must be within 0.02 of the exact lens at
// every radius; the image-space methods miss it by up to 0.14 (caustics_test). With each tracer the
// device has: the compute tracer everywhere, ray queries where it has them.
TEST(ExactPaths, ExactPhotonsMatchTheExactBallLensWithEachTracer) {
  test::SceneEngine e;
  std::vector<graph::Tracer> tracers{graph::Tracer::compute};
  if (e.vk.ray_queries().available) tracers.push_back(graph::Tracer::ray_query);
  for (graph::Tracer tracer : tracers) {
    SCOPED_TRACE(graph::tracer_name(tracer));
    e.tracer = tracer;
    auto scene = test::load_bundled_scene("sphere_plane");
    const std::vector<double> radii{0.05, 0.1, 0.2, 0.3, 0.5};
    const test::ExactLens lens = test::exact_ball_lens(*scene, radii);
    auto frame = e.render("caustics_raytraced", scene, {"fresnel=false", "grid=1024"}, {"caustics"});
    const double exact_entering = test::flux_into_ball(*scene);
    const double entering = frame.counters.at("caustic.flux_entering"), landed = frame.counters.at("caustic.flux");
    const std::vector<double> inside = test::map_flux_inside(*scene, e.executor.read_image("caustics"), radii);
    for (size_t k = 0; k < radii.size(); ++k) {
      std::printf("r = %.2f R: exact %.4f, traced %.4f of the entering flux\n", radii[k], lens.inside[k], inside[k] / entering);
      EXPECT_NEAR(inside[k] / entering, lens.inside[k], 0.02) << "r = " << radii[k];
    }
    // The exact lens counts every ray that reaches the floor; the map holds those inside the light's view.
    const double on_floor = landed + frame.counters.at("caustic.flux_off_map");
    std::printf("entering %.4f (exact %.4f), on the floor %.4f (%.4f of it; exact %.4f), in the map %.4f\n", entering, exact_entering,
                on_floor, on_floor / entering, lens.landed, landed);
    EXPECT_NEAR(entering, exact_entering, 0.01 * exact_entering);  // the silhouette sampled by 1024^2 photons
    EXPECT_NEAR(on_floor / entering, lens.landed, 0.005);
    EXPECT_EQ(frame.counters.at("photons.dropped_tir"), 0.0);
    EXPECT_EQ(frame.counters.at("photons.reflected_outside"), 0.0);  // no Fresnel: nothing reflects off the outside
    EXPECT_GT(frame.counters.at("photons.exact"), 0.0);
  }
}

// The flux of the caustic map that `graph` renders (its frame, counters included, into *frame when given).
double rendered_flux(test::SceneEngine& e, const std::string& graph_name, std::shared_ptr<const scene::Scene> scene,
                     const std::vector<std::string>& sets, graph::FrameResult* frame = nullptr) {
  auto result = e.render(graph_name, std::move(scene), sets, {"caustics"});
  if (frame) *frame = std::move(result);
  return test::map_flux(e.executor.read_image("caustics"));
}

// A glass ball under a quad cut into a checker by its alpha MASK (tests/data/mask_over_lens.json):
// only the light through the holes reaches the ball. The ray-query tracer passes the holes (its
// candidate hits are tested against the mask's texture) and lands the photon reference's caustic
// flux within 3%; the image-space map sees the holes through the light's depth map, and lands the
// photons whose floor point the quad hides from the light where the light sees the quad (0.789 of
// the reference; 0.757 when they were dropped); with the mask treated as opaque, the reference has
// no caustic at all.
TEST(ExactPaths, MaskedSurfacesLetPhotonsThroughTheirHoles) {
  test::SceneEngine e;
  auto scene = std::make_shared<scene::Scene>(
      scene::load_scene_file((std::filesystem::path(CAUSTICA_SOURCE_DIR) / "tests/data/mask_over_lens.json").string()));
  reference::PhotonOptions options;
  options.photons = 4'000'000;
  options.fresnel = false;
  const double reference = test::map_flux(reference::trace_photon_reference(*scene, options).caustic_map);
  auto opaque = std::make_shared<scene::Scene>(*scene);
  for (auto& o : opaque->objects) o.material.alpha_mode = scene::AlphaMode::opaque;
  const double reference_opaque = test::map_flux(reference::trace_photon_reference(*opaque, options).caustic_map);
  const double traced = rendered_flux(e, "caustics_raytraced", scene, {"fresnel=false", "grid=1024"});
  const double regular = rendered_flux(e, "caustics_regular", scene, {"fresnel=false", "grid=1024"});
  std::printf("caustic flux under the masked quad: reference %.5f (%.5f with the mask opaque), ray query %.4f, regular %.4f of it\n",
              reference, reference_opaque, traced / reference, regular / reference);
  ASSERT_GT(reference, 0.0);
  EXPECT_LT(reference_opaque, 0.01 * reference);
  EXPECT_NEAR(traced / reference, 1.0, 0.03);
  EXPECT_GT(regular / reference, 0.775);
}

// distance=material chooses the method from the material a photon meets first: exact paths
// through a solid (the ball lens: the ray-query tracer's map, to the photon), image space through
// a thin wall, where image space sees the exact path (the thin panes without Fresnel: the
// image-space map, to the photon, with no exact photon at all).
TEST(ExactPaths, MaterialModeTracesSolidsExactlyAndThinWallsInImageSpace) {
  test::SceneEngine e;
  auto ball = test::load_bundled_scene("sphere_plane");
  const double exact = rendered_flux(e, "caustics_raytraced", ball, {"distance=ray_query", "grid=1024"});
  graph::FrameResult by_material;
  const double chosen = rendered_flux(e, "caustics_raytraced", ball, {"distance=material", "grid=1024"}, &by_material);
  const double image_space = rendered_flux(e, "caustics_raytraced", ball, {"distance=dv_dn", "grid=1024"});
  std::printf("ball lens: material %.5f, ray query %.5f, image space %.5f\n", chosen, exact, image_space);
  EXPECT_NEAR(chosen / exact, 1.0, 1e-4);
  EXPECT_LT(image_space / exact, 0.9);  // what the choice avoids
  EXPECT_GT(by_material.counters.at("photons.exact"), 0.0);

  auto panes = test::load_bundled_scene("thin_panes");
  auto thin = e.render("caustics_raytraced", panes, {"distance=material", "grid=1024", "fresnel=false"}, {"caustics"});
  const auto thin_map = e.executor.read_image("caustics");
  e.render("caustics_raytraced", panes, {"distance=dv_dn", "grid=1024", "fresnel=false"}, {"caustics"});
  const auto image_space_map = e.executor.read_image("caustics");
  EXPECT_EQ(thin.counters.at("photons.exact"), 0.0);
  EXPECT_LT(test::relative_difference(thin_map, image_space_map), 1e-5);

  // The camera's rays choose alike.
  auto view = [&](const std::shared_ptr<scene::Scene>& scene, const char* distance) {
    e.render("refraction_raytraced", scene, {std::string("distance=") + distance}, {"refracted"});
    return e.executor.read_image("refracted").rgba;
  };
  EXPECT_EQ(view(ball, "material"), view(ball, "ray_query"));
  EXPECT_NE(view(ball, "material"), view(ball, "dv_dn"));
  EXPECT_EQ(view(panes, "material"), view(panes, "dv_dn"));
}

// Where image space cannot see a thin wall's whole path, distance=material traces it exactly, so its
// map is the ray-query tracer's (tests/data/thin_walls_reflect.json): the light a steep pane
// reflects onto the floor (the exact tracer's Fresnel choices, replayed), and the light through a
// pane that a glass ball below it then bends. Image space alone loses the first and misplaces the
// second; the panes' transmitted light stays in image space.
TEST(ExactPaths, MaterialModeTracesWhatImageSpaceCannotSeeBehindAThinWall) {
  test::SceneEngine e;
  auto shared = std::make_shared<scene::Scene>(
      scene::load_scene_file((std::filesystem::path(CAUSTICA_SOURCE_DIR) / "tests/data/thin_walls_reflect.json").string()));
  auto map_of = [&](const char* distance, graph::FrameResult* frame = nullptr) {
    auto result = e.render("caustics_raytraced", shared, {std::string("distance=") + distance, "grid=1024"}, {"caustics"});
    if (frame) *frame = result;
    return e.executor.read_image("caustics");
  };
  graph::FrameResult exact_frame, material_frame;
  const auto exact = map_of("ray_query", &exact_frame), chosen = map_of("material", &material_frame), image_space = map_of("dv_dn");
  const auto chosen_vs_exact = reference::compare_images(chosen, exact, 1.5),
             image_vs_exact = reference::compare_images(image_space, exact, 1.5);
  std::printf("material against ray query: energy %.5f, relative L1 %.5f (%.0f of %.0f photons exact); image space: energy %.4f, L1 %.4f\n",
              chosen_vs_exact.energy_ratio, chosen_vs_exact.relative_l1, material_frame.counters.at("photons.exact"),
              exact_frame.counters.at("photons.exact"), image_vs_exact.energy_ratio, image_vs_exact.relative_l1);
  EXPECT_NEAR(chosen_vs_exact.energy_ratio, 1.0, 1e-3);
  EXPECT_LT(chosen_vs_exact.relative_l1, 0.01);
  EXPECT_LT(image_vs_exact.energy_ratio, 0.97);  // the steep pane's reflection, lost
  EXPECT_GT(image_vs_exact.relative_l1, 0.2);    // the ball's caustic, missing
  EXPECT_LT(material_frame.counters.at("photons.exact"), 0.8 * exact_frame.counters.at("photons.exact"));

  // The camera's rays choose alike: through the pane over the ball, the ball is seen.
  auto view = [&](const char* distance) {
    e.render("refraction_raytraced", shared, {std::string("distance=") + distance}, {"refracted"});
    return e.executor.read_image("refracted");
  };
  const auto view_exact = view("ray_query");
  const double view_chosen = reference::compare_images(view("material"), view_exact, 1.5).relative_l1,
               view_image_space = reference::compare_images(view("dv_dn"), view_exact, 1.5).relative_l1;
  std::printf("camera, relative L1 against ray query: material %.2e, image space %.2e\n", view_chosen, view_image_space);
  EXPECT_LT(view_chosen, 1e-4);
  EXPECT_GT(view_image_space, 1e-3);
}

// The adaptive traversal with distance=material keeps a thin wall's Fresnel weights instead of the
// regular grid's replayed choices: a cluster whose photons all happened to pass would converge
// with their whole power, one that reflected refine on, and the map would gain what the walls
// reflect (1.035 of the exact map on the thin panes at 2048^2 when it did).
TEST(ExactPaths, AdaptiveMaterialModeKeepsTheThinWallsFresnelWeights) {
  test::SceneEngine e;
  auto panes = test::load_bundled_scene("thin_panes");
  const double exact = rendered_flux(e, "caustics_raytraced", panes, {"distance=ray_query", "grid=2048"});
  const double adaptive = rendered_flux(e, "caustics_adaptive_hybrid", panes, {"distance=material", "grid=2048"});
  std::printf("thin panes, Fresnel on: adaptive material %.5f of the ray-query map\n", adaptive / exact);
  EXPECT_NEAR(adaptive / exact, 1.0, 0.01);
}

// The adaptive hybrid keeps the exact caustic's flux at n = 2.4, where exact paths reflect inside
// the refractor at every interface: a cluster whose four photons are all lost ends only when none
// of their paths reflected inside (adaptive_photons.comp, lost_for_good), since where such paths
// leave changes from facet to facet. Against 4e6 reference photons at 2048^2 (2026-11-27): 0.983
// with that exception, 0.954 without it (and this test fails). The traversal's second look at
// clusters decided on random draws no longer shows here: switched off, the map kept 0.9996 of the
// regular grid's hybrid map, as with it.
TEST(ExactPaths, AdaptiveHybridKeepsTheHighIndexEnergy) {
  test::SceneEngine e;
  auto scene = test::load_bundled_scene("stability/high_index");
  reference::PhotonOptions options;
  options.photons = 4'000'000;
  const double reference = test::map_flux(reference::trace_photon_reference(*scene, options).caustic_map);
  const double adaptive = rendered_flux(e, "caustics_adaptive_hybrid", scene, {"grid=2048"});
  std::printf("n = 2.4: adaptive hybrid %.4f of the photon reference's caustic flux\n", adaptive / reference);
  EXPECT_GT(adaptive / reference, 0.97);
  EXPECT_LT(adaptive / reference, 1.03);
}

// The caustic map's relative L1 (blur 1.5 texels, as the chart) against 2e7 reference photons of
// the scene (seed 1), for each graph and settings rendered.
struct CausticError {
  test::SceneEngine& e;
  std::shared_ptr<const scene::Scene> subject;
  io::ImageData reference_map = trace_reference(*subject);

  static io::ImageData trace_reference(const scene::Scene& s) {
    reference::PhotonOptions options;
    options.photons = 20'000'000;
    return reference::trace_photon_reference(s, options).caustic_map;
  }
  double operator()(const char* graph, const std::vector<std::string>& sets) const {
    e.render(graph, subject, sets, {"caustics"});
    return reference::compare_images(e.executor.read_image("caustics"), reference_map, 1.5).relative_l1;
  }
};

// The adaptive hybrid's error stays within 1.5 times the ray-query tracer's at the same grid on
// the ball lens, whose focus puts a fifth of the caustic flux into four texels. Its trusted
// landings are image space's, sampled from light-view buffer texels, and a cluster whose four such
// landings share a caustic-map texel at 512^2 put its power a tenth of a texel off the focus: so
// the hybrid graphs let clusters converge from 1024^2 on. Measured at 2048^2 against 2e7 reference
// photons: ray query 0.037; adaptive hybrid 0.050 (0.078 converging from 512^2), 0.049 since the
// search blends the buffers' normals.
TEST(ExactPaths, AdaptiveHybridKeepsTheBallLensFocusInPlace) {
  test::SceneEngine e;
  auto scene = test::load_bundled_scene("sphere_plane");
  const CausticError error_of{e, scene};
  const double exact = error_of("caustics_raytraced", {"distance=ray_query", "grid=2048"});
  const double hybrid = error_of("caustics_adaptive_hybrid", {"grid=2048"});
  std::printf("ball lens at 2048^2, relative L1 against the photon reference: ray query %.4f, adaptive hybrid %.4f (%.2fx)\n", exact,
              hybrid, hybrid / exact);
  EXPECT_LT(hybrid, 1.5 * exact);
}

// The bunny's rows of docs/exact_paths.md's targets at 2048^2 photons: the default graph's
// image-space search at most 0.25 relative L1, the adaptive hybrid at most 0.15 and at most 1.5
// times the ray-query tracer's error. The chart measured 0.229, 0.087 and 1.41x against 10^8
// reference photons; this reference has 2e7 (seed 1), whose own noise adds to every error.
TEST(ExactPaths, TheBunnyMeetsTheSearchAndHybridTargets) {
  test::SceneEngine e;
  auto scene = test::load_bundled_scene("bunny_plane");
  const CausticError error_of{e, scene};
  const double search = error_of("caustics_adaptive", {"grid=2048"});
  const double hybrid = error_of("caustics_adaptive_hybrid", {"grid=2048"});
  const double exact = error_of("caustics_raytraced", {"distance=ray_query", "grid=2048"});
  std::printf("bunny at 2048^2, relative L1 against 2e7 reference photons: search %.4f, adaptive hybrid %.4f, ray query %.4f (%.2fx)\n",
              search, hybrid, exact, hybrid / exact);
  EXPECT_LE(search, 0.25);
  EXPECT_LE(hybrid, 0.15);
  EXPECT_LE(hybrid, 1.5 * exact);
}

// The hybrid splits the Fresnel reflections it cannot follow in image space (off the entry, or back
// inside at the exit) off a trusted path and traces them exactly from there. On stacked refractors,
// where light reflected off one refractor lands through another, image space weights that light
// away: the regular-grid hybrid keeps 0.916 of the ray-query tracer's flux without the reflections,
// and 0.99 with them (every reflection traced, or a quarter of them with four times the power).
// Every exact trace has its reason counted.
TEST(ExactPaths, HybridTracesTheFresnelReflectionsImageSpaceCannotFollow) {
  test::SceneEngine e;
  auto scene = test::load_bundled_scene("three_refractors");
  const double exact = rendered_flux(e, "caustics_raytraced", scene, {"distance=ray_query", "grid=512"});
  double kept[3];
  const char* shares[] = {"0", "0.25", "1"};
  for (int i = 0; i < 3; ++i) {
    graph::FrameResult frame;
    kept[i] = rendered_flux(e, "caustics_raytraced", scene, {"distance=hybrid", "grid=512", std::string("hybrid_reflections=") + shares[i]},
                            &frame) /
              exact;
    const double reasons = sum_of(frame, {"photons.retraced.tir", "photons.retraced.empty_back", "photons.retraced.off_surface",
                                          "photons.retraced.multiple_refractors", "photons.retraced.no_landing",
                                          "photons.retraced.refractor_ahead", "photons.retraced.reflection"});
    std::printf("hybrid_reflections %s: %.4f of the ray-query map's flux; %.0f reflections traced, %.0f photons traced exactly\n",
                shares[i], kept[i], frame.counters.at("photons.retraced.reflection"), frame.counters.at("photons.exact"));
    // A re-traced photon whose exact path misses the refractor (past its silhouette) is not exact.
    EXPECT_LE(frame.counters.at("photons.exact"), reasons) << shares[i];
    EXPECT_GT(frame.counters.at("photons.exact"), 0.98 * reasons) << shares[i];
    if (i == 0)
      EXPECT_EQ(frame.counters.at("photons.retraced.reflection"), 0.0);
    else
      EXPECT_GT(frame.counters.at("photons.retraced.reflection"), 0.0);
  }
  EXPECT_LT(kept[0], 0.95);
  EXPECT_NEAR(kept[1], 1.0, 0.02);
  EXPECT_NEAR(kept[2], 1.0, 0.02);
}

// With Fresnel and absorption, every entering photon ends in exactly one place: landed, escaped,
// trapped, off the map, or absorbed on the way; the sums add up to the entering flux.
TEST(ExactPaths, EveryEnteringPhotonIsAccountedFor) {
  test::SceneEngine e;
  auto scene = test::load_bundled_scene("sphere_plane");
  scene->objects.back().material.absorption = glm::vec3(0.3f, 0.2f, 0.1f);
  auto frame = e.render("caustics_raytraced", scene, {"grid=512"}, {});
  const double entering = frame.counters.at("caustic.flux_entering");
  const double rest =
      sum_of(frame, {"caustic.flux", "caustic.flux_escaped", "caustic.flux_trapped", "caustic.flux_off_map", "caustic.flux_absorbed"});
  std::printf(
      "entering %.5f, landed + escaped + trapped + off map + absorbed %.5f; absorbed %.5f, reflected off the outside %.0f photons\n",
      entering, rest, frame.counters.at("caustic.flux_absorbed"), frame.counters.at("photons.reflected_outside"));
  EXPECT_NEAR(rest, entering, 1e-4 * entering);
  EXPECT_NEAR(frame.counters.at("caustic.flux_dropped"),
              sum_of(frame, {"caustic.flux_escaped", "caustic.flux_trapped", "caustic.flux_off_map"}), 1e-4 * entering);
  EXPECT_GT(frame.counters.at("caustic.flux_absorbed"), 0.0);
  EXPECT_GT(frame.counters.at("photons.reflected_outside"), 0.0);  // Fresnel on: some reflect off the outside and are followed
}

// The same photon and seed take the same path every time; another seed changes the Fresnel choices.
TEST(ExactPaths, FresnelChoicesAreDeterministicPerSeed) {
  test::SceneEngine e;
  auto scene = test::load_bundled_scene("sphere_plane");
  auto reflected = [&](const char* seed) {
    return e.render("caustics_raytraced", scene, {"grid=256", std::string("seed=") + seed}, {}).counters.at("photons.reflected_outside");
  };
  const double first = reflected("1"), again = reflected("1"), other = reflected("2");
  std::printf("photons reflected off the outside: seed 1 %.0f and %.0f, seed 2 %.0f\n", first, again, other);
  EXPECT_EQ(first, again);
  EXPECT_NE(first, other);
}

// A workgroup queues its photons' exact paths and traces them side by side (photon.glsl,
// finish_photon): each photon must get its own path's result back, the same in every run, however
// the invocations interleave. The adaptive traversal's decisions and both maps' counters are
// compared across two runs of each hybrid (when a queue was refilled before every photon had
// taken its result, the adaptive counts changed from run to run).
TEST(ExactPaths, QueuedExactPathsReturnToTheirPhotonsInEveryRun) {
  test::SceneEngine e;
  auto scene = test::load_bundled_scene("three_refractors");
  const std::vector<std::string> counters{"photons.processed",
                                          "photons.exact",
                                          "photons.retraced.tir",
                                          "photons.retraced.no_landing",
                                          "photons.retraced.refractor_ahead",
                                          "photons.retraced.reflection",
                                          "photons.splatted",
                                          "photons.converged"};
  const std::vector<std::pair<const char*, std::vector<std::string>>> runs{{"caustics_adaptive_hybrid", {"grid=1024"}},
                                                                           {"caustics_raytraced", {"distance=hybrid", "grid=512"}}};
  for (const auto& [graph_name, sets] : runs) {
    graph::FrameResult first, again;
    const double first_flux = rendered_flux(e, graph_name, scene, sets, &first),
                 again_flux = rendered_flux(e, graph_name, scene, sets, &again);
    std::printf("%s: %.0f photons processed, %.0f traced exactly; map flux %.6f and %.6f\n", graph_name,
                first.counters.at("photons.processed"), first.counters.at("photons.exact"), first_flux, again_flux);
    EXPECT_GT(first.counters.at("photons.exact"), 0.0) << graph_name;
    // Every counter is reported by both graphs (a missing one fails rather than being skipped).
    for (const auto& name : counters) {
      ASSERT_TRUE(first.counters.count(name) && again.counters.count(name)) << graph_name << " does not report " << name;
      EXPECT_EQ(first.counters.at(name), again.counters.at(name)) << graph_name << " " << name;
    }
    EXPECT_NEAR(again_flux, first_flux, 1e-5 * first_flux) << graph_name;  // float atomics add in any order
  }
}

// The hybrid keeps the image-space estimate where it can be trusted and re-traces the rest: on the
// ball lens, the estimate's false total internal reflection near the rim is re-traced, so the
// hybrid lands (nearly) the exact lens's flux where the d_V/d_N estimate alone loses about 22%.
TEST(ExactPaths, HybridRetracesWhereTheEstimateFails) {
  test::SceneEngine e;
  auto scene = test::load_bundled_scene("sphere_plane");
  const test::ExactLens lens = test::exact_ball_lens(*scene, {0.5});
  auto image_space = e.render("caustics_adaptive", scene, {"fresnel=false", "distance=dv_dn"}, {});
  auto hybrid = e.render("caustics_adaptive_hybrid", scene, {"fresnel=false"}, {});
  const double retraced =
      sum_of(hybrid, {"photons.retraced.tir", "photons.retraced.empty_back", "photons.retraced.off_surface",
                      "photons.retraced.multiple_refractors", "photons.retraced.no_landing", "photons.retraced.refractor_ahead"});
  const double exact_landed = lens.landed * test::flux_into_ball(*scene);
  std::printf(
      "landed: image space %.4f, hybrid %.4f, exact %.4f; re-traced %.0f of %.0f photons (tir %.0f, empty back %.0f, off surface %.0f)\n",
      image_space.counters.at("caustic.flux"), hybrid.counters.at("caustic.flux"), exact_landed, retraced,
      hybrid.counters.at("photons.processed"), hybrid.counters.at("photons.retraced.tir"),
      hybrid.counters.at("photons.retraced.empty_back"), hybrid.counters.at("photons.retraced.off_surface"));
  EXPECT_GT(hybrid.counters.at("photons.retraced.tir"), 0.0);
  EXPECT_LT(retraced, 0.5 * hybrid.counters.at("photons.processed"));  // most photons keep the estimate
  EXPECT_LE(hybrid.counters.at("photons.exact"), retraced);            // only re-traced photons are traced exactly
  EXPECT_LT(image_space.counters.at("caustic.flux"), 0.85 * exact_landed);
  EXPECT_NEAR(hybrid.counters.at("caustic.flux"), exact_landed, 0.05 * exact_landed);
}

// Image space sees one refractor layer: on the bunny, light that leaves one fold meets the bunny
// again (an ear, the body). The hybrid traces each trusted path's exit ray exactly, lands it where
// it meets a receiver and re-traces it from the light where it meets a refractor. Against the
// ray-query tracer's map of the same photons (the paths they share are the same paths, so what
// differs is the image-space part's error), measured at 512^2: relative L1 0.140 and energy 0.995
// (0.187 and 1.000 when the search read the nearest texel's normal; against 2e7 reference photons
// the energy is 0.995, 1.001 and 0.998 at 512^2, 1024^2 and 2048^2); with the exit ray marched
// through the light's depth map instead, 0.239 and 1.015 (the light the bunny would have caught
// again landed as if it were not there).
namespace {

// The regular-grid hybrid's map at 512^2 against the ray-query tracer's of the same photons (the
// paths they share are the same paths, so what differs is the image-space part's error).
struct HybridAgainstExact {
  graph::FrameResult hybrid;
  reference::ImageComparison c;
};

HybridAgainstExact hybrid_against_ray_query(test::SceneEngine& e, const char* scene_name) {
  auto scene = test::load_bundled_scene(scene_name);
  e.render("caustics_raytraced", scene, {"distance=ray_query", "grid=512"}, {"caustics"});
  const io::ImageData exact = e.executor.read_image("caustics");
  auto hybrid = e.render("caustics_raytraced", scene, {"distance=hybrid", "grid=512"}, {"caustics"});
  return {std::move(hybrid), reference::compare_images(e.executor.read_image("caustics"), exact, 1.5)};
}

}  // namespace

TEST(ExactPaths, HybridRetracesExitRaysThatMeetTheRefractorAgain) {
  test::SceneEngine e;
  const auto [hybrid, c] = hybrid_against_ray_query(e, "bunny_plane");
  std::printf("bunny, hybrid against the ray-query map: relative L1 %.4f, energy %.4f; %.0f exit rays met the bunny again\n", c.relative_l1,
              c.energy_ratio, hybrid.counters.at("photons.retraced.refractor_ahead"));
  EXPECT_GT(hybrid.counters.at("photons.retraced.refractor_ahead"), 0.0);
  EXPECT_NEAR(c.energy_ratio, 1.0, 0.01);
  EXPECT_LT(c.relative_l1, 0.17);
}

// Light that leaves a convex solid cannot meet it again (scene/convexity.cpp), so the hybrid traces
// its exit ray against the receivers alone, past every refractor's structure; another refractor on
// its way still sends it back to the light, since its bounds are crossed. On the stacked refractors
// (a ball, a slab and a box, all convex) no exit ray can then meet a refractor (203 did when they
// were traced against everything; 2,507 cross another's bounds, 2,305 did), and the map is the
// same: against the ray-query tracer's of the same photons at 512^2, energy 0.9933 and relative L1
// 0.1517 either way.
TEST(ExactPaths, HybridTracesConvexRefractorsExitRaysPastTheRefractors) {
  test::SceneEngine e;
  const auto [hybrid, c] = hybrid_against_ray_query(e, "three_refractors");
  std::printf(
      "stacked refractors, hybrid against the ray-query map: relative L1 %.4f, energy %.4f; exit rays that met a refractor %.0f, "
      "that crossed another's bounds %.0f\n",
      c.relative_l1, c.energy_ratio, hybrid.counters.at("photons.retraced.refractor_ahead"),
      hybrid.counters.at("photons.retraced.multiple_refractors"));
  EXPECT_EQ(hybrid.counters.at("photons.retraced.refractor_ahead"), 0.0);
  EXPECT_GT(hybrid.counters.at("photons.retraced.multiple_refractors"), 0.0);
  EXPECT_NEAR(c.energy_ratio, 1.0, 0.01);
  EXPECT_LT(c.relative_l1, 0.17);
}

namespace {

struct CameraRun {
  double error;  // relative L1 against the ray-traced reference over the refractor's pixels
  graph::FrameResult frame;
};

CameraRun camera_refraction(test::SceneEngine& e, const std::string& graph, const std::shared_ptr<scene::Scene>& scene,
                            const reference::RefractionImage& reference, const std::vector<std::string>& sets = {}) {
  CameraRun r;
  r.frame = e.render(graph, scene, sets, {"refracted"});
  r.error = reference::refraction_relative_l1(e.executor.read_image("refracted"), reference);
  return r;
}

}  // namespace

// Camera rays traced exactly through every interface of every refractor land on the Embree
// reference (engine/reference/refraction_reference.cpp, written separately from the shaders),
// where the image-space estimate is off by 15 to 50%. What remains is the lit image's shadow map
// against the reference's exact shadow rays. Measured at 320x180 when written: 0.007 sphere, 0.087
// bunny, 0.018 three refractors (d_V/d_N: 0.154, 0.480, 0.500); the limits leave some room.
TEST(ExactPaths, RayQueryRefractionMatchesTheRayTracedReference) {
  test::SceneEngine e;
  struct Case {
    const char* scene;
    double limit;
  };
  for (auto [name, limit] : {Case{"sphere_plane", 0.02}, Case{"bunny_plane", 0.12}, Case{"three_refractors", 0.04}}) {
    auto scene = test::load_bundled_scene(name);
    const auto reference = reference::render_refraction_reference(*scene, e.width, e.height);
    const CameraRun exact = camera_refraction(e, "refraction_raytraced", scene, reference);
    const CameraRun estimate = camera_refraction(e, "refraction_deferred", scene, reference);
    std::printf("%-16s relative L1: ray query %.4f, d_V/d_N %.4f; %.0f pixels traced, %.0f trapped\n", name, exact.error, estimate.error,
                exact.frame.counters.at("refraction.exact_pixels"), exact.frame.counters.at("refraction.trapped_pixels"));
    EXPECT_LT(exact.error, limit) << name;
    EXPECT_LT(exact.error, 0.5 * estimate.error) << name;
    EXPECT_GT(exact.frame.counters.at("refraction.exact_pixels"), 0.0) << name;
  }
}

// The camera sees a textured pane's tint and transmission per pixel in image space too: the
// refractor buffers carry them (front_tint) for deferred refraction and for each layer of the
// multi-layer pass. Through tests/data/gltf/tinted_pane.gltf and blend_pane.gltf (caustics_test,
// TintAndTransmissionAreReadPerTexelInEveryMethod) a thin wall bends nothing, so image space sees
// the exact path and lands on the ray-traced reference but for the lit image's shadow map; with
// each pane's means it would show both halves purple.
TEST(ExactPaths, ImageSpaceRefractionReadsTintAndTransmissionPerPixel) {
  test::SceneEngine e;
  for (const char* pane : {"tinted_pane.gltf", "blend_pane.gltf"}) {
    const std::string file = (std::filesystem::path(CAUSTICA_SOURCE_DIR) / "tests/data/gltf" / pane).string();
    auto scene = std::make_shared<scene::Scene>(scene::load_model_scene(file, false));
    const auto reference = reference::render_refraction_reference(*scene, e.width, e.height);
    for (const char* graph : {"refraction_deferred", "refraction_multilayer"}) {
      const CameraRun run = camera_refraction(e, graph, scene, reference);
      std::printf("%s, %s: relative L1 %.4f\n", pane, graph, run.error);
      EXPECT_LT(run.error, 0.05) << pane << ", " << graph;
    }
  }
}

// The camera hybrid searches in image space and traces a pixel exactly only where the search cannot
// be trusted, with one counter per reason, and stays within 1.5 times the exact tracer's error: on
// the ball lens it traces well under all of the refractor's pixels (measured 1746 of 3830: the exit
// rays whose hit the camera does not see); with three refractors, the pixels whose exit rays pass
// another refractor's bounds (the refractor invisible to one image-space layer) are traced, which
// takes the error from the search's 0.30 to 0.018 (exact: 0.018). Measured when the search
// began to blend the back surface's normals (refraction.glsl, smooth_normal): hybrid against exact
// 1.04x on the ball lens, 1.01x with three refractors, 1.27x on the bunny; with the nearest
// normal, 1.78x, 1.27x and 1.40x.
TEST(ExactPaths, HybridRefractionTracesOnlyWhereTheSearchFails) {
  test::SceneEngine e;
  for (const char* name : {"sphere_plane", "three_refractors", "bunny_plane"}) {
    auto scene = test::load_bundled_scene(name);
    const auto reference = reference::render_refraction_reference(*scene, e.width, e.height);
    const CameraRun exact = camera_refraction(e, "refraction_raytraced", scene, reference);
    const CameraRun hybrid = camera_refraction(e, "refraction_hybrid", scene, reference);
    const CameraRun search = camera_refraction(e, "refraction_deferred", scene, reference, {"distance=search"});
    const auto& c = hybrid.frame.counters;
    const double reasons = sum_of(
        hybrid.frame, {"refraction.retraced.tir", "refraction.retraced.empty_back", "refraction.retraced.off_surface",
                       "refraction.retraced.multiple_refractors", "refraction.retraced.off_screen", "refraction.retraced.refractor_ahead"});
    std::printf(
        "%-16s relative L1: hybrid %.4f, ray query %.4f, search %.4f; traced %.0f of %.0f pixels (tir %.0f, empty back %.0f, off "
        "surface %.0f, other refractor %.0f, off screen %.0f, refractor ahead %.0f)\n",
        name, hybrid.error, exact.error, search.error, c.at("refraction.exact_pixels"), exact.frame.counters.at("refraction.exact_pixels"),
        c.at("refraction.retraced.tir"), c.at("refraction.retraced.empty_back"), c.at("refraction.retraced.off_surface"),
        c.at("refraction.retraced.multiple_refractors"), c.at("refraction.retraced.off_screen"),
        c.at("refraction.retraced.refractor_ahead"));
    EXPECT_EQ(reasons, c.at("refraction.exact_pixels")) << name;  // every traced pixel has exactly one reason
    EXPECT_LT(hybrid.error, 1.5 * exact.error) << name;
    EXPECT_LT(hybrid.error, search.error) << name;
    if (std::string(name) == "sphere_plane") {
      EXPECT_LT(c.at("refraction.exact_pixels"), 0.6 * exact.frame.counters.at("refraction.exact_pixels")) << name;
    } else if (std::string(name) == "bunny_plane") {
      EXPECT_GT(c.at("refraction.retraced.refractor_ahead"), 0.0) << name;
    } else {
      // Three convex solids: an exit ray is traced past the refractors, so none meets one; the
      // other refractors' bounds send those pixels to the exact tracer.
      EXPECT_EQ(c.at("refraction.retraced.refractor_ahead"), 0.0) << name;
      EXPECT_GT(c.at("refraction.retraced.multiple_refractors"), 0.0) << name;
    }
  }
}

// The image-space search follows total internal reflection inside the refractor for a few bounces
// (Davis and Wyman 2007) instead of dropping the ray, on every device (no ray queries). On the
// bunny, where many rays meet it at the exit, d_V/d_N drops 33,547 photons and marks 1,796 camera
// pixels as total internal reflection; the search without following dropped 35,853 and 1,654, with
// following 20,982 and 768 (measured when written), and lands 15% more flux. search_bounces (3 by
// default in the passes, 1 in caustics_adaptive.json) sets how many bounces: with 0 the search
// drops them at the first, as d_V/d_N does (34,943 photons and 1,645 pixels; 11% less flux than
// with 3).
TEST(ExactPaths, TheSearchFollowsTotalInternalReflectionInside) {
  test::SceneEngine e;
  auto scene = test::load_bundled_scene("bunny_plane");
  auto estimate = e.render("caustics_adaptive", scene, {"distance=dv_dn"}, {});
  auto unfollowed = e.render("caustics_adaptive", scene, {"distance=search", "search_bounces=0"}, {});
  auto search = e.render("caustics_adaptive", scene, {"distance=search", "search_bounces=3"}, {});
  EXPECT_GT(unfollowed.counters.at("photons.dropped_tir"), 1.3 * search.counters.at("photons.dropped_tir"));
  EXPECT_GT(unfollowed.counters.at("refraction.tir_pixels"), 1.5 * search.counters.at("refraction.tir_pixels"));
  EXPECT_LT(unfollowed.counters.at("caustic.flux"), 0.95 * search.counters.at("caustic.flux"));
  std::printf(
      "dropped as total internal reflection: d_V/d_N %.0f photons, %.0f pixels; search %.0f photons, %.0f pixels; flux %.4f -> %.4f\n",
      estimate.counters.at("photons.dropped_tir"), estimate.counters.at("refraction.tir_pixels"), search.counters.at("photons.dropped_tir"),
      search.counters.at("refraction.tir_pixels"), estimate.counters.at("caustic.flux"), search.counters.at("caustic.flux"));
  EXPECT_LT(search.counters.at("photons.dropped_tir"), 0.75 * estimate.counters.at("photons.dropped_tir"));
  EXPECT_LT(search.counters.at("refraction.tir_pixels"), 0.6 * estimate.counters.at("refraction.tir_pixels"));
  EXPECT_GT(search.counters.at("caustic.flux"), 1.08 * estimate.counters.at("caustic.flux"));
}

// The adaptive traversal decides on a photon's first exit alone: light that the search follows
// inside lands scattered, and refining where it lands took the bunny's clusters to 21% more photons
// (270,464 against 223,088 at 2048^2, when this was written). So one bounce processes exactly the
// photons of none, lands the light it follows (12% more flux), and keeps the regular map's flux
// with the same bounce within 2% (0.994 when written), the followed light splatted as coarse samples.
TEST(ExactPaths, FollowedReflectionsDoNotSteerTheAdaptiveTraversal) {
  test::SceneEngine e;
  auto scene = test::load_bundled_scene("bunny_plane");
  auto unfollowed = e.render("caustics_adaptive", scene, {"distance=search", "search_bounces=0", "grid=2048"}, {});
  auto followed = e.render("caustics_adaptive", scene, {"distance=search", "search_bounces=1", "grid=2048"}, {});
  auto regular = e.render("caustics_regular", scene, {"distance=search", "search_bounces=1", "grid=2048"}, {});
  const double flux = followed.counters.at("caustic.flux");
  std::printf("photons %.0f -> %.0f; flux %.4f -> %.4f, regular map %.4f\n", unfollowed.counters.at("photons.processed"),
              followed.counters.at("photons.processed"), unfollowed.counters.at("caustic.flux"), flux, regular.counters.at("caustic.flux"));
  EXPECT_EQ(followed.counters.at("photons.processed"), unfollowed.counters.at("photons.processed"));
  EXPECT_GT(flux, 1.08 * unfollowed.counters.at("caustic.flux"));
  EXPECT_NEAR(flux, regular.counters.at("caustic.flux"), 0.02 * regular.counters.at("caustic.flux"));
}
