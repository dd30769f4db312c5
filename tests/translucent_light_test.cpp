// The light a translucent surface passes on to what lies behind it (reference/translucent_light.h):
// a known answer worked by hand, the shadows on either side of the leaf, and the side rule.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "core/paths.h"
#include "io/json_document.h"
#include "reference/exact_scene.h"
#include "reference/refraction_reference.h"
#include "reference/translucent_light.h"

using namespace caustica;

namespace {

constexpr float kE0 = 2.0f;  // the directional light's irradiance on the leaf (W/m^2)

// scenes/materials/translucent_leaf.gltf's material: (1 - 0) 0.7 (0.7, 1, 0.2) of its irradiance
// passes to the far side.
void make_translucent(scene::Material& m) {
  m.albedo = {0.2f, 0.45f, 0.1f};
  m.metallic_roughness = true;
  m.metallic = 0.0f;
  m.roughness = 0.8f;
  m.diffuse_transmission = 0.7f;
  m.diffuse_transmission_color = {0.7f, 1.0f, 0.2f};
}

// A 2 x 2 leaf (object 1) 1 above a 40 x 40 floor (object 0), centred over the origin, its normal
// +y (or -y: turned upside down), lit by a directional light of irradiance kE0 straight down, the
// camera looking at the origin from under the leaf's edge; `extra` adds objects (blockers) to the
// scene file's list.
scene::Scene leaf_over_floor(bool normal_up, const std::string& extra = "") {
  scene::Scene s =
      scene::load_scene(JsonDocument::parse(R"({
    "camera": {"position": [0, 0.5, 4], "target": [0, 0, 0]},
    "lights": [{"type": "directional", "position": [0, 10, 0], "target": [0, 0, 0], "intensity": 2}],
    "objects": [{"name": "floor", "primitive": {"type": "plane", "size": [40, 40]}},
                {"name": "leaf", "primitive": {"type": "plane", "size": [2, 2]}, "transform": {"translate": [0, 1, 0])" +
                                                std::string(normal_up ? "" : R"(, "rotate": [180, 0, 0])") + "}}" + extra + "]}",
                                            "leaf_over_floor.json"));
  make_translucent(s.objects.at(1).material);
  EXPECT_EQ(s.lights.at(0).intensity, kE0);
  return s;
}

// E_t at p, with the random numbers of stream `stream` of `key` (the reference picture's pixel
// `key`: its index in the image, stream 0).
glm::vec3 gathered(const scene::Scene& s, glm::vec3 p, glm::vec3 n, uint32_t receiver, uint64_t key = 0, uint64_t stream = 1) {
  const reference::ExactScene exact(s);
  const reference::TranslucentLight light(exact);
  reference::Random random(key, stream);
  return light.irradiance(p, n, receiver, random);
}

// E_t's green at floor point p (facing up, on object 0) over 64 estimates of 256 samples each, each
// with its own random numbers: their mean, and one estimate's standard deviation.
struct Estimates {
  double mean, deviation;
  glm::vec3 first;  // the first estimate, every channel
};
Estimates estimate_green(const scene::Scene& s, glm::vec3 p) {
  const reference::ExactScene exact(s);
  const reference::TranslucentLight light(exact);
  constexpr int kEstimates = 64;
  double sum = 0, sum2 = 0;
  glm::vec3 first(0.0f);
  for (int key = 0; key < kEstimates; ++key) {
    reference::Random random(uint64_t(key), 1);
    const glm::vec3 e = light.irradiance(p, glm::vec3(0, 1, 0), 0, random);
    if (key == 0) first = e;
    sum += double(e.g);
    sum2 += double(e.g) * double(e.g);
  }
  const double mean = sum / kEstimates;
  return {mean, std::sqrt(std::max(0.0, sum2 / kEstimates - mean * mean)), first};
}

// The view factor from a point to an a x b rectangle parallel to its surface, at distance c, the
// point under one of its corners (the standard closed form).
double corner_view_factor(double a, double b, double c) {
  const double x = a / c, y = b / c, sx = std::sqrt(1 + x * x), sy = std::sqrt(1 + y * y);
  return (x / sx * std::atan(y / sx) + y / sy * std::atan(x / sy)) / (2 * M_PI);
}

}  // namespace

// The floor point under the leaf's centre gathers E_t = (1 - m) d c E0 F, F the view factor of the
// leaf from it: four 1 x 1 quarters at distance 1, X = Y = 1, sqrt(1 + X^2) = 1.414214, each
//   F_q = [X/sqrt(1+X^2) atan(Y/sqrt(1+X^2)) + Y/sqrt(1+Y^2) atan(X/sqrt(1+Y^2))] / (2 pi)
//       = 2 x 0.707107 x atan(0.707107) / (2 pi) = 2 x 0.707107 x 0.615480 / 6.283185
//       = 0.870420 / 6.283185 = 0.138532,
// F = 4 x 0.138532 = 0.554126, and E_t = 0.7 x (0.7, 1, 0.2) x 2 x 0.554126 = (0.54304, 0.77578, 0.15516),
// whichever way the leaf's normal faces (the light reaches its far side from either).
// The noise: 64 estimates of 256 samples each (their own random numbers) measure the deviation of
// one estimate (2.5%; 2.2% over 4096 estimates, whose mean was 0.77578); their mean, whose
// deviation is an eighth of it (0.3%), must lie within 4 of its deviations of the answer (a chance
// of 6e-5 of failing were the estimator unbiased; the epsilon offsets bias it far less), and one
// estimate's deviation must stay under 4% (the noise translucent_light.h states).
TEST(TranslucentLight, TheFloorUnderALeafGathersItsViewFactorOfTheTransmittedLight) {
  const double quarter = corner_view_factor(1, 1, 1);
  EXPECT_NEAR(quarter, 0.138532, 1e-6);
  const double expected = 0.7 * 1.0 * double(kE0) * 4 * quarter;  // green
  EXPECT_NEAR(expected, 0.77578, 1e-5);
  for (bool normal_up : {true, false}) {
    const auto [mean, deviation, first] = estimate_green(leaf_over_floor(normal_up), glm::vec3(0.0f));
    std::printf("normal %s: E_t green %.5f (exact %.5f), one estimate's relative deviation %.4f\n", normal_up ? "+y" : "-y", mean, expected,
                deviation / mean);
    EXPECT_NEAR(mean, expected, 4 * deviation / 8);
    EXPECT_LT(deviation / expected, 0.04);
    // The colour is the transmission colour's: red and blue in its proportions, sample by sample.
    EXPECT_NEAR(first.r / first.g, 0.7f, 1e-5f);
    EXPECT_NEAR(first.b / first.g, 0.2f, 1e-5f);
  }
}

// What a leaf passes is its texels' (tests/data/surfaces/half_leaf_over_floor.json: the same leaf
// at the same height, under a directional light of 3 W/m^2, its diffuseTransmissionTexture passing
// light through the -x half only): E_t = 0.7 x 1 x 3 x F (green) with F the view factor of the -x
// half, [-1, 0] x [-1, 1], from the floor point. Under the -x half's middle (x = -0.5) it is four
// 0.5 x 1 corner rectangles at distance 1, X = 0.5, Y = 1, sqrt(1 + X^2) = 1.118034:
//   F_c(0.5, 1) = [0.447214 atan(0.894427) + 0.707107 atan(0.353553)] / (2 pi)
//               = [0.447214 x 0.729728 + 0.707107 x 0.339837] / 6.283185 = 0.566647 / 6.283185 = 0.090184,
// F = 0.360737, E_t = 0.757548. Under the +x half's middle (x = 0.5) the -x half is the 1.5 wide
// rectangle less the 0.5 wide one on either side of the point, sqrt(1 + 1.5^2) = 1.802776:
//   F_c(1.5, 1) = [0.832050 atan(0.554700) + 0.707107 atan(1.060660)] / (2 pi)
//               = [0.832050 x 0.506445 + 0.707107 x 0.814827] / 6.283185 = 0.997557 / 6.283185 = 0.158766,
// F = 2 x (0.158766 - 0.090184) = 0.137164, E_t = 0.288044. The texture's mean (half the factor)
// would give both points 0.35 x 3 x (0.360737 + 0.137164) = 0.522796. Each within 4 deviations of
// the mean of 64 estimates, as above.
TEST(TranslucentLight, WhatALeafPassesIsItsTexelsAtEachPoint) {
  EXPECT_NEAR(4 * corner_view_factor(0.5, 1, 1), 0.360737, 1e-6);
  EXPECT_NEAR(2 * (corner_view_factor(1.5, 1, 1) - corner_view_factor(0.5, 1, 1)), 0.137164, 1e-6);
  const scene::Scene s = scene::load_scene_file((data_dir() / "tests/data/surfaces/half_leaf_over_floor.json").string());
  ASSERT_EQ(s.objects.front().name, "floor");
  ASSERT_TRUE(s.objects.back().material.surface_textures.diffuse_transmission.used());
  for (const auto& [x, expected] : {std::pair{-0.5f, 0.757548}, std::pair{0.5f, 0.288044}}) {
    const auto [mean, deviation, first] = estimate_green(s, glm::vec3(x, 0.0f, 0.0f));
    std::printf("under x = %+.1f: E_t green %.5f (exact %.5f), one estimate's relative deviation %.4f\n", double(x), mean, expected,
                deviation / mean);
    EXPECT_NEAR(mean, expected, 4 * deviation / 8) << x;
  }
}

// An opaque slab between the leaf and the floor point hides the whole leaf from it; one between the
// light and the leaf leaves the leaf unlit: either way the point gathers nothing.
TEST(TranslucentLight, ABlockerOnEitherSideOfTheLeafLeavesNoLight) {
  const glm::vec3 p(0.0f), up(0, 1, 0);
  EXPECT_GT(gathered(leaf_over_floor(true), p, up, 0).g, 0.5f);  // the same point, unblocked
  const auto slab = [](float height) {
    return R"(, {"name": "slab", "primitive": {"type": "box", "size": [3, 0.1, 3]}, "transform": {"translate": [0, )" +
           std::to_string(height) + ", 0]}}";
  };
  EXPECT_EQ(gathered(leaf_over_floor(true, slab(0.5f)), p, up, 0), glm::vec3(0.0f)) << "between the leaf and the floor";
  EXPECT_EQ(gathered(leaf_over_floor(true, slab(2.0f)), p, up, 0), glm::vec3(0.0f)) << "between the light and the leaf";
}

// tests/data/surfaces/translucent_leaf.json: the glTF leaf, moved to stand 1.5 up in the xy plane,
// lit from -z. The floor in front of it (+z) gathers its light; the floor behind it, on the light's
// side, sees only its lit face and gathers nothing (at x = 0.5, z = -0.5, clear of the checker
// tiles, whose tops would hide the leaf from a point under them); so does a point above the
// horizontal leaf of the first test, facing it from the light's side (without the rule it would
// gather what the floor below does). A scene without a translucent surface gathers nothing and
// draws no random numbers.
TEST(TranslucentLight, OnlyTheFarSideFromTheLightPassesItOn) {
  const scene::Scene s = scene::load_scene_file((data_dir() / "tests/data/surfaces/translucent_leaf.json").string());
  ASSERT_EQ(s.objects.front().name, "floor");
  ASSERT_GT(s.objects.back().material.diffuse_transmission, 0.0f);
  const glm::vec3 up(0, 1, 0);
  const glm::vec3 front = gathered(s, glm::vec3(0, 0, 1), up, 0), behind = gathered(s, glm::vec3(0.5f, 0, -0.5f), up, 0);
  std::printf("in front of the leaf %.5f, behind it %.5f\n", double(front.g), double(behind.g));
  EXPECT_GT(front.g, 0.01f);
  EXPECT_EQ(behind, glm::vec3(0.0f));
  for (bool normal_up : {true, false}) {
    EXPECT_EQ(gathered(leaf_over_floor(normal_up), glm::vec3(0, 2, 0), -up, 0), glm::vec3(0.0f))
        << "above the leaf, normal up " << normal_up;
  }

  scene::Scene opaque = s;
  opaque.objects.back().material.diffuse_transmission = 0.0f;
  const reference::ExactScene exact(opaque);
  const reference::TranslucentLight light(exact);
  EXPECT_TRUE(light.empty());
  reference::Random random(7, 1), untouched(7, 1);
  EXPECT_EQ(light.irradiance(glm::vec3(0, 0, 1), up, 0, random), glm::vec3(0.0f));
  EXPECT_EQ(random.uniform(), untouched.uniform());
}

// The reference picture: the floor pixel under the leaf's centre (the middle of a 33 x 33 picture)
// is brighter by the floor's diffuse reflectance over pi times the E_t that pixel's random numbers
// give, and only by that: the light is wired into the camera's shading with the pixel's numbers.
// A MASK leaf whose coverage is under its cutoff everywhere is not there: it passes nothing.
TEST(TranslucentLight, TheReferencePictureLightsTheFloorUnderTheLeafWithIt) {
  const scene::Scene s = leaf_over_floor(true);
  scene::Scene opaque = s;
  opaque.objects.at(1).material.diffuse_transmission = 0.0f;
  constexpr uint32_t kSize = 33, kMiddle = kSize / 2;
  const auto lit = reference::render_refraction_reference(s, kSize, kSize).radiance;
  const auto shadowed = reference::render_refraction_reference(opaque, kSize, kSize).radiance;
  const glm::vec3 e = gathered(s, glm::vec3(0.0f), glm::vec3(0, 1, 0), 0, uint64_t{kMiddle} * kSize + kMiddle, 0);
  const glm::vec3 floor_diffuse = s.objects.at(0).material.albedo / glm::pi<float>();
  for (int c = 0; c < 3; ++c) {
    const size_t i = (size_t{kMiddle} * kSize + kMiddle) * 4 + size_t(c);
    EXPECT_NEAR(lit.rgba[i] - shadowed.rgba[i], floor_diffuse[c] * e[c], 1e-3f * floor_diffuse[c] * e[c]) << "channel " << c;
  }

  scene::Scene cut_out = s;
  cut_out.objects.at(1).material.alpha_mode = scene::AlphaMode::mask;
  cut_out.objects.at(1).material.alpha = 0.3f;
  EXPECT_EQ(gathered(cut_out, glm::vec3(0.0f), glm::vec3(0, 1, 0), 0), glm::vec3(0.0f));
}
