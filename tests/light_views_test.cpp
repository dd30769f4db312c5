// A point light's caustic view (scene/light_views.cpp): a frustum from the light that holds every
// refractor's bounding sphere, no wider than the margin asks, and none where the refractors lie
// around the light; spot and directional lights keep their own view. On the CPU.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "io/json_document.h"
#include "scene/scene.h"

using namespace caustica;
using namespace caustica::scene;

namespace {

// The angle from the light's axis to the far side of a sphere, and its own angular radius.
struct SeenSphere {
  float off_axis, radius;
};
SeenSphere seen(const Light& light, glm::vec3 center, float radius) {
  const glm::vec3 to = center - light.view.position;
  const float distance = glm::length(to);
  return {std::acos(std::clamp(glm::dot(to / distance, light.as_caustic_view().axis()), -1.0f, 1.0f)), std::asin(radius / distance)};
}

Scene point_light_over_balls(const std::string& light, const std::string& balls) {
  return load_scene(JsonDocument::parse(R"({"camera": {"position": [0, 4, 8], "target": [0, 0, 0]}, "lights": [)" + light +
                                            R"(], "objects": [{"name": "floor", "primitive": {"type": "plane", "size": [20, 20]}})" +
                                            balls + "]}",
                                        "point.json"));
}

std::string ball(float x, float y, float z, float radius) {
  return R"(, {"primitive": {"type": "sphere", "radius": )" + std::to_string(radius) + R"(}, "transform": {"translate": [)" +
         std::to_string(x) + ", " + std::to_string(y) + ", " + std::to_string(z) + R"(]}, "material": {"refractor": true}})";
}

}  // namespace

// Over one ball the view looks at it, and its cone is the ball's own, widened by the margin only:
// a ball of radius 1 seen from 4.5 away subtends asin(1 / 4.5) = 12.84 degrees.
TEST(CausticViews, AViewHoldsTheBallItLooksAt) {
  const Scene s = point_light_over_balls(R"({"type": "point", "position": [0, 6, 0]})", ball(0, 1.5f, 0, 1));
  const Light& light = s.lights.at(0);
  ASSERT_TRUE(light.has_caustic_view);
  EXPECT_NEAR(glm::dot(light.as_caustic_view().axis(), glm::vec3(0, -1, 0)), 1.0f, 1e-5f);
  const float tan_half = std::tan(glm::radians(light.caustic_view.fov_y_degrees) * 0.5f);
  const float subtended = std::asin(1.0f / 4.5f);
  EXPECT_GE(tan_half, std::tan(subtended));
  EXPECT_NEAR(tan_half, kCausticViewMargin * std::tan(subtended), 2e-3f);
  const double values = s.expression_values().at("scene.light0.view");
  EXPECT_EQ(values, 1.0);
}

// Three balls spread under a light low over the middle one: one frustum holds all three spheres.
TEST(CausticViews, AViewHoldsEveryRefractorTheLightReaches) {
  const Scene s = point_light_over_balls(R"({"type": "point", "position": [0, 2.2, 0.6]})",
                                         ball(-1.8f, 0.6f, 0, 0.6f) + ball(0, 0.6f, 0, 0.6f) + ball(1.8f, 0.6f, 0, 0.6f));
  const Light& light = s.lights.at(0);
  ASSERT_TRUE(light.has_caustic_view);
  const float half = glm::radians(light.caustic_view.fov_y_degrees) * 0.5f;
  for (float x : {-1.8f, 0.0f, 1.8f}) {
    const SeenSphere sphere = seen(light, glm::vec3(x, 0.6f, 0), 0.6f);
    EXPECT_LE(sphere.off_axis + sphere.radius, half) << "ball at x = " << x;
  }
}

// A light inside a ball, or among balls on every side of it, has no single frustum: no view, and
// the graph's caustic passes for it are culled by light.view.
TEST(CausticViews, ALightAmongItsRefractorsHasNoView) {
  const Scene inside = point_light_over_balls(R"({"type": "point", "position": [0, 1.5, 0]})", ball(0, 1.5f, 0, 1));
  EXPECT_FALSE(inside.lights.at(0).has_caustic_view);
  EXPECT_EQ(inside.expression_values().at("scene.light0.view"), 0.0);
  const Scene among = point_light_over_balls(R"({"type": "point", "position": [0, 1, 0]})",
                                             ball(3, 1, 0, 0.5f) + ball(-3, 1, 0, 0.5f) + ball(0, 1, 3, 0.5f));
  EXPECT_FALSE(among.lights.at(0).has_caustic_view);
  // Without refractors there is nothing to aim at.
  const Scene none = point_light_over_balls(R"({"type": "point", "position": [0, 3, 0]})", "");
  EXPECT_FALSE(none.lights.at(0).has_caustic_view);
}

// A spot or directional light throws its caustic through its own view (docs/caustics.md says why).
TEST(CausticViews, SpotAndDirectionalLightsKeepTheirOwnView) {
  const Scene spot =
      point_light_over_balls(R"({"type": "spot", "position": [0.5, 6, 0], "target": [0, 0, 0], "fov": 60})", ball(0.5f, 1, 0, 0.5f));
  EXPECT_TRUE(spot.lights.at(0).has_caustic_view);
  EXPECT_EQ(spot.lights.at(0).caustic_view_projection(), spot.lights.at(0).view_projection());
  const Scene sun = point_light_over_balls(R"({"type": "directional", "position": [0, 10, 0], "target": [0, 0, 0]})", ball(2, 1, -1, 0.5f));
  EXPECT_TRUE(sun.lights.at(0).has_caustic_view);
  EXPECT_EQ(sun.lights.at(0).caustic_view_projection(), sun.lights.at(0).view_projection());
}
