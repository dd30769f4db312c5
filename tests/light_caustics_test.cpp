// Every light throws its caustic (per-light caustic passes in the bundled graphs, graph/per_light.h):
// a point light through a view fitted to its refractors, with the flux the ball subtends from it and
// the photon reference's map; and on a scene of three lights each light's caustic map is the one it
// throws alone, which lighting adds as it adds their direct light; and the render of the three is
// near the whole reference picture (caustica reference --picture).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "graph/per_light.h"
#include "reference/image_metrics.h"
#include "reference/photon_reference.h"
#include "reference/refraction_reference.h"
#include "scene/scene.h"
#include "scene_engine.h"

using namespace caustica;

namespace {

constexpr const char* kSmallMaps[] = {"grid=512", "light_size=256", "shadow_size=256", "caustic_size=128"};

std::vector<std::string> small_maps() {
  return {std::begin(kSmallMaps), std::end(kSmallMaps)};
}

// The scene with only light `light` of the three (index 0 in it), or with light 0 dark.
std::shared_ptr<const scene::Scene> with_light(const scene::Scene& all, size_t light, bool dark = false) {
  auto one = std::make_shared<scene::Scene>(all);
  one->lights = {all.lights.at(light)};
  if (dark) one->lights.front().intensity = 0.0f;
  return one;
}

// Each caustic view's photon reference map with Fresnel off, `photons` shared among the views by
// their flux (empty where a view's share rounds to none).
std::vector<io::ImageData> reference_maps(const scene::Scene& scene, uint64_t photons, uint32_t map_size) {
  const std::vector<uint64_t> shares = reference::photons_per_view(scene, photons);
  std::vector<io::ImageData> maps(shares.size());
  for (uint32_t view = 0; view < shares.size(); ++view) {
    if (shares[view] == 0) continue;
    reference::PhotonOptions options;
    options.light = view;
    options.photons = shares[view];
    options.fresnel = false;
    options.map_size = map_size;
    maps[view] = reference::trace_photon_reference(scene, options).caustic_map;
  }
  return maps;
}

}  // namespace

// tests/data/point_light.json: a point light of 40 W/sr 4.5 above the centre of a glass ball of
// radius 1. The ball subtends the cone of half angle asin(1 / 4.5), whose solid angle is
// 2 pi (1 - sqrt(1 - 1 / 4.5^2)) = 0.157105 sr: 6.2842 W enter it. Its photons all land (the floor
// is wide) or are counted dropped, and the ray-query map matches the photon reference's.
TEST(LightCaustics, APointLightThrowsTheFluxItsBallSubtends) {
  test::SceneEngine e;
  auto scene =
      std::make_shared<const scene::Scene>(scene::load_scene_file(std::string(CAUSTICA_SOURCE_DIR) + "/tests/data/point_light.json"));
  ASSERT_TRUE(scene->lights.front().has_caustic_view);
  const double expected = 40.0 * 2.0 * 3.14159265358979 * (1.0 - std::sqrt(1.0 - 1.0 / (4.5 * 4.5)));
  const graph::FrameResult frame = e.render("caustics_regular", scene, {"fresnel=false", "grid=1024"}, {});
  const double in = frame.counters.at("caustic.flux_entering"), splatted = frame.counters.at("caustic.flux"),
               dropped = frame.counters.at("caustic.flux_dropped");
  std::printf("point light: entering %.4f (expected %.4f), splatted %.4f, dropped %.4f\n", in, expected, splatted, dropped);
  EXPECT_NEAR(in, expected, 0.015 * expected);
  EXPECT_NEAR(splatted + dropped, in, 1e-3 * in);

  reference::PhotonOptions options;
  options.photons = 8'000'000;
  options.fresnel = false;
  const auto reference = reference::trace_photon_reference(*scene, options);
  e.render("caustics_raytraced", scene, {"fresnel=false", "grid=1024"}, {"caustics"});
  const auto exact = reference::compare_images(e.executor.read_image("caustics"), reference.caustic_map, 1.5);
  std::printf("point light: ray-query map against the reference: energy %.4f, relative L1 %.4f\n", exact.energy_ratio, exact.relative_l1);
  EXPECT_NEAR(exact.energy_ratio, 1.0, 0.03);
  EXPECT_LT(exact.relative_l1, 0.15);
}

// scenes/three_lights.json: two spots and a point light, each over its own ball. In one render each
// light's caustic map (caustics#K) is the map that light throws alone; were every instance to
// follow light 0, or the point light to throw nothing, the maps would differ. And lighting adds
// the lights' caustics as it adds their direct light: the picture under three lights is the sum of
// the pictures under each, less the ambient light counted twice over.
TEST(LightCaustics, EachLightThrowsItsOwnCausticAndLightingAddsThem) {
  test::SceneEngine e;
  e.width = 160;
  e.height = 90;
  const auto scene = test::load_bundled_scene("three_lights");
  ASSERT_EQ(scene->lights.size(), 3u);
  std::set<std::string> maps{"lit"};
  for (uint32_t light = 0; light < 3; ++light) maps.insert(graph::light_instance("caustics", light));
  e.render("caustics_regular", scene, small_maps(), maps);
  std::vector<io::ImageData> thrown;
  for (uint32_t light = 0; light < 3; ++light) thrown.push_back(e.executor.read_image(graph::light_instance("caustics", light)));
  const io::ImageData all = e.executor.read_image("lit");

  std::vector<double> sum(all.rgba.size(), 0.0);
  for (uint32_t light = 0; light < 3; ++light) {
    e.render("caustics_regular", with_light(*scene, light), small_maps(), {"caustics", "lit"});
    const io::ImageData alone = e.executor.read_image("caustics");
    std::printf("light %u: caustic flux %.4f, alone %.4f\n", light, test::map_flux(thrown[light]), test::map_flux(alone));
    EXPECT_GT(test::map_flux(alone), 0.0) << "light " << light << " throws no caustic";
    EXPECT_LT(test::relative_difference(thrown[light], alone), 1e-4) << "light " << light;
    const io::ImageData lit = e.executor.read_image("lit");
    for (size_t i = 0; i < sum.size(); ++i) sum[i] += double(lit.rgba[i]);
  }
  e.render("caustics_regular", with_light(*scene, 0, true), small_maps(), {"lit"});
  const io::ImageData ambient = e.executor.read_image("lit");
  double difference = 0, total = 0;
  for (size_t i = 0; i < sum.size(); ++i) {
    if (i % 4 == 3) continue;
    difference += std::abs(sum[i] - 2.0 * double(ambient.rgba[i]) - double(all.rgba[i]));
    total += std::abs(double(all.rgba[i]));
  }
  std::printf("three lights against the sum of each alone: relative L1 %.5f\n", difference / total);
  EXPECT_LT(difference / total, 3e-3);
}

// The ground truth of a multi-light render (caustica reference --picture): every light's photon map,
// the photons shared by flux, lighting the ray-traced picture. The exact graph on three_lights is
// compared with it over the whole linear picture (image-space refraction through the balls, shadow
// maps against shadow rays, the maps' resolution: what remains). Against a picture with light 0's
// caustic alone (what the reference made before) it is measurably further off: the other two
// lights' caustics are in both the render and the reference.
TEST(LightCaustics, AThreeLightRenderIsNearTheWholeReferencePicture) {
  test::SceneEngine e;
  e.width = 160;
  e.height = 90;
  const auto scene = test::load_bundled_scene("three_lights");
  e.render("caustics_raytraced", scene, {"grid=1024", "caustic_size=256"}, {"refracted"});
  const io::ImageData render = e.executor.read_image("refracted");

  const std::vector<uint64_t> shares = reference::photons_per_view(*scene, 4'000'000);
  std::vector<io::ImageData> maps(scene->lights.size());
  reference::CausticMaps lit(scene->lights.size(), nullptr);
  for (uint32_t light = 0; light < scene->lights.size(); ++light) {
    reference::PhotonOptions options;
    options.light = light;
    options.photons = shares[light];
    options.map_size = 256;
    maps[light] = reference::trace_photon_reference(*scene, options).caustic_map;
    lit[light] = &maps[light];
  }
  auto relative_l1 = [&](const reference::CausticMaps& with) {
    const io::ImageData picture = reference::render_refraction_reference(*scene, e.width, e.height, with).radiance;
    double difference = 0, total = 0;
    for (size_t i = 0; i < picture.rgba.size(); ++i) {
      if (i % 4 == 3) continue;
      difference += std::abs(double(render.rgba[i]) - double(picture.rgba[i]));
      total += std::abs(double(picture.rgba[i]));
    }
    return difference / total;
  };
  const double whole = relative_l1(lit), first_only = relative_l1({lit[0]});
  std::printf("three lights against the whole reference picture: relative L1 %.4f (against light 0's caustic alone %.4f)\n", whole,
              first_only);
  EXPECT_LT(whole, 0.05);
  EXPECT_GT(first_only, 1.2 * whole);
}

// tests/data/point_light_inside.json: a point light of 40 W/sr at the centre of a glass ball of
// radius 1, 1.5 over a 10 x 10 floor. Every ray from it meets the glass square on and leaves
// unbent, so with Fresnel off the glass changes nothing: the floor receives what the light sends
// into its solid angle, 4 atan(a b / (h sqrt(h^2 + a^2 + b^2))) = 4.6489 sr (a = b = 5, h = 1.5),
// 185.96 W, all of it through the caustics of the six cube faces (the glass casts the shadow), and
// the floor in front of the ball looks as it does without the ball. Each face's map holds the flux
// the photon reference's does, whose photons start in the glass as the engine's.
TEST(LightCaustics, APointLightInsideAGlassBallLightsTheFloorAsIfItWereNotThere) {
  test::SceneEngine e;
  e.width = 160;
  e.height = 90;
  auto scene = std::make_shared<const scene::Scene>(
      scene::load_scene_file(std::string(CAUSTICA_SOURCE_DIR) + "/tests/data/point_light_inside.json"));
  const std::vector<scene::CausticView> views = scene::caustic_views(scene->lights);
  ASSERT_EQ(views.size(), 6u);
  const std::vector<std::string> settings{"fresnel=false", "grid=512", "light_size=256", "shadow_size=256", "caustic_size=256"};
  std::set<std::string> kept{"lit"};
  for (uint32_t view = 0; view < 6; ++view) kept.insert(graph::light_instance("caustics", view));
  e.render("caustics_raytraced", scene, settings, kept);
  double flux = 0;
  std::vector<io::ImageData> maps;
  for (uint32_t view = 0; view < 6; ++view) {
    maps.push_back(e.executor.read_image(graph::light_instance("caustics", view)));
    flux += test::map_flux(maps.back());
  }
  const double expected = 40.0 * 4.0 * std::atan(25.0 / (1.5 * std::sqrt(1.5 * 1.5 + 50.0)));
  std::printf("point light inside a ball: caustic flux on the floor %.3f (expected %.3f)\n", flux, expected);
  EXPECT_NEAR(flux, expected, 0.02 * expected);
  const io::ImageData lit = e.executor.read_image("lit");

  auto bare = std::make_shared<scene::Scene>(*scene);
  bare->objects.resize(1);  // the floor alone
  e.render("caustics_raytraced", bare, settings, {"lit"});
  const io::ImageData unblocked = e.executor.read_image("lit");
  double difference = 0, total = 0;
  for (uint32_t y = e.height * 4 / 5; y < e.height; ++y) {  // the floor in front of the ball
    for (uint32_t x = 0; x < e.width; ++x) {
      for (uint32_t c = 0; c < 3; ++c) {
        const size_t i = (size_t{y} * e.width + x) * 4 + c;
        difference += std::abs(double(lit.rgba[i]) - double(unblocked.rgba[i]));
        total += double(unblocked.rgba[i]);
      }
    }
  }
  std::printf("point light inside a ball: the floor in front against no ball, relative L1 %.4f\n", difference / total);
  EXPECT_LT(difference / total, 0.08);

  const std::vector<io::ImageData> references = reference_maps(*scene, 3'000'000, 256);
  for (uint32_t view = 0; view < 6; ++view) {
    const io::ImageData& map = references[view];
    const double ratio = test::map_flux(maps[view]) / std::max(test::map_flux(map), 1e-12);
    std::printf("face %d: engine %.3f, reference %.3f\n", views[view].face, test::map_flux(maps[view]), test::map_flux(map));
    if (test::map_flux(map) > 0.01 * expected) {
      EXPECT_NEAR(ratio, 1.0, 0.03) << "face " << views[view].face;
    }
  }
}

// The same ball with the bulb 0.6 above its centre: rays now meet the glass obliquely and leave it
// bent away from the normal (from n = 1.5 into air). The exact graph's photons (the device's path
// tracer, started in the glass), the image-space photons (the nearest back face the light sees,
// one refraction out: separate code) and the photon reference's (Embree on the host) land alike,
// face by face; had a side started its photons in air, they would bend towards the normal at the
// glass instead and land elsewhere. Image space misjudges some photons that leave near the horizon
// (the receiver depth marched at grazing angles): its side faces keep 4-5% more than the others.
TEST(LightCaustics, ABulbOffTheBallsCentreLeavesTheGlassAsTheReferenceDoes) {
  test::SceneEngine e;
  e.width = 64;
  e.height = 36;
  auto scene =
      std::make_shared<scene::Scene>(scene::load_scene_file(std::string(CAUSTICA_SOURCE_DIR) + "/tests/data/point_light_inside.json"));
  scene->lights.front().view.position.y += 0.6f;
  scene::fit_caustic_view(scene->lights.front(), *scene);
  ASSERT_EQ(scene->lights.front().inside, 1);
  const std::vector<scene::CausticView> views = scene::caustic_views(scene->lights);
  ASSERT_EQ(views.size(), 6u);
  std::set<std::string> kept;
  for (uint32_t view = 0; view < 6; ++view) kept.insert(graph::light_instance("caustics", view));
  const std::vector<std::string> settings{"fresnel=false", "grid=1024", "light_size=512", "caustic_size=128"};
  std::vector<io::ImageData> exact, image_space;
  e.render("caustics_raytraced", scene, settings, kept);
  for (uint32_t view = 0; view < 6; ++view) exact.push_back(e.executor.read_image(graph::light_instance("caustics", view)));
  e.render("caustics_regular", scene, settings, kept);
  for (uint32_t view = 0; view < 6; ++view) image_space.push_back(e.executor.read_image(graph::light_instance("caustics", view)));
  const std::vector<io::ImageData> references = reference_maps(*scene, 4'000'000, 128);
  for (uint32_t view = 0; view < 6; ++view) {
    const io::ImageData& reference_map = references[view];
    if (test::map_flux(reference_map) < 1.0) continue;  // the +y face's photons leave upwards
    const auto by_path = reference::compare_images(exact[view], reference_map, 1.5);
    const auto by_image = reference::compare_images(image_space[view], reference_map, 1.5);
    std::printf("bulb off centre, face %d: exact energy %.4f, relative L1 %.4f; image space %.4f, %.4f\n", views[view].face,
                by_path.energy_ratio, by_path.relative_l1, by_image.energy_ratio, by_image.relative_l1);
    EXPECT_NEAR(by_path.energy_ratio, 1.0, 0.01) << "face " << views[view].face;
    EXPECT_LT(by_path.relative_l1, 0.03) << "face " << views[view].face;
    EXPECT_NEAR(by_image.energy_ratio, 1.0, 0.06) << "face " << views[view].face;
    EXPECT_LT(by_image.relative_l1, 0.08) << "face " << views[view].face;
  }
}
