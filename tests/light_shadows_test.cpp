// Every light casts its shadow (per-light shadow passes, graph/per_light.h): direct light is linear in
// the lights, so with no ambient light the darkening an occluder brings to a picture lit by three
// lights (two spots and a point light) is the sum of the darkenings it brings to the pictures lit by
// each light alone. Were only one light shadowed, the other two lights' shadows would be missing
// from the three-light picture. And the shadows are where exact shadow rays put them: the picture
// against the ray-traced reference's (Embree, reference/refraction_reference.h).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/paths.h"
#include "graph/graph_desc.h"
#include "graph/per_light.h"
#include "io/json_document.h"
#include "reference/refraction_reference.h"
#include "scene/scene.h"
#include "scene_engine.h"

using namespace caustica;

namespace {

// The G-buffer, a shadow map per light, lighting into a 32-bit image (the sums below compare to
// float rounding, not to half floats'), as the bundled graphs declare them.
const char* kShadowGraph = R"({
  "name": "shadows",
  "resources": {
    "depth": {"type": "image", "format": "d32f"},
    "normal": {"type": "image", "format": "rgba16f"},
    "albedo": {"type": "image", "format": "rgba8"},
    "shadow": {"type": "image", "format": "d32f", "width": 512, "height": 512, "layers": "1 + 5 * light.point",
               "fallback": null, "for_each": "light"},
    "lit": {"type": "image", "format": "rgba32f"}
  },
  "passes": [
    {"name": "gbuffer", "type": "gbuffer", "outputs": {"depth": "depth", "normal": "normal", "albedo": "albedo"}},
    {"name": "shadow", "type": "shadow_map", "for_each": "light", "enabled": "light.objects", "params": {"light": "$light"},
     "outputs": {"depth": "shadow"}},
    {"name": "lighting", "type": "lighting", "inputs": {"depth": "depth", "normal": "normal", "albedo": "albedo", "shadow": "shadow"},
     "outputs": {"color": "lit"}}
  ],
  "outputs": ["lit"]
})";

// A floor and a box above it under the lights of `lights` (indices into the three below), without
// the box where `occluder` is false. The point light stands beside the box's top, so that the box's
// shadow from it spans two faces of its cube (-y and +x).
std::shared_ptr<const scene::Scene> scene_with(const std::vector<int>& lights, bool occluder) {
  const nlohmann::json all_lights[] = {
      {{"type", "spot"}, {"position", {-4.0, 5.0, 0.5}}, {"target", {0.0, 0.0, 0.0}}, {"fov", 70}, {"intensity", 40}},
      {{"type", "spot"}, {"position", {3.5, 5.0, -1.0}}, {"target", {0.0, 0.0, 0.0}}, {"fov", 70}, {"intensity", 40}},
      {{"type", "point"}, {"position", {-0.8, 2.2, 0.3}}, {"intensity", 6}}};
  nlohmann::json j = {{"name", "three_lights"},
                      {"camera", {{"position", {0.0, 6.0, 6.0}}, {"target", {0.0, 0.0, 0.0}}, {"fov", 60}}},
                      {"ambient", 0.0},
                      {"sky", {0.0, 0.0, 0.0}},
                      {"lights", nlohmann::json::array()},
                      {"objects", {{{"name", "floor"}, {"primitive", {{"type", "plane"}, {"size", {12, 12}}}}}}}};
  for (int light : lights) j["lights"].push_back(all_lights[light]);
  if (occluder) {
    j["objects"].push_back(
        {{"name", "box"}, {"primitive", {{"type", "box"}, {"size", {0.6, 0.6, 0.6}}}}, {"transform", {{"translate", {0.0, 1.3, 0.0}}}}});
  }
  return std::make_shared<const scene::Scene>(scene::load_scene(JsonDocument::parse(j.dump(), "three_lights.json")));
}

io::ImageData lit(test::SceneEngine& engine, const graph::GraphDesc& graph, std::shared_ptr<const scene::Scene> scene) {
  engine.render(graph, std::move(scene), {"lit"});
  return engine.executor.read_image("lit");
}

// The linear radiance of the floor and box under `lights`, less that of the floor alone.
std::vector<double> darkening(test::SceneEngine& engine, const graph::GraphDesc& graph, const std::vector<int>& lights) {
  const io::ImageData with = lit(engine, graph, scene_with(lights, true));
  const io::ImageData without = lit(engine, graph, scene_with(lights, false));
  std::vector<double> out(with.rgba.size());
  for (size_t i = 0; i < out.size(); ++i) out[i] = double(with.rgba[i]) - double(without.rgba[i]);
  return out;
}

}  // namespace

TEST(LightShadows, EveryLightCastsItsShadowAndTheShadowsAdd) {
  test::SceneEngine engine;
  engine.width = 192;
  engine.height = 128;
  const graph::GraphDesc graph = graph::load_graph(JsonDocument::parse(kShadowGraph, "shadows.json"));
  const std::vector<double> all = darkening(engine, graph, {0, 1, 2});
  std::vector<double> sum(all.size(), 0.0);
  for (int light = 0; light < 3; ++light) {
    const std::vector<double> alone = darkening(engine, graph, {light});
    // Each light alone: its shadow takes a share of the light that reached the floor there.
    double shadowed = 0;
    for (size_t i = 0; i < alone.size(); i += 4) shadowed += alone[i] < -1e-3 ? 1 : 0;
    EXPECT_GT(shadowed, 200) << "light " << light << " casts no shadow of the box";
    for (size_t i = 0; i < sum.size(); ++i) sum[i] += alone[i];
  }
  double difference = 0, total = 0;
  for (size_t i = 0; i < all.size(); ++i) {
    if (i % 4 == 3) continue;
    difference += std::abs(all[i] - sum[i]);
    total += std::abs(sum[i]);
  }
  ASSERT_GT(total, 0.0);
  EXPECT_LT(difference / total, 1e-4) << "the three lights' picture is not the sum of its lights' shadows";
}

TEST(LightShadows, ShadowMapsPutEveryLightsShadowWhereShadowRaysDo) {
  test::SceneEngine engine;
  engine.width = 192;
  engine.height = 128;
  const graph::GraphDesc graph = graph::load_graph(JsonDocument::parse(kShadowGraph, "shadows.json"));
  // The three lights, and the point light alone (its shadow falls across two faces of its cube).
  for (const std::vector<int>& lights : {std::vector<int>{0, 1, 2}, std::vector<int>{2}}) {
    const auto scene = scene_with(lights, true);
    const io::ImageData picture = lit(engine, graph, scene);
    const io::ImageData exact = reference::render_refraction_reference(*scene, engine.width, engine.height).radiance;
    ASSERT_EQ(picture.rgba.size(), exact.rgba.size());
    double difference = 0, total = 0;
    for (size_t i = 0; i < exact.rgba.size(); ++i) {
      if (i % 4 == 3) continue;
      difference += std::abs(double(picture.rgba[i]) - double(exact.rgba[i]));
      total += std::abs(double(exact.rgba[i]));
    }
    ASSERT_GT(total, 0.0);
    std::printf("%zu light(s): shadow maps against shadow rays, relative L1 %.4f\n", lights.size(), difference / total);
    // Filtered map edges against hard ray-traced ones (0.001 here); with only the first light
    // shadowed the three lights' picture is 0.023 away.
    EXPECT_LT(difference / total, 0.005) << lights.size() << " light(s)";
  }
}

// A light that moves starts over its own shadow and caustic passes and what reads every light's
// (lighting), not the other lights' (the viewer, reusing unchanged passes, on the bundled
// three-light scene, where the point light throws its caustic through its fitted view).
TEST(LightShadows, MovingOneLightRedrawsOnlyItsOwnShadowAndCaustic) {
  test::SceneEngine engine;
  engine.reuse = true;
  const auto scene = test::load_bundled_scene("three_lights");
  auto graph = graph::load_graph_file((data_dir() / "graphs/caustics_adaptive.json").string());
  graph::apply_overrides(graph, {"grid=256", "light_size=256", "shadow_size=256", "caustic_size=128"});
  engine.executor.set_scene(scene);
  engine.configure(graph, 160, 90);
  engine.executor.run_frame(false);
  std::vector<scene::Light> lights = scene->lights;
  lights[1].view.position.x += 0.5f;
  engine.executor.set_view(scene->camera, lights);
  const graph::FrameResult moved = engine.executor.run_frame(false);
  std::map<std::string, bool> ran;
  for (const auto& p : moved.passes) ran[p.name] = p.ran();
  for (const char* pass : {"shadow", "receivers", "light_refractors", "caustics"}) {
    EXPECT_TRUE(ran.at(graph::light_instance(pass, 1))) << pass << " of the moved light";
    for (uint32_t light : {0u, 2u}) EXPECT_FALSE(ran.at(graph::light_instance(pass, light))) << pass << " of light " << light;
  }
  EXPECT_TRUE(ran.at("lighting"));
}
