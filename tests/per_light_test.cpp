// Per-light passes and resources ("for_each": "light", graph/per_light.h), on the CPU against the
// test registry: the instances, their names, parameters, sizes and bindings, the culling of a light's
// instance by its "enabled", and the messages for per-light parts that do not fit together.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "builtin_passes.h"
#include "graph/compiler.h"
#include "graph/per_light.h"
#include "plan_queries.h"
#include "test_registry.h"

using namespace caustica;
using namespace caustica::graph;
using test::pass_named;

namespace {

const PassRegistry& lights_registry() {
  static const PassRegistry r = test::make_test_registry();
  return r;
}

// Three lights: a spot, a point light and a directional light.
std::map<std::string, double> three_lights() {
  std::map<std::string, double> values = typical_scene_values();
  values["scene.lights"] = 3;
  const char* types[] = {"spot", "point", "directional"};
  for (int k = 0; k < 3; ++k) {
    const std::string prefix = "scene.light" + std::to_string(k) + ".";
    for (const char* type : types) values[prefix + type] = type == types[k] ? 1 : 0;
    values[prefix + "view"] = k == 1 ? 0 : 1;
    values[prefix + "objects"] = 2;
    values[prefix + "refractors"] = 1;
  }
  return values;
}

// Whether the plan's lighting pass reads element `light` of its per-light port `port`.
bool lighting_reads(const Plan& plan, const std::string& port, uint32_t light) {
  return test::pass_named(plan, "lighting").ports.count(port_element(port, light)) > 0;
}

Plan compile_for_lights(const nlohmann::json& j, const std::map<std::string, double>& scene_values = three_lights()) {
  CompileOptions options;
  options.output_width = 64;
  options.output_height = 32;
  options.scene_values = scene_values;
  return compile_graph(load_graph(JsonDocument::parse(j.dump(2), "lights.json")), lights_registry(), options);
}

std::string per_light_error(const nlohmann::json& j) {
  try {
    compile_for_lights(j);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

std::string resource_at(const Plan& plan, const PlannedPass& pass, const std::string& port) {
  const auto it = pass.ports.find(port);
  return it == pass.ports.end() ? "(unbound)" : plan.resources[it->second].name;
}

// A light-view image per light, blurred per light by its index, gathered by a pass that runs once.
nlohmann::json per_light_graph() {
  nlohmann::json per_light_image = {{"type", "image"}, {"format", "rgba16f"}, {"for_each", "light"}, {"width", "16 * (1 + light.point)"},
                                    {"height", "16"},  {"fallback", nullptr}};
  return {
      {"resources",
       {{"view", per_light_image},
        {"blurred", per_light_image},
        {"base", {{"type", "image"}, {"format", "rgba16f"}}},
        {"out", {{"type", "image"}, {"format", "rgba8"}}}}},
      {"passes",
       {{{"name", "gather"}, {"type", "gather"}, {"inputs", {{"lights", "blurred"}, {"base", "base"}}}, {"outputs", {{"color", "out"}}}},
        {{"name", "camera"}, {"type", "source"}, {"params", {{"mode", "b"}}}, {"outputs", {{"color", "base"}}}},
        {{"name", "light_view"}, {"type", "source"}, {"for_each", "light"}, {"outputs", {{"color", "view"}}}},
        {{"name", "blur"},
         {"type", "filter"},
         {"for_each", "light"},
         {"enabled", "1 - light.directional"},
         {"params", {{"radius", "$light"}}},
         {"inputs", {{"source", "view"}}},
         {"outputs", {{"target", "blurred"}}}}}},
      {"outputs", {"out"}}};
}

}  // namespace

TEST(PerLight, EachLightGetsItsInstancesNamedByItsIndex) {
  const Plan plan = compile_for_lights(per_light_graph());
  std::vector<std::string> names;
  for (const auto& p : plan.passes) names.push_back(p.name);
  for (const char* name : {"light_view#0", "light_view#1", "blur#0", "blur#1", "camera", "gather"})
    EXPECT_NE(std::find(names.begin(), names.end(), name), names.end()) << name;
  // Each instance reads and writes its own light's images, with its light's index as "$light".
  for (int k = 0; k < 2; ++k) {
    const PlannedPass& blur = pass_named(plan, "blur#" + std::to_string(k));
    EXPECT_EQ(resource_at(plan, blur, "source"), "view#" + std::to_string(k));
    EXPECT_EQ(resource_at(plan, blur, "target"), "blurred#" + std::to_string(k));
    EXPECT_EQ(blur.params["radius"], k);
  }
  // Sized per light: the point light's (light 1) twice as wide.
  EXPECT_EQ(plan.resources[static_cast<size_t>(plan.find_resource("view#0"))].width, 16u);
  EXPECT_EQ(plan.resources[static_cast<size_t>(plan.find_resource("view#1"))].width, 32u);
}

TEST(PerLight, ALightsInstanceIsCulledByItsEnabledAndItsElementLeftUnbound) {
  const Plan plan = compile_for_lights(per_light_graph());
  // "1 - light.directional": light 2 is directional.
  EXPECT_NE(std::find(plan.disabled.begin(), plan.disabled.end(), "blur#2"), plan.disabled.end());
  EXPECT_EQ(plan.disabled_by.at("blur#2"), "1 - scene.light2.directional");
  const PlannedPass& gather = pass_named(plan, "gather");
  EXPECT_EQ(resource_at(plan, gather, "lights[0]"), "blurred#0");
  EXPECT_EQ(resource_at(plan, gather, "lights[1]"), "blurred#1");
  EXPECT_EQ(resource_at(plan, gather, "lights[2]"), "(unbound)");
  // What only the culled instance would read is culled with it.
  EXPECT_NE(std::find(plan.culled.begin(), plan.culled.end(), "light_view#2"), plan.culled.end());
  EXPECT_EQ(plan.find_resource("blurred"), -1);  // the per-light resource itself is only its instances
}

// Each instance follows its own light (PlannedPass::lights), and what reads every light's instances
// follows them all; moving another light leaves an instance (RunPolicy.MovingOneLight...).
TEST(PerLight, EachInstanceFollowsItsOwnLight) {
  const Plan plan = compile_for_lights(per_light_graph());
  EXPECT_EQ(pass_named(plan, "light_view#1").lights, 1u << 1);
  EXPECT_EQ(pass_named(plan, "blur#1").lights, 1u << 1) << "through its input";
  EXPECT_EQ(pass_named(plan, "gather").lights, (1u << 0) | (1u << 1)) << "light 2's instance is disabled";
  EXPECT_EQ(pass_named(plan, "camera").lights, kAllLights) << "a pass that does not follow the lights";
}

TEST(PerLight, WithoutASceneThereIsOneLight) {
  const Plan plan = compile_for_lights(per_light_graph(), typical_scene_values());
  EXPECT_EQ(plan.find_resource("view#1"), -1);
  EXPECT_EQ(resource_at(plan, pass_named(plan, "gather"), "lights[0]"), "blurred#0");
}

TEST(PerLight, OneResourceOnAPerLightPortIsElementZero) {
  nlohmann::json g = per_light_graph();
  g["passes"][0]["inputs"]["lights"] = "base";
  g["passes"][0]["inputs"]["base"] = "base";
  const std::string error = per_light_error(g);
  // The same image on two ports of one pass is refused as before, but by its element's name.
  EXPECT_NE(error.find("binds 'base' to two ports ('base' and 'lights')"), std::string::npos) << error;
  g["resources"]["other"] = {{"type", "image"}, {"format", "rgba16f"}};
  g["passes"].push_back({{"name", "other"}, {"type", "source"}, {"outputs", {{"color", "other"}}}});
  g["passes"][0]["inputs"]["lights"] = "other";
  const Plan plan = compile_for_lights(g);
  EXPECT_EQ(resource_at(plan, pass_named(plan, "gather"), "lights[0]"), "other");
}

TEST(PerLight, PartsThatDoNotFitTogetherAreRefusedAtTheirPlace) {
  auto expect_error = [](const nlohmann::json& g, const std::string& where, const std::string& what) {
    const std::string error = per_light_error(g);
    EXPECT_NE(error.find(where), std::string::npos) << error;
    EXPECT_NE(error.find(what), std::string::npos) << error;
  };
  nlohmann::json once_writes = per_light_graph();
  once_writes["passes"][1]["outputs"]["color"] = "view";
  expect_error(once_writes, "/passes/1/outputs/color", "'view' is a per-light resource (one image per light), which only a pass");
  nlohmann::json each_writes_one = per_light_graph();
  each_writes_one["passes"][2]["outputs"]["color"] = "base";
  expect_error(each_writes_one, "/passes/2/outputs/color", "runs once per light and writes 'base', which is one resource");
  nlohmann::json one_port = per_light_graph();
  one_port["passes"][0]["inputs"]["base"] = "view";
  expect_error(one_port, "/passes/0/inputs/base", "'view' is a per-light resource (one per light), and port 'base'");
  nlohmann::json output = per_light_graph();
  output["outputs"] = {"view"};
  expect_error(output, "/outputs/0", "'view' is a per-light resource (one image per light), which a graph output cannot be");
  nlohmann::json misspelt = per_light_graph();
  misspelt["passes"][2]["for_each"] = "lights";
  expect_error(misspelt, "/passes/2/for_each", "unknown \"for_each\" 'lights' (did you mean 'light'?)");
  nlohmann::json unknown = per_light_graph();
  unknown["passes"][3]["enabled"] = "light.spott";
  expect_error(unknown, "/passes/3/enabled", "spott");
}

TEST(PerLight, ExpressionsReadTheirLightsValuesAndNothingElse) {
  EXPECT_EQ(light_instance("shadow", 3), "shadow#3");
  EXPECT_EQ(port_element("shadow", 3), "shadow[3]");
  EXPECT_EQ(split_port_element("shadow[12]"), (std::pair<std::string, int>{"shadow", 12}));
  EXPECT_EQ(split_port_element("shadow"), (std::pair<std::string, int>{"shadow", -1}));
  EXPECT_EQ(split_port_element("shadow[x]"), (std::pair<std::string, int>{"shadow[x]", -1}));
  nlohmann::json g = per_light_graph();
  // light.index, and a name that only ends in "light." is not the light's.
  g["parameters"] = {{"spotlight", {{"type", "int"}, {"default", 2}, {"min", 0}, {"max", 8}}}};
  g["passes"][3]["params"]["radius"] = "light.index * 4 + spotlight";
  const Plan plan = compile_for_lights(g);
  EXPECT_EQ(pass_named(plan, "blur#0").params["radius"], 2);
  EXPECT_EQ(pass_named(plan, "blur#1").params["radius"], 6);
}

// An instance's expressions are read as written: a mistake in one is quoted in the user's words
// (not "scene.light0.view"), a misspelt light name is offered its light's spelling, and the plan
// still says with the light's own names why an instance is off.
TEST(PerLight, AMistakeInAnInstancesExpressionIsQuotedAsWritten) {
  nlohmann::json g = per_light_graph();
  g["passes"][3]["enabled"] = "light.spot * nosuch";
  const std::string unknown = per_light_error(g);
  EXPECT_NE(unknown.find("in expression \"light.spot * nosuch\""), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("unknown name 'nosuch'"), std::string::npos) << unknown;
  EXPECT_EQ(unknown.find("scene.light"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("/passes/3/enabled"), std::string::npos) << unknown;
  g["passes"][3]["enabled"] = "light.sopt";
  const std::string misspelt = per_light_error(g);
  EXPECT_NE(misspelt.find("did you mean 'light.spot'"), std::string::npos) << misspelt;
  g["resources"]["view"]["height"] = "16 * light.pointt";
  g["passes"][3]["enabled"] = "1";
  const std::string resource = per_light_error(g);
  EXPECT_NE(resource.find("in expression \"16 * light.pointt\""), std::string::npos) << resource;
  EXPECT_NE(resource.find("did you mean 'light.point'"), std::string::npos) << resource;
  // A pass made once has no light to read.
  g = per_light_graph();
  g["passes"][0]["enabled"] = "light.spot";
  EXPECT_NE(per_light_error(g).find("unknown name 'light.spot'"), std::string::npos) << per_light_error(g);
  const Plan plan = compile_for_lights(per_light_graph());
  EXPECT_EQ(plan.disabled_by.at("blur#2"), "1 - scene.light2.directional");
}

// A point light's shadow drawn into an image of one layer (a graph made for spot lights) compiles,
// and the plan says that the light stays unshadowed; the bundled graphs' per-light maps say nothing
// (a receiver map of one layer is the caustic view's, not a shadow).
TEST(PerLight, APointLightsShadowInOneLayerIsWarnedOf) {
  CompileOptions options;
  options.scene_values = three_lights();
  options.scene_values["scene.light1.view"] = 1;  // the point light's caustic view is fitted
  auto warnings_with = [&](bool cube) {
    nlohmann::json g = nlohmann::json::parse(std::ifstream(std::string(CAUSTICA_SOURCE_DIR) + "/graphs/caustics_adaptive.json"));
    if (!cube) g["resources"]["shadow"].erase("layers");
    return compile_graph(load_graph(JsonDocument::parse(g.dump(2), "lights.json")), passes::builtin_registry(), options).warnings;
  };
  const std::vector<std::string> cube = warnings_with(true);
  EXPECT_TRUE(cube.empty()) << cube.front();
  const std::vector<std::string> flat = warnings_with(false);
  ASSERT_EQ(flat.size(), 1u);
  EXPECT_NE(flat[0].find("pass 'shadow#1' draws light 1's shadow into 'shadow#1', which has one layer; light 1 is a point light"),
            std::string::npos)
      << flat[0];
}

namespace {
// three_lights() whose light `light` stands among its refractors and throws its caustics through
// three cube faces: caustic views 0..2 are the lights', views 3 and 4 that light's further faces.
// As the scene gives them: each view's .light, .face and .view; the compiler adds its light's others.
std::map<std::string, double> with_cube_faces(int light) {
  std::map<std::string, double> values = three_lights();
  values["scene.light" + std::to_string(light) + ".view"] = 1;
  values["scene.caustic_views"] = 5;
  const int lights_of[] = {0, 1, 2, light, light};
  for (int k = 0; k < 5; ++k) {
    const std::string to = "scene.caustic" + std::to_string(k) + ".";
    values[to + "view"] = values["scene.light" + std::to_string(lights_of[k]) + ".view"];
    values[to + "light"] = lights_of[k];
    values[to + "face"] = lights_of[k] == light ? k : -1;
  }
  return values;
}
}  // namespace

// Every bundled caustic graph throws each caustic view's caustic through its own instances
// (receivers, light-view refractors, photons, their maps), which lighting reads as its per-view
// ports: a point light among its refractors (light 1) through each of its cube faces, each
// instance its light's; the shadows stay one per light. A light without a caustic view gets none.
TEST(PerLight, EveryBundledCausticGraphGivesEachCausticViewItsPasses) {
  for (const char* name : {"caustics_regular", "caustics_adaptive", "caustics_progressive", "caustics_raytraced", "full_hybrid"}) {
    SCOPED_TRACE(name);
    const GraphDesc graph = load_graph_file(std::string(CAUSTICA_SOURCE_DIR) + "/graphs/" + name + ".json");
    CompileOptions options;
    options.scene_values = with_cube_faces(1);
    options.ray_queries = true;
    const Plan all = compile_graph(graph, passes::builtin_registry(), options);
    EXPECT_TRUE(all.warnings.empty()) << all.warnings.front();
    const PlannedPass& lighting = pass_named(all, "lighting");
    const int lights_of[] = {0, 1, 2, 1, 1};
    for (uint32_t view = 0; view < 5; ++view) {
      for (const char* pass : {"receivers", "light_refractors"}) {
        EXPECT_EQ(pass_named(all, light_instance(pass, view)).params["light"], view) << pass;
        EXPECT_EQ(all.instances.at(light_instance(pass, view)).light, lights_of[view]) << pass;
      }
      const auto map = lighting.ports.find(port_element("caustics", view));
      ASSERT_NE(map, lighting.ports.end()) << "view " << view;
      EXPECT_EQ(all.resources[map->second].name, light_instance("caustics", view));
      EXPECT_EQ(all.resources[lighting.ports.at(port_element("caustic_depth", view))].name, light_instance("receiver_depth", view));
    }
    // Moving light 1 re-runs its three faces' passes, and no other light's.
    EXPECT_EQ(pass_named(all, "light_refractors#4").lights, 1u << 1);
    EXPECT_EQ(all.find_resource("shadow#3"), -1);
    EXPECT_EQ(pass_named(all, "shadow#1").params["light"], 1);

    options.scene_values = three_lights();  // light 1 without a view: one view per light, its own
    const Plan unviewed = compile_graph(graph, passes::builtin_registry(), options);
    EXPECT_EQ(unviewed.disabled_by.at("light_refractors#1"), "scene.caustic1.view * scene.caustic1.refractors");
    EXPECT_FALSE(lighting_reads(unviewed, "caustics", 1));
    EXPECT_TRUE(lighting_reads(unviewed, "caustics", 2));
    EXPECT_FALSE(lighting_reads(unviewed, "caustics", 3));
    EXPECT_TRUE(unviewed.warnings.empty()) << unviewed.warnings.front();
  }
}

// A graph whose caustic passes are made once draws from caustic view 0 alone: light 0's first
// cube face of three, and the plan says that the rest of its caustic is lost.
TEST(PerLight, AGraphThatDrawsOneOfAPointLightsFacesIsWarnedOf) {
  CompileOptions options;
  options.scene_values = with_cube_faces(0);
  const GraphDesc graph = load_graph_file(std::string(CAUSTICA_SOURCE_DIR) + "/graphs/examples/caustic_filter.json");
  const Plan plan = compile_graph(graph, passes::builtin_registry(), options);
  ASSERT_EQ(plan.warnings.size(), 1u);
  EXPECT_NE(plan.warnings[0].find("light 0 is a point light among its refractors, which throws its caustics through 3 cube faces"),
            std::string::npos)
      << plan.warnings[0];
  EXPECT_NE(plan.warnings[0].find("the graph draws from 1 of them"), std::string::npos) << plan.warnings[0];
  options.scene_values = three_lights();
  EXPECT_TRUE(compile_graph(graph, passes::builtin_registry(), options).warnings.empty());
}

// Per-view parts bind per-light ones as their light's, and refuse what has no one answer.
TEST(PerLight, AViewsInstanceReadsItsLightsAndALightsCannotReadAView) {
  nlohmann::json g = per_light_graph();
  g["resources"]["face"] = {{"type", "image"}, {"format", "rgba16f"}, {"for_each", "caustic_view"}, {"width", "16"}, {"height", "16"}};
  g["passes"].push_back({{"name", "per_face"},
                         {"type", "filter"},
                         {"for_each", "caustic_view"},
                         {"params", {{"radius", "$light"}}},
                         {"inputs", {{"source", "view"}}},
                         {"outputs", {{"target", "face"}}}});
  g["passes"][0]["inputs"]["lights"] = "face";
  CompileOptions options;
  options.output_width = 64;
  options.output_height = 32;
  options.scene_values = with_cube_faces(1);
  const Plan plan = compile_graph(load_graph(JsonDocument::parse(g.dump(2), "lights.json")), lights_registry(), options);
  EXPECT_EQ(resource_at(plan, pass_named(plan, "per_face#4"), "source"), "view#1") << "view 4 is light 1's";
  EXPECT_EQ(pass_named(plan, "per_face#4").params["radius"], 4);
  EXPECT_EQ(resource_at(plan, pass_named(plan, "gather"), "lights[4]"), "face#4");
  nlohmann::json light_reads_view = per_light_graph();
  light_reads_view["resources"]["face"] = g["resources"]["face"];
  light_reads_view["passes"][3]["inputs"]["source"] = "face";
  const std::string error = per_light_error(light_reads_view);
  EXPECT_NE(error.find("/passes/3/inputs/source"), std::string::npos) << error;
  EXPECT_NE(error.find("pass 'blur' runs once per light and reads 'face', one per caustic view"), std::string::npos) << error;
}
