// The device's interface model (shaders/refraction/interface.glsl) against values worked by hand from
// glTF's extensions: tests/data/interface/interface_probe.comp evaluates it at chosen materials and
// angles on the device. The host's model (reference/interface_physics.h), written apart, meets the
// same numbers in scene_test's InterfacePhysics.
#include <gtest/gtest.h>

#include <filesystem>
#include <glm/gtc/type_ptr.hpp>

#include "scene_engine.h"

using namespace caustica;

namespace {

struct KnownAnswer {
  const char* what;
  glm::vec3 reflectance;
  float coat;
};

}  // namespace

TEST(InterfaceOnTheDevice, EachLayerMeetsTheValuesWorkedByHand) {
  test::SceneEngine e;
  const graph::GraphDesc probe =
      graph::load_graph_file((std::filesystem::path(CAUSTICA_SOURCE_DIR) / "tests/data/interface/interface_probe.json").string());
  e.render(probe, test::load_bundled_scene("sphere_plane"), {});
  const io::ImageData values = e.executor.read_image("values");
  ASSERT_EQ(values.width, 8u);
  // Glass of n = 1.5 from air unless said: F0 = (0.5 / 2.5)^2 = 0.04; at 45 degrees rs = -0.303337,
  // rp = 0.092013, F = 0.050240; at 60 degrees rs = -0.420204, rp = -0.042449, F = 0.089187.
  // A film of 1.3 on it: r12 = (1 - 1.3) / 2.3 = -0.130435, r23 = (1.3 - 1.5) / 2.8 = -0.071429.
  const KnownAnswer answers[] = {
      {"plain glass, normal incidence", glm::vec3(0.04f), 0.0f},
      // specular 0.8 x min(0.04 x (2, 1, 0.5), 1) = (0.064, 0.032, 0.016)
      {"specular colour (2, 1, 0.5), weight 0.8, normal incidence", glm::vec3(0.064f, 0.032f, 0.016f), 0.0f},
      // red: 0.08 + 0.92 x (0.050240 - 0.04) / 0.96 = 0.089813, x 0.8 = 0.071851; green 0.8 x 0.050240;
      // blue: 0.02 + 0.98 x 0.010667 = 0.030453, x 0.8 = 0.024363
      {"specular colour (2, 1, 0.5), weight 0.8, 45 degrees", glm::vec3(0.071851f, 0.040192f, 0.024363f), 0.0f},
      // C = 0.04 + 0.96 x 0 = 0.04; 0.04 + 0.96 x 0.04 = 0.0784
      {"full clear coat, normal incidence", glm::vec3(0.0784f), 0.04f},
      // C = 0.04 + 0.96 x 0.5^5 = 0.07; 0.07 + 0.93 x 0.089187 = 0.152944
      {"full clear coat, 60 degrees", glm::vec3(0.152944f), 0.07f},
      // green: ((r12 - r23) / (1 - r12 r23))^2 = (-0.059006 / 0.990683)^2 = 0.0035475; red (cos delta =
      // -0.946392) 0.0045607, blue (cos delta = -0.792751) 0.0074530
      {"film 1.3, a quarter wave at 587.56 nm", glm::vec3(0.0045607f, 0.0035475f, 0.0074530f), 0.0f},
      // a half wave adds a whole period: the bare interface's 0.04 in green
      {"film 1.3, a half wave at 587.56 nm", glm::vec3(-1.0f, 0.04f, -1.0f), 0.0f},
      // from inside: r12 = +0.071429, r23 = +0.130435, the same squares and product
      {"the quarter-wave film from inside the glass", glm::vec3(0.0045607f, 0.0035475f, 0.0074530f), 0.0f},
  };
  for (uint32_t i = 0; i < 8; ++i) {
    const glm::vec4 texel = glm::make_vec4(&values.rgba[size_t{i} * 4]);
    std::printf("%-58s %.6f %.6f %.6f, coat %.4f\n", answers[i].what, double(texel.r), double(texel.g), double(texel.b), double(texel.a));
    for (int c = 0; c < 3; ++c) {
      if (answers[i].reflectance[c] < 0.0f) continue;  // not worked by hand
      EXPECT_NEAR(texel[c], answers[i].reflectance[c], 2e-5f) << answers[i].what << ", channel " << c;
    }
    EXPECT_NEAR(texel[3], answers[i].coat, 1e-6f) << answers[i].what;
  }
}
