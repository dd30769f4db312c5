// Each light's caustic view (scene/light_views.cpp): a frustum from a spot or point light, or a prism
// along a directional light, that holds every refractor's bounding sphere it reaches, no wider than
// the margin asks (and never wider than a spot's or directional light's own view), and none for a
// point light whose refractors lie around it; on the CPU.
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

// A spot light of 60 degrees over a ball of radius 0.5 five units below it: its caustic view is the
// ball's cone, asin(0.5 / 5) = 5.74 degrees, widened by the margin, where its shadow keeps the whole
// frustum; aimed at the ball, whatever the spot's own aim. A spot narrower than the ball's cone
// keeps its own frustum.
TEST(CausticViews, ASpotLightsViewIsFittedToItsRefractors) {
  const std::string off_ball = ball(0.5f, 1.0f, 0.0f, 0.5f);
  const Scene wide = point_light_over_balls(R"({"type": "spot", "position": [0.5, 6, 0], "target": [0, 0, 0], "fov": 60})", off_ball);
  const Light& light = wide.lights.at(0);
  ASSERT_TRUE(light.has_caustic_view);
  EXPECT_EQ(light.view.fov_y_degrees, 60.0f);
  EXPECT_NEAR(std::tan(glm::radians(light.caustic_view.fov_y_degrees) * 0.5f), kCausticViewMargin * std::tan(std::asin(0.1f)), 1e-3f);
  EXPECT_NEAR(glm::dot(light.as_caustic_view().axis(), glm::vec3(0, -1, 0)), 1.0f, 1e-5f);
  const Scene narrow = point_light_over_balls(R"({"type": "spot", "position": [0.5, 6, 0], "target": [0.5, 0, 0], "fov": 8})", off_ball);
  EXPECT_EQ(narrow.lights.at(0).caustic_view.fov_y_degrees, 8.0f);
  EXPECT_EQ(narrow.lights.at(0).caustic_view.target, narrow.lights.at(0).view.target);
}

// A directional light fitted around the whole floor (its shadow) throws its caustic through a prism
// around the ball alone: centred on the ball across the light, half a side of the ball's radius
// times the margin.
TEST(CausticViews, ADirectionalLightsPrismIsFittedToItsRefractors) {
  const Scene s = point_light_over_balls(R"({"type": "directional", "position": [0, 10, 0], "target": [0, 0, 0]})", ball(2, 1, -1, 0.5f));
  const Light& light = s.lights.at(0);
  ASSERT_TRUE(light.has_caustic_view);
  EXPECT_GT(light.extent, 10.0f);  // the 20 x 20 floor
  EXPECT_NEAR(light.caustic_extent, kCausticViewMargin * 0.5f, 1e-3f);
  EXPECT_NEAR(light.caustic_view.position.x, 2.0f, 1e-4f);
  EXPECT_NEAR(light.caustic_view.position.z, -1.0f, 1e-4f);
  EXPECT_NEAR(glm::dot(light.as_caustic_view().axis(), light.axis()), 1.0f, 1e-6f);
  // The ball's centre projects to the middle of the caustic view's square.
  const glm::vec4 clip = light.caustic_view_projection() * glm::vec4(2, 1, -1, 1);
  EXPECT_NEAR(clip.x / clip.w, 0.0f, 1e-4f);
  EXPECT_NEAR(clip.y / clip.w, 0.0f, 1e-4f);
}
