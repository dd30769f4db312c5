// The reference tracers' model of a refractor's interface with glTF's material layers
// (engine/reference/interface_physics.h) against values worked by hand from the model's formulas:
// KHR_materials_specular's scaled curve, KHR_materials_clearcoat's coat, KHR_materials_iridescence's
// thin film (the Airy sum), and facts of physics any lossless stack obeys.
#include <gtest/gtest.h>

#include <cmath>
#include <utility>

#include "reference/interface_physics.h"

using namespace caustica;
using reference::fresnel_dielectric;
using reference::interface_reflectance;

namespace {

constexpr float kTolerance = 2e-6f;

// A material with only the given layers on a plain dielectric.
scene::Material plain() {
  return scene::Material{};
}
scene::Material with_film(float thickness_nm, float iridescence = 1.0f, float film_ior = 1.3f) {
  scene::Material m;
  m.iridescence = iridescence;
  m.film_ior = film_ior;
  m.film_thickness_nm = thickness_nm;
  return m;
}

// The reflectance of a smooth surface, whose facet normal is its geometric normal: cos_outside is
// the incident cosine from the air, the refracted one from inside.
glm::vec3 smooth_reflectance(const scene::Material& m, float cos_i, float eta_i, float eta_t) {
  const float cos_outside = eta_i == 1.0f ? cos_i : reference::snell_cos(cos_i, eta_i, eta_t);
  return interface_reflectance(m, cos_i, cos_outside, eta_i, eta_t).reflectance;
}

void expect_channels(glm::vec3 got, glm::vec3 want, float tolerance = kTolerance) {
  EXPECT_NEAR(got.r, want.r, tolerance);
  EXPECT_NEAR(got.g, want.g, tolerance);
  EXPECT_NEAR(got.b, want.b, tolerance);
}

// The film's interfaces at normal incidence, air | 1.3 | glass 1.5:
// r12 = (1 - 1.3) / (1 + 1.3) = -0.3 / 2.3 = -0.130435, r23 = (1.3 - 1.5) / (1.3 + 1.5) = -0.2 / 2.8 = -0.071429,
// r12 r23 = 0.009317, r12^2 = 0.017013, r23^2 = 0.005102.
// Quarter-wave in green (delta = pi, cos delta = -1): d = 587.56 / (4 * 1.3) = 112.992 nm,
// R = ((r12 - r23) / (1 - r12 r23))^2 = (-0.059006 / 0.990683)^2 = (-0.059561)^2 = 0.003548.
constexpr float kQuarterWaveGreenNm = 587.56f / (4.0f * 1.3f);
constexpr float kQuarterWaveGreenR = 0.0035475f;

}  // namespace

TEST(InterfacePhysics, TheDefaultMaterialIsTheBareDielectric) {
  // n = 1.5 at normal incidence: ((1.5 - 1) / (1.5 + 1))^2 = 0.2^2 = 0.04.
  expect_channels(smooth_reflectance(plain(), 1.0f, 1.0f, 1.5f), glm::vec3(0.04f));
  // 45 degrees air -> 1.5: sin_t = 0.707107 / 1.5 = 0.471405, cos_t = 0.881917;
  // rs = (0.707107 - 1.5 * 0.881917) / (0.707107 + 1.322876) = -0.303337,
  // rp = (1.5 * 0.707107 - 0.881917) / (1.060660 + 0.881917) = 0.092013,
  // F = (0.092013 + 0.008466) / 2 = 0.050240.
  expect_channels(smooth_reflectance(plain(), std::sqrt(0.5f), 1.0f, 1.5f), glm::vec3(0.050240f));
  for (float cos_i : {1.0f, 0.95f, 0.8f, 0.6f, 0.4f, 0.2f, 0.05f}) {
    const float into = fresnel_dielectric(cos_i, 1.0f, 1.5f);
    expect_channels(smooth_reflectance(plain(), cos_i, 1.0f, 1.5f), glm::vec3(into));
    const float out = fresnel_dielectric(cos_i, 1.5f, 1.0f);  // 1 past the critical angle
    expect_channels(smooth_reflectance(plain(), cos_i, 1.5f, 1.0f), glm::vec3(out));
    EXPECT_EQ(interface_reflectance(plain(), cos_i, 1.0f, 1.0f, 1.5f).coat, 0.0f);
  }
  // Glass -> air at 60 degrees: 1.5 sin 60 = 1.299 > 1, total internal reflection.
  const auto tir = interface_reflectance(plain(), 0.5f, 0.0f, 1.5f, 1.0f);
  expect_channels(tir.reflectance, glm::vec3(1.0f), 0.0f);
  EXPECT_EQ(tir.coat, 0.0f);
}

TEST(InterfacePhysics, SpecularScalesTheCurveByColourAndWeight) {
  scene::Material m;
  m.specular = 0.8f;
  m.specular_color = glm::vec3(2.0f, 1.0f, 0.5f);
  // Normal incidence, n = 1.5: F = F0 = 0.04, so F' = F0' = 0.04 * (2, 1, 0.5) = (0.08, 0.04, 0.02);
  // R = 0.8 * F' = (0.064, 0.032, 0.016).
  expect_channels(smooth_reflectance(m, 1.0f, 1.0f, 1.5f), glm::vec3(0.064f, 0.032f, 0.016f));
  // 45 degrees, F = 0.050240 (above): red F' = 0.08 + 0.92 * (0.050240 - 0.04) / 0.96 = 0.08 + 0.009813
  // = 0.089813, green F' = F = 0.050240, blue 0.02 + 0.98 * 0.010240 / 0.96 = 0.030453; times 0.8:
  // (0.071851, 0.040192, 0.024363).
  expect_channels(smooth_reflectance(m, std::sqrt(0.5f), 1.0f, 1.5f), glm::vec3(0.071851f, 0.040192f, 0.024363f));
  // The same rescaling from inside: the curve's F0 = ((1 - 1.5) / (1 + 1.5))^2 = 0.04 either way.
  expect_channels(smooth_reflectance(m, 1.0f, 1.5f, 1.0f), glm::vec3(0.064f, 0.032f, 0.016f));
}

TEST(InterfacePhysics, SpecularZeroLetsEverythingCrossShortOfTotalInternalReflection) {
  scene::Material m;
  m.specular = 0.0f;
  for (float cos_i : {1.0f, 0.7f, 0.3f, 0.01f}) expect_channels(smooth_reflectance(m, cos_i, 1.0f, 1.5f), glm::vec3(0.0f), 0.0f);
  // From inside the critical cosine is sqrt(1 - 1/1.5^2) = 0.745356: above it all crosses, below it
  // total internal reflection still reflects everything.
  for (float cos_i : {1.0f, 0.9f, 0.76f}) expect_channels(smooth_reflectance(m, cos_i, 1.5f, 1.0f), glm::vec3(0.0f), 0.0f);
  expect_channels(smooth_reflectance(m, 0.7f, 1.5f, 1.0f), glm::vec3(1.0f), 0.0f);
}

TEST(InterfacePhysics, ASpecularColourPastOneClampsF0ToOne) {
  scene::Material m;
  m.specular_color = glm::vec3(30.0f, 1.0f, 1.0f);
  // Red: F0' = min(0.04 * 30, 1) = min(1.2, 1) = 1, so F' = 1 + 0 * (...) = 1 at every angle;
  // green and blue keep the bare curve (0.04 at normal incidence, 0.050240 at 45 degrees). (The min is
  // also implied by the final clamp: with F0' > 1, F' = F0' (1 - x) + x >= 1 for x = (F - F0) / (1 - F0) <= 1.)
  expect_channels(smooth_reflectance(m, 1.0f, 1.0f, 1.5f), glm::vec3(1.0f, 0.04f, 0.04f));
  expect_channels(smooth_reflectance(m, std::sqrt(0.5f), 1.0f, 1.5f), glm::vec3(1.0f, 0.050240f, 0.050240f));
  m.specular = 0.5f;  // the weight still applies: 0.5 * 1
  EXPECT_NEAR(smooth_reflectance(m, 0.3f, 1.0f, 1.5f).r, 0.5f, kTolerance);
}

TEST(InterfacePhysics, TheClearCoatReflectsItsShareFirst) {
  scene::Material m;
  m.clearcoat = 1.0f;
  // cos_outside 1: Fc = 0.04 + 0.96 * 0^5 = 0.04 = C; over n = 1.5 at normal incidence (0.04):
  // 0.04 + (1 - 0.04) * 0.04 = 0.04 + 0.0384 = 0.0784.
  auto r = interface_reflectance(m, 1.0f, 1.0f, 1.0f, 1.5f);
  EXPECT_NEAR(r.coat, 0.04f, kTolerance);
  expect_channels(r.reflectance, glm::vec3(0.0784f));
  // cos_outside 0.5: Fc = 0.04 + 0.96 * 0.5^5 = 0.04 + 0.96 / 32 = 0.04 + 0.03 = 0.07.
  r = interface_reflectance(m, 1.0f, 0.5f, 1.0f, 1.5f);
  EXPECT_NEAR(r.coat, 0.07f, kTolerance);
  expect_channels(r.reflectance, glm::vec3(0.07f + 0.93f * 0.04f));  // 0.07 + 0.0372 = 0.1072
  // Half a coat over the base at 60 degrees (cos 0.5) from the air: C = 0.5 * 0.07 = 0.035.
  // Base: sin_t = 0.866025 / 1.5 = 0.577350, cos_t = 0.816497; rs = (0.5 - 1.224745) / (0.5 + 1.224745)
  // = -0.420204, rp = (0.75 - 0.816497) / (0.75 + 0.816497) = -0.042449, F = (0.176571 + 0.001802) / 2
  // = 0.089187. R = 0.035 + 0.965 * 0.089187 = 0.035 + 0.086065 = 0.121065.
  m.clearcoat = 0.5f;
  r = interface_reflectance(m, 0.5f, 0.5f, 1.0f, 1.5f);
  EXPECT_NEAR(r.coat, 0.035f, kTolerance);
  expect_channels(r.reflectance, glm::vec3(0.121065f));
  // The coat over a coloured specular layer: C + (1 - C) * (0.064, 0.032, 0.016) at normal incidence
  // with C = 0.5 * 0.04 = 0.02: (0.02 + 0.98 * 0.064, ...) = (0.08272, 0.05136, 0.03568).
  m.specular = 0.8f;
  m.specular_color = glm::vec3(2.0f, 1.0f, 0.5f);
  expect_channels(interface_reflectance(m, 1.0f, 1.0f, 1.0f, 1.5f).reflectance, glm::vec3(0.08272f, 0.05136f, 0.03568f));
}

TEST(InterfacePhysics, AQuarterWaveFilmInGreenCancelsGreensReflection) {
  const glm::vec3 r = smooth_reflectance(with_film(kQuarterWaveGreenNm), 1.0f, 1.0f, 1.5f);
  EXPECT_NEAR(r.g, kQuarterWaveGreenR, kTolerance);
  // Red: delta = pi * 587.56 / 656.27 = 2.812675, cos delta = -0.946392, 2 r12 r23 cos delta = 0.018634 *
  // -0.946392 = -0.017634; R = (0.017013 + 0.005102 - 0.017634) / (1 + 0.0000868 - 0.017634)
  // = 0.0044803 / 0.982452 = 0.004561.
  EXPECT_NEAR(r.r, 0.0045607f, kTolerance);
  // Blue: delta = pi * 587.56 / 486.13 = 3.797079, cos delta = -0.792751, 2 r12 r23 cos delta = -0.014772;
  // R = (0.022115 - 0.014772) / (1.0000868 - 0.014772) = 0.0073434 / 0.985315 = 0.007453.
  EXPECT_NEAR(r.b, 0.0074530f, kTolerance);
  EXPECT_GT(r.r, r.g + 0.0005f);
  EXPECT_GT(r.b, r.r + 0.0005f);
}

TEST(InterfacePhysics, AHalfWaveFilmIsAbsentInGreen) {
  // delta = 2 pi, cos delta = 1: R = ((r12 + r23) / (1 + r12 r23))^2 = (-0.201863 / 1.009317)^2
  // = (-0.2)^2 = 0.04, the bare interface's.
  const glm::vec3 r = smooth_reflectance(with_film(587.56f / (2.0f * 1.3f)), 1.0f, 1.0f, 1.5f);
  EXPECT_NEAR(r.g, 0.04f, kTolerance);
}

TEST(InterfacePhysics, AFilmOfNoThicknessIsTheBareInterface) {
  // delta = 0: R = ((r12 + r23) / (1 + r12 r23))^2 = r13^2 for either polarisation, at any angle.
  for (float cos_i : {1.0f, std::sqrt(0.5f), 0.3f}) {
    expect_channels(smooth_reflectance(with_film(0.0f), cos_i, 1.0f, 1.5f), glm::vec3(fresnel_dielectric(cos_i, 1.0f, 1.5f)));
  }
  expect_channels(smooth_reflectance(with_film(0.0f), std::sqrt(0.5f), 1.0f, 1.5f), glm::vec3(0.050240f));
  for (float cos_i : {1.0f, 0.9f, 0.8f}) {  // from inside, short of the critical 0.745356
    expect_channels(smooth_reflectance(with_film(0.0f), cos_i, 1.5f, 1.0f), glm::vec3(fresnel_dielectric(cos_i, 1.5f, 1.0f)));
  }
}

TEST(InterfacePhysics, AnObliqueFilmUsesItsOwnAngleForThePhaseAndBothPolarisations) {
  // 45 degrees, air | 1.3 | 1.5: cos in the film = sqrt(1 - (0.707107 / 1.3)^2) = 0.839132, in the glass
  // 0.881917. d = 587.56 / (4 * 1.3 * 0.839132) = 134.654 nm makes delta = pi in green.
  // s: r12 = (0.707107 - 1.090872) / (0.707107 + 1.090872) = -0.213442, r23 = (1.090872 - 1.322876) /
  // (1.090872 + 1.322876) = -0.096118; Rs = ((r12 - r23) / (1 - r12 r23))^2 = (-0.117324 / 0.979484)^2 = 0.014348.
  // p: r12 = (1.3 * 0.707107 - 0.839132) / (0.919239 + 0.839132) = 0.045558, r23 = (1.5 * 0.839132 -
  // 1.3 * 0.881917) / (1.258698 + 1.146492) = 0.046651; Rp = (-0.001094 / 0.997875)^2 = 0.0000012.
  // R = (0.014348 + 0.0000012) / 2 = 0.007174.
  const float d = 587.56f / (4.0f * 1.3f * 0.8391317f);
  EXPECT_NEAR(smooth_reflectance(with_film(d), std::sqrt(0.5f), 1.0f, 1.5f).g, 0.0071744f, kTolerance);
}

TEST(InterfacePhysics, IridescenceMixesTheFilmWithTheBareInterface) {
  // Half of 0.003548 and half of 0.04: (0.0035475 + 0.04) / 2 = 0.021774.
  EXPECT_NEAR(smooth_reflectance(with_film(kQuarterWaveGreenNm, 0.5f), 1.0f, 1.0f, 1.5f).g, 0.0217738f, kTolerance);
  EXPECT_NEAR(smooth_reflectance(with_film(kQuarterWaveGreenNm, 0.0f), 1.0f, 1.0f, 1.5f).g, 0.04f, kTolerance);
}

TEST(InterfacePhysics, AFilmReflectsAlikeFromEitherSide) {
  // A lossless stack reflects as much from either side along the same path (Stokes): from inside the
  // glass at normal incidence the film's interfaces are r12 = (1.5 - 1.3) / 2.8 = 0.071429 and
  // r23 = (1.3 - 1) / 2.3 = 0.130435, the same squares and product as from outside.
  EXPECT_NEAR(smooth_reflectance(with_film(kQuarterWaveGreenNm), 1.0f, 1.5f, 1.0f).g, kQuarterWaveGreenR, kTolerance);
  for (float d : {0.0f, 75.0f, 300.0f, 640.0f, 1100.0f}) {
    expect_channels(smooth_reflectance(with_film(d), 1.0f, 1.5f, 1.0f), smooth_reflectance(with_film(d), 1.0f, 1.0f, 1.5f));
    // Obliquely: 45 degrees outside is cos_t = 0.881917 inside.
    expect_channels(smooth_reflectance(with_film(d), 0.8819171f, 1.5f, 1.0f), smooth_reflectance(with_film(d), std::sqrt(0.5f), 1.0f, 1.5f),
                    1e-5f);
  }
}

TEST(InterfacePhysics, EveryLayeredReflectanceStaysWithinZeroAndOne) {
  for (float film_ior : {1.0f, 1.3f, 2.4f}) {
    for (float d = 0.0f; d <= 1200.0f; d += 37.5f) {
      scene::Material m = with_film(d, 1.0f, film_ior);
      m.specular_color = glm::vec3(3.0f, 1.0f, 0.2f);
      m.clearcoat = d > 600.0f ? 1.0f : 0.0f;
      for (float cos_i = 0.0f; cos_i <= 1.0f; cos_i += 0.05f) {
        for (auto [eta_i, eta_t] : {std::pair{1.0f, 1.5f}, std::pair{1.5f, 1.0f}, std::pair{1.0f, 2.4f}}) {
          const auto r = interface_reflectance(m, cos_i, cos_i, eta_i, eta_t);
          for (int c = 0; c < 3; ++c) {
            EXPECT_TRUE(r.reflectance[c] >= 0.0f && r.reflectance[c] <= 1.0f)
                << "n " << film_ior << " d " << d << " cos " << cos_i << " " << eta_i << "->" << eta_t << ": " << r.reflectance[c];
            EXPECT_GE(r.reflectance[c], r.coat - 1e-7f);
          }
        }
      }
    }
  }
}
