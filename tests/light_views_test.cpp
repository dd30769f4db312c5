// A light's caustic view (scene/light_views.cpp): a frustum (a directional light's prism) from the
// light that holds every refractor's bounding sphere it reaches, no wider than the margin asks, and
// for a point light none where the refractors lie around it. On the CPU.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

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

// A light moved in the scene (move_light) has its view fitted again: moved 3 to the side, its view
// turns to the ball and narrows to the ball's cone from there.
TEST(CausticViews, AMovedLightsViewIsFittedAgain) {
  Scene s = point_light_over_balls(R"({"type": "point", "position": [0, 6, 0]})", ball(0, 1.5f, 0, 1));
  move_light(s, 0, glm::vec3(3, 0, 0));
  const Light& light = s.lights.at(0);
  EXPECT_EQ(light.view.position, glm::vec3(3, 6, 0));
  const glm::vec3 to_ball = glm::normalize(glm::vec3(0, 1.5f, 0) - light.view.position);
  EXPECT_NEAR(glm::dot(light.as_caustic_view().axis(), to_ball), 1.0f, 1e-4f);
  EXPECT_NEAR(std::tan(glm::radians(light.caustic_view.fov_y_degrees) * 0.5f),
              kCausticViewMargin * std::tan(std::asin(1.0f / glm::length(glm::vec3(0, 1.5f, 0) - light.view.position))), 2e-3f);
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
// A point light that no frustum holds its refractors in throws through the faces of a cube about
// it: inside a ball every face holds glass (and the light stands in it); among three balls on
// the +x, -x and +z sides only those three faces, each one caustic view, the first light 0's and
// the others after the lights. Without refractors there is nothing to aim at.
TEST(CausticViews, ALightAmongItsRefractorsThrowsThroughTheCubeFacesThatHoldThem) {
  const Scene inside = point_light_over_balls(R"({"type": "point", "position": [0, 1.5, 0]})", ball(0, 1.5f, 0, 1));
  const Light& bulb = inside.lights.at(0);
  EXPECT_TRUE(bulb.has_caustic_view);
  EXPECT_EQ(bulb.caustic_faces, 0x3fu);
  EXPECT_EQ(bulb.inside, 1) << "the ball, object 1";
  EXPECT_EQ(bulb.caustic_view_count(), 6u);
  const std::vector<CausticView> views = caustic_views(inside.lights);
  ASSERT_EQ(views.size(), 6u);
  for (int face = 0; face < 6; ++face) {
    EXPECT_EQ(views[static_cast<size_t>(face)].face, face);
    EXPECT_EQ(views[static_cast<size_t>(face)].light, 0u);
    EXPECT_NEAR(std::tan(glm::radians(views[static_cast<size_t>(face)].seen.view.fov_y_degrees) * 0.5f), kCubeFaceCausticTan, 1e-5f);
    EXPECT_NEAR(glm::dot(views[static_cast<size_t>(face)].seen.axis(), Light::face_axis(static_cast<uint32_t>(face))), 1.0f, 1e-6f);
  }
  EXPECT_EQ(inside.expression_values().at("scene.caustic_views"), 6.0);
  EXPECT_EQ(inside.expression_values().at("scene.caustic5.face"), 5.0);
  EXPECT_EQ(inside.expression_values().at("scene.caustic5.light"), 0.0);

  const Scene among = point_light_over_balls(R"({"type": "point", "position": [0, 1, 0]})",
                                             ball(3, 1, 0, 0.5f) + ball(-3, 1, 0, 0.5f) + ball(0, 1, 3, 0.5f));
  EXPECT_EQ(among.lights.at(0).caustic_faces, (1u << 0) | (1u << 1) | (1u << 4));
  EXPECT_EQ(among.lights.at(0).inside, -1);
  const std::vector<CausticView> faces = caustic_views(among.lights);
  ASSERT_EQ(faces.size(), 3u);
  EXPECT_EQ(faces[0].face, 0);
  EXPECT_EQ(faces[1].face, 1);
  EXPECT_EQ(faces[2].face, 4);
  const Scene none = point_light_over_balls(R"({"type": "point", "position": [0, 3, 0]})", "");
  EXPECT_FALSE(none.lights.at(0).has_caustic_view);
  EXPECT_FALSE(caustic_views(none.lights).at(0).present);
}

// The faces share out every direction: each leaves through exactly one face, the one whose axis
// its largest component lies along (ties to x, then y, as the shaders' cube_face).
TEST(CausticViews, EveryDirectionLeavesThroughOneCubeFace) {
  const glm::vec3 directions[] = {{1, 0.2f, -0.3f}, {-0.1f, -2, 0.5f}, {0.3f, 0.3f, -0.9f}, {1, 1, 0}, {0, -1, -1}, {-1, 1, 1}};
  const int expected[] = {0, 3, 5, 0, 3, 1};
  for (size_t i = 0; i < std::size(directions); ++i) {
    int through = 0;
    for (int face = 0; face < 6; ++face) {
      if (leaves_through_face(directions[i], face)) {
        ++through;
        EXPECT_EQ(face, expected[i]) << i;
      }
    }
    EXPECT_EQ(through, 1) << i;
  }
}

// A spot's caustic view is narrowed to the refractors it reaches: the ball's own cone widened by the
// margin, about the axis to it; a ball outside the spot's cone does not widen it. (Left with its
// own 60-degree view the ball, 10 degrees across, would cover a 36th of the caustic map.)
TEST(CausticViews, ASpotsViewIsFittedToTheRefractorsItReaches) {
  const Scene s = point_light_over_balls(R"({"type": "spot", "position": [0.5, 6, 0], "target": [0, 0, 0], "fov": 60})",
                                         ball(0.5f, 1, 0, 0.5f) + ball(9, 1, 0, 0.5f));
  const Light& light = s.lights.at(0);
  ASSERT_TRUE(light.has_caustic_view);
  EXPECT_NEAR(glm::dot(light.as_caustic_view().axis(), glm::vec3(0, -1, 0)), 1.0f, 1e-5f);
  const float tan_half = std::tan(glm::radians(light.caustic_view.fov_y_degrees) * 0.5f);
  EXPECT_NEAR(tan_half, kCausticViewMargin * std::tan(std::asin(0.5f / 5.0f)), 2e-3f);
  // Its cone is still the spot's own: the caustic passes weigh their photons by it.
  EXPECT_EQ(light.as_caustic_view().view.fov_y_degrees, light.caustic_view.fov_y_degrees);
  EXPECT_EQ(light.axis(), glm::normalize(glm::vec3(-0.5f, -6, 0)));
  // A ball that fills the spot's cone leaves it its own view, as does the scene's "caustic_view": "light".
  const Scene filling =
      point_light_over_balls(R"({"type": "spot", "position": [0, 6, 0], "target": [0, 0, 0], "fov": 20})", ball(0, 1, 0, 1.5f));
  EXPECT_EQ(filling.lights.at(0).caustic_view_projection(), filling.lights.at(0).view_projection());
  const Scene own = point_light_over_balls(
      R"({"type": "spot", "position": [0.5, 6, 0], "target": [0, 0, 0], "fov": 60, "caustic_view": "light"})", ball(0.5f, 1, 0, 0.5f));
  EXPECT_TRUE(own.lights.at(0).has_caustic_view);
  EXPECT_EQ(own.lights.at(0).caustic_view_projection(), own.lights.at(0).view_projection());
}

// A directional light's prism is narrowed across its direction to a square about the ball, twice its
// radius in half side, the ball at the square's middle; one that would reach outside the light's own
// prism is not (there is no light there).
TEST(CausticViews, ASunsPrismIsFittedToTheRefractorsItReaches) {
  const Scene s = point_light_over_balls(R"({"type": "directional", "position": [0, 10, 0], "target": [0, 0, 0]})", ball(2, 1, -1, 0.5f));
  const Light& light = s.lights.at(0);
  ASSERT_TRUE(light.has_caustic_view);
  EXPECT_NEAR(light.caustic_extent, kCausticViewMargin * 0.5f, 1e-5f);
  EXPECT_GT(light.extent, 5.0f);  // fitted to the floor when loaded
  const glm::vec4 middle = light.caustic_view_projection() * glm::vec4(2, 1, -1, 1);
  EXPECT_NEAR(middle.x / middle.w, 0.0f, 1e-5f);
  EXPECT_NEAR(middle.y / middle.w, 0.0f, 1e-5f);
  const glm::vec4 edge = light.caustic_view_projection() * glm::vec4(2 + kCausticViewMargin * 0.5f, 0, -1, 1);
  EXPECT_NEAR(std::abs(edge.x / edge.w), 1.0f, 1e-5f);
  EXPECT_EQ(light.as_caustic_view().axis(), light.axis());
  const Scene edge_of_light = point_light_over_balls(
      R"({"type": "directional", "position": [0, 10, 0], "target": [0, 0, 0], "extent": 2.5})", ball(2, 1, -1, 0.5f));
  EXPECT_EQ(edge_of_light.lights.at(0).caustic_view_projection(), edge_of_light.lights.at(0).view_projection());
}
