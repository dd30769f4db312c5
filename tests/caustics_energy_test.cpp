// Caustics on the device (lavapipe, validation on; any message fails): energy bookkeeping against
// the exact flux into the ball lens, n = 1, where the caustic must exactly replace the shadow, the
// ball lens's cumulative flux against the exact lens, and the reference picture's caustic lighting.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "caustics_common.h"
#include "reference/refraction_reference.h"

using namespace caustica;
using namespace caustica::test::caustic_tests;

namespace {

// The scene made `k` times larger: every length, the light's intensity kept (the flux into the ball
// is a solid angle times it, which scaling leaves alone).
void scale_scene(scene::Scene& scene, float k) {
  auto scale_view = [k](scene::View& view) {
    view.position *= k;
    view.target *= k;
    view.near_plane *= k;
    view.far_plane *= k;
  };
  scale_view(scene.camera);
  for (auto& light : scene.lights) scale_view(light.view);
  for (auto& object : scene.objects) {
    for (auto& p : object.mesh.positions) p *= k;
    for (auto& d : object.mesh.normal_distance) d *= k;
    object.bounds_min *= k;
    object.bounds_max *= k;
    object.radius *= k;
  }
  for (auto& light : scene.lights) scene::fit_caustic_view(light, scene);
}

}  // namespace

// Image-space photons look for their receiver as far as the scene reaches: the ball lens made ten
// times larger lands the same share of its entering flux as the ball lens (a search that stopped a
// fixed 8 scene units out lost every photon of the large one).
TEST(Caustics, ImageSpacePhotonsFindTheirReceiversInALargeScene) {
  Engine e;
  auto landed_share = [&](float scale) {
    auto scene = load("sphere_plane");
    scale_scene(*scene, scale);
    auto frame = e.render("caustics_regular", scene, {"fresnel=false", "grid=1024"});
    return frame.counters.at("caustic.flux") / frame.counters.at("caustic.flux_entering");
  };
  const double unit = landed_share(1.0f), large = landed_share(10.0f);
  std::printf("landed share of the entering flux: ball lens %.4f, ten times larger %.4f\n", unit, large);
  EXPECT_GT(unit, 0.5);
  EXPECT_NEAR(large, unit, 0.01 * unit);
}

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
// must equal the direct light of the scene without the sphere (docs/oracles.md).
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

// docs/oracles.md's ball lens, cumulative flux inside radius r on the floor. The exact answer traces the
// light's rays through a perfect sphere analytically (both refractions exact; no ray that enters
// a sphere can meet total internal reflection), stratified over the sphere's solid angle. The
// engine's is read from the adaptive caustic map (2048^2 effective photons, both convergence
// tests): each texel's flux at the floor point its centre sees. Each way of finding the exit is
// pinned on its own: the fraction of the entering flux inside r, and the shape (the fraction of the
// landed flux inside r), each within a bound under twice the method's worst error when this was
// written (in the comments), so that a doubling of a method's error fails. d_V/d_N loses about a
// fifth of the entering flux to false total internal reflection near the rim, at every radius; the
// search, which finds the back surface, loses little. Measured when written (largest errors, both
// convergence tests, r = 0.5 R): d_V/d_N -0.141 of the entering flux and +0.053 of the landed; the
// search +0.0024 (r = 0.05 R) and +0.0215.
TEST(Caustics, BallLensCumulativeFluxMatchesTheExactLens) {
  Engine e;
  auto scene = load("sphere_plane");
  const std::vector<double> radii{0.05, 0.1, 0.2, 0.3, 0.5};
  const test::ExactLens lens = test::exact_ball_lens(*scene, radii);
  const std::vector<double>& exact = lens.inside;
  const double exact_landed = lens.landed;
  struct Method {
    const char* distance;
    double entering_bound, landed_bound;
  };
  for (const auto& [distance, entering_bound, landed_bound] : {Method{"dv_dn", 0.2, 0.075}, Method{"search", 0.004, 0.03}}) {
    for (const char* test : {"same_texel", "within_texel"}) {
      auto frame = e.render("caustics_adaptive", scene,
                            {"fresnel=false", "grid=2048", std::string("distance=") + distance, std::string("converge_test=") + test});
      const std::vector<double> engine = test::map_flux_inside(*scene, e.executor.read_image("caustics"), radii);
      const double entering = flux_into_ball(*scene), landed = frame.counters.at("caustic.flux");
      for (size_t k = 0; k < radii.size(); ++k) {
        std::printf(
            "%s, %s, r = %.2f R: exact %.4f, engine %.4f of the entering flux (error %+.4f), %.4f of the landed flux (error %+.4f)\n",
            distance, test, radii[k], exact[k], engine[k] / entering, engine[k] / entering - exact[k], engine[k] / landed,
            engine[k] / landed - exact[k] / exact_landed);
        EXPECT_NEAR(engine[k] / entering, exact[k], entering_bound) << distance << ", " << test << ", r = " << radii[k];
        EXPECT_NEAR(engine[k] / landed, exact[k] / exact_landed, landed_bound) << distance << ", " << test << ", r = " << radii[k];
      }
      EXPECT_GT(frame.counters.at("photons.splatted"), 0.0);
    }
  }
}

// The reference picture lights surfaces with a caustic map as the engine's lighting pass does:
// given the engine's own map, the caustic it adds to the directly seen floor (the picture with the
// map less the picture without) matches what the lighting pass adds (caustics_regular's lit image
// less refraction_deferred's, which draws no caustic), in total within 2% and pixel by pixel
// within a relative L1 of 0.05 (the engine offsets its lookups along the normal and tests a
// receiver depth map, the reference traces exact rays: 0.2% and 0.004 when this was written).
TEST(Caustics, TheReferencePictureProjectsACausticMapAsTheEngineDoes) {
  Engine e;
  auto scene = load("sphere_plane");
  auto with_caustics = e.render("caustics_regular", scene, {"grid=1024"});
  const io::ImageData map = e.executor.read_image("caustics");
  const io::ImageData lit = e.executor.read_image("lit");
  e.SceneEngine::render("refraction_deferred", scene, {}, {"lit"});
  const io::ImageData lit_without = e.executor.read_image("lit");
  const auto picture = reference::render_refraction_reference(*scene, kWidth, kHeight, {&map});
  const auto picture_without = reference::render_refraction_reference(*scene, kWidth, kHeight);
  double engine_sum = 0, reference_sum = 0, difference = 0;
  for (size_t i = 0; i < picture.refractor.size(); ++i) {
    if (picture.refractor[i]) continue;
    const double engine_caustic = double(lit.rgba[i * 4 + 1]) - double(lit_without.rgba[i * 4 + 1]);
    const double reference_caustic = double(picture.radiance.rgba[i * 4 + 1]) - double(picture_without.radiance.rgba[i * 4 + 1]);
    engine_sum += engine_caustic;
    reference_sum += reference_caustic;
    difference += std::abs(engine_caustic - reference_caustic);
  }
  std::printf("caustic radiance added on the directly seen floor: engine %.4f, reference picture %.4f, relative L1 %.4f\n", engine_sum,
              reference_sum, difference / reference_sum);
  ASSERT_GT(reference_sum, 0.0);
  EXPECT_NEAR(engine_sum, reference_sum, 0.02 * reference_sum);
  EXPECT_LT(difference / reference_sum, 0.05);
}
