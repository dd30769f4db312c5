// Caustics on the device, materials that spread the light: rough glass (per object and per texel
// on the exact paths) and dispersion by colour band, and the interface layers and the coat's own
// normal map per texel, against the photon reference.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "caustics_common.h"
#include "reference/photon_reference.h"

using namespace caustica;
using namespace caustica::test::caustic_tests;

namespace {

// The floor's flux under each half of pane asset tests/data/gltf/`asset` (flux_under_pane_halves):
// the photon reference's (1e6 photons), the exact tracer's (1024^2) and, where asked, image space's
// (caustics_regular, 1024^2).
struct PaneHalves {
  std::array<glm::dvec3, 2> reference, traced, image_space;
};
PaneHalves pane_halves(Engine& e, const char* asset, bool image_space = false) {
  const std::string file = (std::filesystem::path(CAUSTICA_SOURCE_DIR) / "tests/data/gltf" / asset).string();
  auto scene = std::make_shared<scene::Scene>(scene::load_model_scene(file, false));
  reference::PhotonOptions options;
  options.photons = 1'000'000;
  PaneHalves flux;
  flux.reference = flux_under_pane_halves(*scene, reference::trace_photon_reference(*scene, options).caustic_map);
  e.render("caustics_raytraced", scene, {"grid=1024"});
  flux.traced = flux_under_pane_halves(*scene, e.executor.read_image("caustics"));
  if (image_space) {
    e.render("caustics_regular", scene, {"grid=1024"});
    flux.image_space = flux_under_pane_halves(*scene, e.executor.read_image("caustics"));
  }
  return flux;
}

}  // namespace

// Rough transmission (glTF's roughness on a transmissive material) blurs the caustic: the ball
// lens at roughness 0.3 spreads its focused light over the floor, in the photon reference and in
// every method, so the flux-weighted distance from the axis grows (by 17% in the reference when
// this was written). The exact tracer's distance and energy are the reference's within 2%. The
// image-space methods refract about the same microfacets at their estimated interfaces, so their
// distance grows too, by at least half the reference's growth.
TEST(Caustics, RoughGlassBlursItsCaustic) {
  Engine e;
  auto scene = load("sphere_plane");
  auto& ball = scene->objects.back();
  auto spread = [&](const io::ImageData& map) {
    double weighted = 0, flux = 0;
    test::for_each_floor_texel(*scene, map, [&](double r, const glm::dvec3& rgb) {
      const double mean = (rgb.x + rgb.y + rgb.z) / 3.0;
      weighted += r * mean;
      flux += mean;
    });
    return std::make_pair(weighted / flux, flux);
  };
  const std::vector<std::string> sets{"grid=1024", "fresnel=false"};
  reference::PhotonOptions options;
  options.photons = 4'000'000;
  options.fresnel = false;
  std::map<std::string, double> smooth_radius;
  const auto [reference_smooth, reference_smooth_flux] = spread(reference::trace_photon_reference(*scene, options).caustic_map);
  for (const char* graph : {"caustics_raytraced", "caustics_regular", "caustics_adaptive"}) {
    e.render(graph, scene, sets);
    smooth_radius[graph] = spread(e.executor.read_image("caustics")).first;
  }
  ball.material.transmission_roughness = 0.3f;
  const auto [reference_rough, reference_flux] = spread(reference::trace_photon_reference(*scene, options).caustic_map);
  std::printf("rough glass: reference mean radius %.4f smooth, %.4f rough; flux %.4f of the smooth\n", reference_smooth, reference_rough,
              reference_flux / reference_smooth_flux);
  EXPECT_GT(reference_rough, 1.1 * reference_smooth);
  for (const char* graph : {"caustics_raytraced", "caustics_regular", "caustics_adaptive"}) {
    e.render(graph, scene, sets);
    const auto [radius, flux] = spread(e.executor.read_image("caustics"));
    std::printf("rough glass %-20s mean radius %.4f smooth, %.4f rough; energy %.4f of the reference\n", graph, smooth_radius[graph],
                radius, flux / reference_flux);
    EXPECT_GT(radius - smooth_radius[graph], 0.5 * (reference_rough - reference_smooth)) << graph;
    if (std::string(graph) != "caustics_raytraced") continue;
    EXPECT_NEAR(radius, reference_rough, 0.02 * reference_rough);
    EXPECT_NEAR(flux / reference_flux, 1.0, 0.02);
  }
}

// Roughness is read per texel where the exact paths meet a surface: tests/data/gltf/rough_pane.gltf
// is a thin pane whose metallic-roughness texture makes its -x half smooth and its +x half fully
// rough. Light through the smooth half passes unbent and lands inside the pane's shadow on the
// floor (|x| < 1.07 from the light 4 above, the pane 1 above), so only the rough half spills light
// past it, most of it on its own side (some as far as past the smooth side: at roughness 1 the
// lobe is wide). In the photon reference and in the exact tracer the flux beyond x = 1.15 is more
// than twice that beyond x = -1.15 (3.3 times when this was written; one roughness for the whole
// pane would make them equal), and the exact tracer's flux on each side is the reference's within
// 8%. (The image-space methods take the object's mean roughness: docs/gltf.md.)
TEST(Caustics, RoughnessIsReadPerTexelOnTheExactPaths) {
  Engine e;
  const std::string file = (std::filesystem::path(CAUSTICA_SOURCE_DIR) / "tests/data/gltf/rough_pane.gltf").string();
  auto scene = std::make_shared<scene::Scene>(scene::load_model_scene(file, false));
  auto spill = [&](const io::ImageData& map) {
    glm::dvec2 outside(0.0);  // flux beyond x = -1.15 and beyond x = 1.15, within the shadow's depth
    test::for_each_floor_point(*scene, map, [&](const glm::dvec3& floor, const glm::dvec3& rgb) {
      if (std::abs(floor.z) > 0.9) return;
      const double flux = (rgb.x + rgb.y + rgb.z) / 3.0;
      if (floor.x < -1.15) outside.x += flux;
      if (floor.x > 1.15) outside.y += flux;
    });
    return outside;
  };
  reference::PhotonOptions options;
  options.photons = 4'000'000;
  const glm::dvec2 reference = spill(reference::trace_photon_reference(*scene, options).caustic_map);
  e.render("caustics_raytraced", scene, {"grid=2048"});
  const glm::dvec2 traced = spill(e.executor.read_image("caustics"));
  std::printf("rough pane: flux past the smooth side %.4g, past the rough side %.4g (reference %.4g, %.4g)\n", traced.x, traced.y,
              reference.x, reference.y);
  EXPECT_GT(reference.y, 2.0 * reference.x);
  EXPECT_GT(traced.y, 2.0 * traced.x);
  EXPECT_NEAR(traced.x, reference.x, 0.08 * reference.x);
  EXPECT_NEAR(traced.y, reference.y, 0.08 * reference.y);
}

// Dispersion (KHR_materials_dispersion) splits the light by colour band: the ball lens of
// dispersion 2 (Abbe number 10; n 1.485 red, 1.5 green, 1.535 blue), raised so that the floor lies
// beyond every band's focus. Blue, bent most, focuses first and has spread widest by the floor,
// red least: the flux-weighted distance from the axis orders blue > green > red, in the photon
// reference and in every method. The exact tracer has each band's distance within 1% of the
// reference's and its energy within 2%; the image-space maps lose the rim's photons (their exit
// estimate, as on a clear lens), which land farthest, so their distances are 6% short, but the
// bands lie as far apart as the reference's (blue minus red within 10%). The regular map and the
// hierarchical traversal trace the three bands of a photon in one pass, the adaptive one traverses
// once per band. Without dispersion the three channels are one.
TEST(Caustics, DispersionSeparatesTheBandsInOrder) {
  Engine e;
  auto scene = load("sphere_plane");
  auto& ball = scene->objects.back();
  for (auto& p : ball.mesh.positions) p.y += 1.5f;
  ball.bounds_min.y += 1.5f;
  ball.bounds_max.y += 1.5f;
  auto spread = [&](const io::ImageData& map) {
    glm::dvec3 weighted(0.0), flux(0.0);
    test::for_each_floor_texel(*scene, map, [&](double r, const glm::dvec3& rgb) {
      weighted += r * rgb;
      flux += rgb;
    });
    return std::make_pair(weighted / flux, flux);
  };
  const std::vector<std::string> sets{"grid=1024", "fresnel=false"};
  e.render("caustics_regular", scene, sets);
  const io::ImageData clear = e.executor.read_image("caustics");
  for (size_t i = 0; i < clear.rgba.size(); i += 4) {  // each channel is its own atomic sum: equal to float rounding
    ASSERT_NEAR(clear.rgba[i + 1], clear.rgba[i], 1e-5f * clear.rgba[i]);
    ASSERT_NEAR(clear.rgba[i + 2], clear.rgba[i], 1e-5f * clear.rgba[i]);
  }

  ball.material.dispersion = 2.0f;
  const glm::vec3 iors = ball.material.band_iors();
  EXPECT_NEAR(iors.x, 1.4849, 1e-4);
  EXPECT_NEAR(iors.y, 1.5, 1e-6);
  EXPECT_NEAR(iors.z, 1.5350, 1e-4);
  EXPECT_NEAR(iors.z - iors.x, 0.5 / 10.0, 1e-6);  // n_F - n_C = (n_d - 1) / V_d
  reference::PhotonOptions options;
  options.photons = 4'000'000;
  options.fresnel = false;
  const auto [reference_radius, reference_flux] = spread(reference::trace_photon_reference(*scene, options).caustic_map);
  std::printf("dispersion: reference mean radius per band %.4f %.4f %.4f\n", reference_radius.x, reference_radius.y, reference_radius.z);
  EXPECT_GT(reference_radius.z, 1.01 * reference_radius.y);
  EXPECT_GT(reference_radius.y, 1.01 * reference_radius.x);
  for (const char* graph : {"caustics_raytraced", "caustics_regular", "caustics_adaptive", "caustics_hierarchical"}) {
    auto frame = e.render(graph, scene, sets);
    const auto [radius, flux] = spread(e.executor.read_image("caustics"));
    const glm::dvec3 energy = flux / reference_flux;
    std::printf("dispersion %-20s mean radius per band %.4f %.4f %.4f, energy %.4f %.4f %.4f, %g batches\n", graph, radius.x, radius.y,
                radius.z, energy.x, energy.y, energy.z, frame.counters.at("photons.batches"));
    EXPECT_GT(radius.z, radius.y) << graph;
    EXPECT_GT(radius.y, radius.x) << graph;
    const std::string name = graph;
    // Image space traces the three bands in one pass over the grid; the exact tracer dispatches each
    // (the adaptive traversal's batches depend on its photon memory).
    if (name != "caustics_adaptive") {
      EXPECT_EQ(frame.counters.at("photons.batches"), name == "caustics_raytraced" ? 3.0 : 1.0) << graph;
    }
    const double separation = radius.z - radius.x, reference_separation = reference_radius.z - reference_radius.x;
    EXPECT_NEAR(separation, reference_separation, 0.1 * reference_separation) << graph;
    if (name != "caustics_raytraced") continue;
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(radius[c], reference_radius[c], 0.01 * reference_radius[c]) << graph << " band " << c;
      EXPECT_NEAR(energy[c], 1.0, 0.02) << graph << " band " << c;
    }
  }
}

// The interface layers are read per texel where the exact paths meet a surface, and in image space
// where the light's refractor buffers hold them (the front_layers port):
// tests/data/gltf/layered_pane.gltf is a smooth thin pane whose layer textures give its -x half a
// specular colour that reflects red whole and green not at all (under a coat and a film), and its
// +x half nothing that reflects. The floor under the -x half gets no red and under the +x half
// white light; the textures' means would light both halves alike (half the red). Checked in the
// photon reference, the exact tracer and image space (caustics_regular: through a thin wall image
// space sees the exact path), each one's green and blue, and the +x half's red, within 5% of the
// reference's.
// So is a clear coat's own normal map: tests/data/gltf/coat_normal_glass.gltf is the pane under a
// full, smooth coat whose normal map tilts the coat's normal 70 degrees towards -x over the -x half
// and leaves the +x half's as the surface's. The light above the pane's centre meets the -x half's
// coat at grazing angles, where the coat's Schlick term reflects a fifth to two thirds of it: the
// floor under the -x half gets less than under the +x half (the coat following the surface's normal
// would light both halves alike), in the photon reference and in the exact tracer, each half's flux
// within 5% of the reference's. (One test, so that one process compiles the exact kernel that reads
// the layers' textures: two run side by side compiled it twice.)
TEST(Caustics, InterfaceLayersAreReadPerTexel) {
  Engine e;
  {
    const auto [reference, traced, image_space] = pane_halves(e, "layered_pane.gltf", true);
    for (const auto& [what, flux] :
         {std::make_pair("reference", reference), std::make_pair("exact tracer", traced), std::make_pair("image space", image_space)}) {
      std::printf("layered pane, %-12s: -x half %.4g %.4g %.4g, +x half %.4g %.4g %.4g\n", what, flux[0].x, flux[0].y, flux[0].z, flux[1].x,
                  flux[1].y, flux[1].z);
      EXPECT_LT(flux[0].x, 0.02 * flux[0].y) << what << ": red passes the -x half";
      EXPECT_GT(flux[1].x, 0.95 * flux[1].y) << what << ": the +x half reflects red";
      for (int half = 0; half < 2; ++half) {
        for (int c = half == 0 ? 1 : 0; c < 3; ++c)
          EXPECT_NEAR(flux[half][c], reference[half][c], 0.05 * reference[half][c]) << what << half << c;
      }
    }
  }
  const auto [reference, traced, image_space] = pane_halves(e, "coat_normal_glass.gltf", true);
  for (const auto& [what, flux] :
       {std::make_pair("reference", reference), std::make_pair("exact tracer", traced), std::make_pair("image space", image_space)}) {
    std::printf("coat normal map, %-12s: -x half %.4g, +x half %.4g\n", what, flux[0].y, flux[1].y);
    EXPECT_LT(flux[0].y, 0.85 * flux[1].y) << what << ": the tilted coat reflects no more than the flat one";
    for (int half = 0; half < 2; ++half) EXPECT_NEAR(flux[half].y, reference[half].y, 0.05 * reference[half].y) << what << half;
  }
}
