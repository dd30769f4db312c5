// User passes (compute and fullscreen passes whose shader the graph names): the compiler's checks
// against the shader on the CPU, with a deliberately wrong shader or declaration for each error,
// and the bundled examples rendered on lavapipe with validation on.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "builtin_passes.h"
#include "graph/compiler.h"
#include "graph/user_pass_type.h"
#include "plan_queries.h"
#include "scene_engine.h"

using namespace caustica;
using namespace caustica::graph;
using test::pass_named;

namespace {

// A folder of its own per test, for the graph and its shader.
std::filesystem::path test_dir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  auto dir = std::filesystem::temp_directory_path() / ("caustica_user_pass_" + std::to_string(::getpid())) / info->name();
  std::filesystem::create_directories(dir);
  return dir;
}

void write(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path) << text;
}

// pattern -> a user compute pass that scales the image -> out.
const char* kScaleShader = R"(#version 460
layout(local_size_x = 8, local_size_y = 4) in;
layout(binding = 0) uniform sampler2D source;
layout(binding = 1, rgba16f) uniform writeonly image2D target;
layout(push_constant) uniform Params {
  float gain;
  int unused_count;
} params;
void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  imageStore(target, p, params.gain * texelFetch(source, p, 0) + float(params.unused_count));
}
)";

nlohmann::json scale_graph() {
  return {{"resources",
           {{"color", {{"type", "image"}, {"format", "rgba16f"}}},
            {"scaled", {{"type", "image"}, {"format", "rgba16f"}}},
            {"unused", {{"type", "image"}, {"format", "rgba16f"}}}}},
          {"passes",
           {{{"name", "pattern"}, {"type", "pattern"}, {"outputs", {{"color", "color"}}}},
            {{"name", "scale"},
             {"type", "compute"},
             {"shader", "scale.comp"},
             {"ports", {{"source", {{"access", "read"}}}, {"target", {{"access", "write"}, {"formats", {"rgba16f"}}}}}},
             {"parameters",
              {{"gain", {{"type", "float"}, {"default", 1.0}, {"min", 0.0}, {"max", 8.0}}},
               {"unused_count", {{"type", "int"}, {"default", 0}}}}},
             {"params", {{"gain", 2.0}}},
             {"dispatch", {"output.width", "output.height / 2 + gain"}},
             {"inputs", {{"source", "color"}}},
             {"outputs", {{"target", "scaled"}}}},
            {{"name", "stray"},
             {"type", "compute"},
             {"shader", "scale.comp"},
             {"ports", {{"source", {{"access", "read"}}}, {"target", {{"access", "write"}}}}},
             {"parameters", {{"gain", {{"type", "float"}, {"default", 1.0}}}, {"unused_count", {{"type", "int"}, {"default", 0}}}}},
             {"dispatch", "target"},
             {"inputs", {{"source", "color"}}},
             {"outputs", {{"target", "unused"}}}}}},
          {"outputs", {"scaled"}}};
}

Plan compile_in(const std::filesystem::path& dir, const nlohmann::json& graph, CompileOptions options = {}) {
  write(dir / "graph.json", graph.dump(2));
  options.output_width = 64;
  options.output_height = 32;
  return compile_graph(load_graph_file((dir / "graph.json").string()), passes::builtin_registry(), options);
}

std::string error_of(const std::filesystem::path& dir, const nlohmann::json& graph) {
  try {
    compile_in(dir, graph);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

// `text` with every `from` made `to`; there must be one.
std::string replaced(std::string text, const std::string& from, const std::string& to) {
  EXPECT_NE(text.find(from), std::string::npos) << from;
  for (size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size())) text.replace(at, from.size(), to);
  return text;
}

TEST(UserPass, CompilesAsABuiltInPassDoes) {
  const auto dir = test_dir();
  write(dir / "scale.comp", kScaleShader);
  CompileOptions reuse;
  reuse.reuse_unchanged_passes = true;
  const Plan plan = compile_in(dir, scale_graph(), reuse);
  // Culled like a built-in pass: "stray" reaches no output.
  ASSERT_EQ(plan.passes.size(), 2u);
  EXPECT_EQ(plan.culled, std::vector<std::string>{"stray"});
  const PlannedPass& scale = pass_named(plan, "scale");
  EXPECT_EQ(scale.type, "compute");
  EXPECT_EQ(scale.params["gain"], 2.0);
  EXPECT_EQ(scale.params["unused_count"], 0);
  // The target was written by a storage write, then read back as the output: a barrier before the
  // compute pass moves "color" from attachment to sampled.
  ASSERT_FALSE(scale.barriers.empty());
  EXPECT_EQ(scale.barriers[0].new_layout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  // Its type holds its shader's reflection: bindings by port, local size, the push block's members
  // at their offsets, and the invocations its dispatch expressions give (32 / 2 + gain 2).
  const UserShader& shader = *scale.decl->user_shader;
  EXPECT_EQ(shader.local_size, (std::array<uint32_t, 3>{8, 4, 1}));
  EXPECT_EQ(shader.invocations, (std::array<uint32_t, 3>{64, 18, 1}));
  ASSERT_EQ(shader.params.size(), 2u);
  EXPECT_EQ(shader.params[1].name, "unused_count");
  EXPECT_EQ(shader.params[1].offset, 4u);
  EXPECT_EQ(shader.params_bytes, 8u);
  EXPECT_FALSE(shader.params_block);
  ASSERT_EQ(shader.bindings.size(), 2u);
  // No scene: what it computes follows from its input and parameters, so a plan may reuse it.
  EXPECT_TRUE(scale.reusable(true));
  EXPECT_NE(plan_to_dot(plan).find("scale"), std::string::npos);

  // An edited shader is a different result: its key changes, an unchanged one keeps it.
  const std::optional<graph::ResultIdentity> key = scale.result_id;
  ASSERT_TRUE(key.has_value());
  EXPECT_EQ(pass_named(compile_in(dir, scale_graph(), reuse), "scale").result_id, key);
  write(dir / "scale.comp", replaced(kScaleShader, "params.gain *", "0.5 * params.gain *"));
  EXPECT_NE(pass_named(compile_in(dir, scale_graph(), reuse), "scale").result_id, key);
}

TEST(UserPass, ACompileErrorNamesTheUsersFileAndLine) {
  const auto dir = test_dir();
  write(dir / "scale.comp", replaced(kScaleShader, "float(params.unused_count)", "undeclared_thing"));
  const std::string error = error_of(dir, scale_graph());
  EXPECT_NE(error.find("graph.json:"), std::string::npos) << error;
  // One message: the shader's file and line once, none of glslang's "ERROR: " or summary lines.
  const std::string shader = (dir / "scale.comp").string();
  EXPECT_NE(error.find("the shader of pass 'scale' does not compile: " + shader +
                       ":11: 'undeclared_thing' : undeclared identifier (at /passes/1/shader)"),
            std::string::npos)
      << error;
  EXPECT_EQ(error.find("ERROR"), std::string::npos) << error;
  EXPECT_EQ(error.find("compilation terminated"), std::string::npos) << error;
  EXPECT_EQ(error.find("shader compile failed"), std::string::npos) << error;
}

TEST(UserPass, APortWithoutABindingIsRefused) {
  const auto dir = test_dir();
  write(dir / "scale.comp", replaced(kScaleShader, "source", "sauce"));
  const std::string error = error_of(dir, scale_graph());
  EXPECT_NE(error.find("port 'source' of pass 'scale' has no binding in " + (dir / "scale.comp").string() +
                       ": it declares no sampled image (sampler2D) named 'source' (did you mean 'sauce'?)"),
            std::string::npos)
      << error;
}

TEST(UserPass, ABindingOfTheWrongKindIsRefused) {
  const auto dir = test_dir();
  write(dir / "scale.comp", replaced(replaced(kScaleShader, "layout(binding = 0) uniform sampler2D source;",
                                              "layout(binding = 0, rgba16f) readonly uniform image2D source;"),
                                     "texelFetch(source, p, 0)", "imageLoad(source, p)"));
  const std::string error = error_of(dir, scale_graph());
  EXPECT_NE(error.find("port 'source' of pass 'scale' is a sampled image (sampler2D), but " + (dir / "scale.comp").string() +
                       ":3: 'source' is a storage image (image2D)"),
            std::string::npos)
      << error;
}

TEST(UserPass, ABindingWithoutAPortIsRefused) {
  const auto dir = test_dir();
  write(dir / "scale.comp", replaced(kScaleShader, "layout(push_constant)",
                                     "layout(binding = 2) readonly buffer Extra { float extra[]; };\nlayout(push_constant)"));
  const std::string error = error_of(dir, scale_graph());
  EXPECT_NE(error.find((dir / "scale.comp").string() +
                       ":5: binding 2 'Extra', a storage buffer (buffer block), is no port of pass 'scale'; declare it under \"ports\""),
            std::string::npos)
      << error;
}

TEST(UserPass, AFormatTheShaderContradictsIsRefused) {
  const auto dir = test_dir();
  write(dir / "scale.comp", replaced(kScaleShader, "binding = 1, rgba16f", "binding = 1, r32f"));
  const std::string error = error_of(dir, scale_graph());
  EXPECT_NE(error.find("format mismatch: port 'target' of pass 'scale' takes rgba16f, but " + (dir / "scale.comp").string() +
                       ":4: 'target' is declared r32f"),
            std::string::npos)
      << error;
}

TEST(UserPass, APushConstantBlockThatDoesNotMatchTheParametersIsRefused) {
  const auto dir = test_dir();
  const std::string file = (dir / "scale.comp").string();
  // A member no parameter declares, and so a parameter the block lacks.
  write(dir / "scale.comp", replaced(kScaleShader, "gain", "gane"));
  std::string error = error_of(dir, scale_graph());
  EXPECT_NE(error.find(file + ":6: member 'gane' of push-constant block 'Params' is no parameter of pass 'scale' (did you mean 'gain'?)"),
            std::string::npos)
      << error;
  EXPECT_NE(error.find("parameter 'gain' of pass 'scale' is not in push-constant block 'Params' (" + file + ":5)"), std::string::npos)
      << error;
  // A member of another type than its parameter's.
  write(dir / "scale.comp", replaced(replaced(kScaleShader, "float gain;", "vec2 gain;"), "params.gain *", "params.gain.x *"));
  error = error_of(dir, scale_graph());
  EXPECT_NE(error.find(file + ":6: member 'gain' of push-constant block 'Params' is vec2, and parameter 'gain' (float) needs float"),
            std::string::npos)
      << error;
}

TEST(UserPass, ReadPortsMustBeReadonlyAndTheDispatchAPort) {
  const auto dir = test_dir();
  write(dir / "scale.comp", kScaleShader);
  nlohmann::json graph = scale_graph();
  graph["passes"][1]["dispatch"] = "targte";
  std::string error = error_of(dir, graph);
  EXPECT_NE(error.find("\"dispatch\": 'targte' is no image port of pass 'scale' (did you mean 'target'?)"), std::string::npos) << error;
  // A storage image written by a shader whose port says it only reads it would escape the plan's barriers.
  write(dir / "scale.comp", replaced(kScaleShader, "uniform writeonly image2D target", "uniform image2D target"));
  graph = scale_graph();
  graph["passes"][1]["ports"]["target"]["access"] = "read";
  graph["passes"][1]["ports"]["target"]["usage"] = "storage";
  graph["passes"][1]["inputs"]["target"] = "color";
  graph["passes"][1]["outputs"].erase("target");
  error = error_of(dir, graph);
  EXPECT_NE(error.find("port 'target' of pass 'scale' is read, but " + (dir / "scale.comp").string() + ":4: 'target' is not readonly"),
            std::string::npos)
      << error;
}

TEST(UserPass, DeclarationsAreCheckedWithTheirPlaceInTheFile) {
  const auto dir = test_dir();
  write(dir / "scale.comp", kScaleShader);
  nlohmann::json graph = scale_graph();
  graph["passes"][1]["ports"]["source"]["acess"] = "read";
  std::string error = error_of(dir, graph);
  EXPECT_NE(error.find("/passes/1/ports/source/acess"), std::string::npos) << error;
  EXPECT_NE(error.find("unknown member 'acess' in a port (did you mean 'access'?)"), std::string::npos) << error;
  graph = scale_graph();
  graph["passes"][0]["shader"] = "scale.comp";
  error = error_of(dir, graph);
  EXPECT_NE(error.find("\"shader\" is for passes of type compute or fullscreen"), std::string::npos) << error;
  graph = scale_graph();
  graph["passes"][1]["shader"] = "missing.comp";
  error = error_of(dir, graph);
  EXPECT_NE(error.find("shader 'missing.comp' of pass 'scale' is neither beside the graph"), std::string::npos) << error;
}

// scale without parameters, counting the texels it copies and summing their red channel.
const char* kCountingShader = R"(#version 460
#extension GL_EXT_shader_atomic_float : require
layout(local_size_x = 8, local_size_y = 4) in;
layout(binding = 0) uniform sampler2D source;
layout(binding = 1, rgba16f) uniform writeonly image2D target;
layout(binding = 2, std430) buffer Counts { uint counters[]; };
layout(binding = 3, std430) buffer Sums { float sums[]; };
void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  vec4 v = texelFetch(source, p, 0);
  imageStore(target, p, v);
  atomicAdd(counters[0], 1u);
  atomicAdd(sums[1], v.r);
}
)";

nlohmann::json counting_graph() {
  nlohmann::json graph = scale_graph();
  auto& pass = graph["passes"][1];
  pass["shader"] = "count.comp";
  pass.erase("parameters");
  pass.erase("params");
  pass["dispatch"] = "target";
  pass["counters"] = {"texels", {{"name", "red"}, {"kind", "sum"}}};
  graph["passes"].erase(2);
  return graph;
}

TEST(UserPass, CountersAreCheckedAgainstTheShadersCounterBuffer) {
  const auto dir = test_dir();
  write(dir / "count.comp", kCountingShader);
  const Plan plan = compile_in(dir, counting_graph());
  const UserShader& shader = *pass_named(plan, "scale").decl->user_shader;
  ASSERT_EQ(shader.counters.size(), 2u);
  EXPECT_EQ(shader.counters[1].name, "red");
  EXPECT_TRUE(shader.counters[1].sum);
  ASSERT_TRUE(shader.counts_buffer && shader.sums_buffer);
  EXPECT_EQ(shader.counts_buffer->binding, 2u);
  EXPECT_EQ(shader.sums_buffer->binding, 3u);

  // A sum without the float view of the buffer.
  write(dir / "count.comp", replaced(replaced(kCountingShader, "layout(binding = 3, std430) buffer Sums { float sums[]; };\n", ""),
                                     "atomicAdd(sums[1], v.r);", ""));
  std::string error = error_of(dir, counting_graph());
  EXPECT_NE(error.find("graph.json:14:19: pass 'scale' declares counters, and " + (dir / "count.comp").string() +
                       " declares no counter buffer layout(set = 0, binding = N) buffer Sums { float sums[]; } for its sums "
                       "(at /passes/1/counters)"),
            std::string::npos)
      << error;
  // The counts as floats.
  write(dir / "count.comp", replaced(replaced(kCountingShader, "uint counters[]", "float counters[]"), "1u);", "1.0);"));
  error = error_of(dir, counting_graph());
  EXPECT_NE(error.find((dir / "count.comp").string() +
                       ":6: member 'counters' of counter buffer 'Counts' is float[]; the counter buffer is uint counters[] (counts) or "
                       "float sums[] (sums)"),
            std::string::npos)
      << error;
  // A counter buffer, and no counters declared.
  write(dir / "count.comp", kCountingShader);
  nlohmann::json graph = counting_graph();
  graph["passes"][1].erase("counters");
  error = error_of(dir, graph);
  EXPECT_NE(error.find((dir / "count.comp").string() +
                       ":6: binding 2 'Counts', a storage buffer (buffer block), is no port of pass 'scale'; declare it under "
                       "\"ports\", or the counters the shader adds to under \"counters\""),
            std::string::npos)
      << error;
  // What the graph file says of a counter.
  graph = counting_graph();
  graph["passes"][1]["counters"][1]["kind"] = "summ";
  error = error_of(dir, graph);
  EXPECT_NE(error.find("unknown counter kind 'summ' (did you mean 'sum'?) (at /passes/1/counters/1/kind)"), std::string::npos) << error;
  graph["passes"][1]["counters"] = {"texels", "texels"};
  error = error_of(dir, graph);
  EXPECT_NE(error.find("two counters are named 'texels' (at /passes/1/counters/1)"), std::string::npos) << error;
}

// The bundled examples on the device, validation on (SceneEngine fails on any message).
TEST(UserPass, TheBackDepthViewShowsTheRefractorsBackSurfaces) {
  test::SceneEngine e;
  e.render(load_graph_file((data_dir() / "graphs/examples/back_depth_view.json").string()), test::load_bundled_scene("sphere_plane"),
           {"light_back"});
  const io::ImageData back = e.executor.read_image("light_back");
  const io::ImageData view = e.executor.read_image("view");
  ASSERT_EQ(view.rgba.size(), back.rgba.size());
  // Grey exactly where the light sees a back surface, black elsewhere.
  size_t surfaces = 0, mismatched = 0;
  for (size_t i = 0; i < back.rgba.size(); i += 4) {
    const bool surface = back.rgba[i + 1] > 0.0f;
    surfaces += surface;
    mismatched += surface != (view.rgba[i] > 0.0f);
  }
  EXPECT_GT(surfaces, back.rgba.size() / 4 / 20);
  EXPECT_EQ(mismatched, 0u);
}

TEST(UserPass, TheCausticFilterSmoothsTheMapAndKeepsItsFlux) {
  test::SceneEngine e;
  auto graph = load_graph_file((data_dir() / "graphs/examples/caustic_filter.json").string());
  apply_overrides(graph, {"grid=128", "caustic_size=128", "light_size=256", "shadow_size=256"});
  e.render(graph, test::load_bundled_scene("sphere_plane"), {"caustics", "filtered_caustics"});
  const io::ImageData map = e.executor.read_image("caustics");
  const io::ImageData filtered = e.executor.read_image("filtered_caustics");
  double flux = 0, filtered_flux = 0, peak = 0, filtered_peak = 0;
  for (size_t i = 0; i < map.rgba.size(); i += 4) {
    flux += static_cast<double>(map.rgba[i]);
    filtered_flux += static_cast<double>(filtered.rgba[i]);
    peak = std::max(peak, static_cast<double>(map.rgba[i]));
    filtered_peak = std::max(filtered_peak, static_cast<double>(filtered.rgba[i]));
  }
  ASSERT_GT(flux, 0.0);
  // The kernel's weights sum to one at each texel: the caustic, away from the map's edges, keeps its flux.
  EXPECT_NEAR(filtered_flux / flux, 1.0, 0.02);
  EXPECT_LT(filtered_peak, 0.7 * peak);
}

// Counters reach the frame's result as a built-in pass's do; a user pass's counters are its own.
TEST(UserPass, CountersReachTheFrameResult) {
  const auto dir = test_dir();
  write(dir / "count.comp", kCountingShader);
  write(dir / "graph.json", counting_graph().dump(2));
  test::SceneEngine e;
  const FrameResult frame = e.render(load_graph_file((dir / "graph.json").string()), test::load_bundled_scene("sphere_plane"), {"color"});
  const io::ImageData color = e.executor.read_image("color");
  double red = 0;
  for (size_t i = 0; i < color.rgba.size(); i += 4) red += static_cast<double>(color.rgba[i]);
  EXPECT_EQ(frame.counters.at("texels"), double(e.width) * e.height);
  ASSERT_GT(red, 0.0);
  EXPECT_NEAR(frame.counters.at("red") / red, 1.0, 1e-4);
  EXPECT_EQ(frame.counter_passes.at("texels"), "scale");

  // Two passes counting under one name: the copy of one pass's counters would overwrite the other's.
  nlohmann::json graph = counting_graph();
  nlohmann::json twice = graph["passes"][1];
  twice["name"] = "scale_again";
  twice["outputs"]["target"] = "unused";
  graph["passes"].push_back(twice);
  graph["outputs"].push_back("unused");
  write(dir / "graph.json", graph.dump(2));
  try {
    e.render(load_graph_file((dir / "graph.json").string()), test::load_bundled_scene("sphere_plane"), {});
    ADD_FAILURE() << "two passes counted under one name";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("counter 'texels' is pass 'scale''s too"), std::string::npos) << error.what();
  }
}

// One compute pass, `shader`, that writes the rgba32f image `image` (its port of that name) over the
// image, with the scene or without.
nlohmann::json one_image_pass(const std::string& pass, const std::string& shader, const std::string& image, bool scene, int width,
                              int height) {
  return {{"resources", {{image, {{"type", "image"}, {"format", "rgba32f"}, {"width", width}, {"height", height}}}}},
          {"passes",
           {{{"name", pass},
             {"type", "compute"},
             {"shader", shader},
             {"scene", scene},
             {"ports", {{image, {{"access", "write"}}}}},
             {"dispatch", image},
             {"outputs", {{image, image}}}}}},
          {"outputs", {image}}};
}

// A pass with "scene": true reads the scene's objects and vertices: each object's bounding box top
// corner from the objects, and again as the largest of its vertices, and the frame's light count.
TEST(UserPass, TheSceneBindingGivesTheScenesObjectsAndVertices) {
  const auto dir = test_dir();
  write(dir / "bounds.comp", R"(#version 460
#extension GL_GOOGLE_include_directive : require
#include "scene/scene.glsl"
SCENE_FRAME
SCENE_VERTICES
SCENE_OBJECTS
layout(local_size_x = 8, local_size_y = 2) in;
layout(binding = 3, rgba32f) uniform writeonly image2D bounds;
void main() {
  uint object = gl_GlobalInvocationID.x;
  if (object >= uint(objects.length())) return;
  vec3 high = objects[object].bounds_max_spread.xyz;
  if (gl_GlobalInvocationID.y == 1u) {
    high = vec3(-1e30);
    for (uint v = 0u; v < uint(vertices.length()); ++v) {
      if (uint(vertices[v].normal_object.w) == object) high = max(high, vertices[v].position_dn.xyz);
    }
  }
  imageStore(bounds, ivec2(gl_GlobalInvocationID.xy), vec4(high, float(frame.light_count)));
}
)");
  const nlohmann::json graph = one_image_pass("bounds", "bounds.comp", "bounds", true, 16, 2);
  write(dir / "graph.json", graph.dump(2));
  const auto scene = test::load_bundled_scene("two_refractors");
  ASSERT_LE(scene->objects.size(), 16u);
  test::SceneEngine e;
  e.render(load_graph_file((dir / "graph.json").string()), scene, {"bounds"});
  const io::ImageData bounds = e.executor.read_image("bounds");
  ASSERT_EQ(bounds.width, 16u);
  for (size_t o = 0; o < scene->objects.size(); ++o) {
    const glm::vec3 high = scene->objects[o].bounds_max;
    const float tolerance = 1e-5f * (1.0f + glm::length(high));
    for (size_t row = 0; row < 2; ++row) {
      const float* texel = &bounds.rgba[4 * (row * 16 + o)];
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(texel[c], high[c], tolerance) << "object " << o << " row " << row;
      EXPECT_EQ(texel[3], static_cast<float>(scene->lights.size()));
    }
  }
}

// Scale's graph with gain "frame.index + 1" run for three frames: frame k equals a fresh render
// with gain k + 1, bit for bit.
void expect_frame_k_as_a_fresh_render(const std::filesystem::path& dir, const nlohmann::json& graph) {
  write(dir / "graph.json", graph.dump(2));
  const auto scene = test::load_bundled_scene("sphere_plane");
  test::SceneEngine e;
  e.width = 32;
  e.height = 16;
  e.executor.set_scene(scene);
  e.executor.configure(load_graph_file((dir / "graph.json").string()), e.width, e.height, {.retained = {"scaled"}});
  std::vector<io::ImageData> frames;
  for (int k = 0; k < 3; ++k) {
    e.executor.run_frame(true);
    frames.push_back(e.executor.read_image("scaled"));
  }
  for (int k = 0; k < 3; ++k) {
    SCOPED_TRACE(k);
    nlohmann::json fresh = graph;
    fresh["passes"][1]["params"]["gain"] = k + 1;
    write(dir / "graph.json", fresh.dump(2));
    e.render(load_graph_file((dir / "graph.json").string()), scene, {"scaled"});
    EXPECT_EQ(frames[static_cast<size_t>(k)].rgba, e.executor.read_image("scaled").rgba);
  }
  EXPECT_NE(frames[0].rgba, frames[1].rgba);
}

// Per-frame parameters: a user pass's parameter may follow the frame, evaluated before each frame
// and pushed when the pass records; on frame k the pass gives what a fresh render with that value
// gives. A dispatch, fixed for the plan, may not name such a parameter.
TEST(UserPass, AParameterFollowsTheFrame) {
  const auto dir = test_dir();
  write(dir / "scale.comp", kScaleShader);
  nlohmann::json graph = scale_graph();
  graph["passes"][1]["params"]["gain"] = "frame.index + 1";
  EXPECT_NE(error_of(dir, graph)
                .find("\"dispatch\" of pass 'scale' names parameter 'gain', which follows the frame (\"frame.index + 1\"); "
                      "a dispatch is fixed for the plan"),
            std::string::npos)
      << error_of(dir, graph);
  graph["passes"][1]["dispatch"] = "target";
  expect_frame_k_as_a_fresh_render(dir, graph);
}

// Scale with its parameters in a uniform block at binding 2 instead of push constants.
std::string uniform_scale_shader() {
  return replaced(kScaleShader, "layout(push_constant) uniform Params", "layout(binding = 2) uniform Params");
}

// The same with the parameters in a uniform block: the pass writes its buffer each time it records.
TEST(UserPass, AParameterInAUniformBlockFollowsTheFrame) {
  const auto dir = test_dir();
  write(dir / "scale.comp", uniform_scale_shader());
  nlohmann::json graph = scale_graph();
  graph["passes"][1]["params"]["gain"] = "frame.index + 1";
  graph["passes"][1]["dispatch"] = "target";
  expect_frame_k_as_a_fresh_render(dir, graph);
}

// 40 float weights and a count in uniform block Params, beyond the 32 parameters of push
// constants; the last weight at an explicit offset, where only the reflection's offsets put it.
constexpr int kWeights = 40;

std::string weights_shader(bool fullscreen) {
  std::string text = "#version 460\nlayout(binding = 1) uniform Params {\n";
  for (int i = 0; i < kWeights - 1; ++i) text += "  float w" + std::to_string(i) + ";\n";
  text += "  layout(offset = 240) float w" + std::to_string(kWeights - 1) + ";\n  uint count;\n} params;\n";
  text += "float weighted(uint t) {\n  float sum = 0.0;\n";
  for (int i = 0; i < kWeights; ++i) {
    text += "  sum += params.w" + std::to_string(i) + " * float((t + " + std::to_string(i) + "u) % 5u + 1u);\n";
  }
  text += "  return sum;\n}\n";
  if (fullscreen) {
    return text + R"(layout(location = 0) out vec4 view;
void main() {
  uint t = uint(gl_FragCoord.y) * 8u + uint(gl_FragCoord.x);
  view = vec4(weighted(t), float(params.count), 0.0, 1.0);
}
)";
  }
  return text + R"(layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, rgba32f) uniform writeonly image2D sums;
void main() {
  uint t = gl_GlobalInvocationID.y * 8u + gl_GlobalInvocationID.x;
  imageStore(sums, ivec2(gl_GlobalInvocationID.xy), vec4(weighted(t), float(params.count), 0.0, 1.0));
}
)";
}

float weight(int i) {
  return 0.1f + 0.05f * static_cast<float>(i);
}

// On the device, a compute and a fullscreen pass with 41 parameters in a uniform block: each texel
// t holds the weights' sum times (t + i) % 5 + 1, as the CPU computes it, and the count.
// A fullscreen pass's fragment shader that shows its uv as colour, into an 8 x 4 image.
nlohmann::json uv_graph(const std::filesystem::path& dir, const std::string& input, const std::string& value = "vec4(uv, 0.0, 1.0)") {
  write(dir / "uv.frag", "#version 460\n" + input + "\nlayout(location = 0) out vec4 view;\nvoid main() { view = " + value + "; }\n");
  return {{"resources", {{"view", {{"type", "image"}, {"format", "rgba32f"}, {"width", 8}, {"height", 4}}}}},
          {"passes",
           {{{"name", "uv"},
             {"type", "fullscreen"},
             {"shader", "uv.frag"},
             {"ports", {{"view", {{"access", "write"}}}}},
             {"outputs", {{"view", "view"}}}}}},
          {"outputs", {"view"}}};
}

TEST(UserPass, TheFullscreenVertexStageGivesUvFromTheTopLeftCorner) {
  const auto dir = test_dir();
  write(dir / "graph.json", uv_graph(dir, "layout(location = 0) in vec2 uv;").dump(2));
  test::SceneEngine e;
  e.render(load_graph_file((dir / "graph.json").string()), test::load_bundled_scene("sphere_plane"), {"view"});
  const io::ImageData texels = e.executor.read_image("view");
  ASSERT_EQ(texels.rgba.size(), 4u * 8u * 4u);
  for (uint32_t y = 0; y < 4; ++y) {
    for (uint32_t x = 0; x < 8; ++x) {
      const size_t t = 4 * (y * 8 + x);
      EXPECT_NEAR(texels.rgba[t], (x + 0.5f) / 8.0f, 1e-5f) << x << "," << y;
      EXPECT_NEAR(texels.rgba[t + 1], (y + 0.5f) / 4.0f, 1e-5f) << x << "," << y;
    }
  }
}

TEST(UserPass, AFragmentInputTheVertexStageDoesNotGiveIsRefusedAtItsLine) {
  const auto dir = test_dir();
  const std::string shader = (dir / "uv.frag").string();
  const std::pair<const char*, const char*> inputs[] = {{"layout(location = 0) in vec3 uv;", "vec4(uv, 1.0)"},
                                                        {"layout(location = 1) in vec2 uv;", "vec4(uv, 0.0, 1.0)"},
                                                        {"layout(location = 0) in vec2 texcoord;", "vec4(texcoord, 0.0, 1.0)"}};
  for (const auto& [input, value] : inputs) {
    SCOPED_TRACE(input);
    const std::string error = error_of(dir, uv_graph(dir, input, value));
    EXPECT_NE(error.find(shader + ":2: fragment input '"), std::string::npos) << error;
    EXPECT_NE(error.find("is not given by a fullscreen pass's vertex stage, which gives only 'uv'"), std::string::npos) << error;
    EXPECT_NE(error.find("(at /passes/0/shader)"), std::string::npos) << error;
  }
}

TEST(UserPass, ParametersInAUniformBlockGoBeyondPushConstants) {
  const auto dir = test_dir();
  write(dir / "weights.comp", weights_shader(false));
  write(dir / "weights.frag", weights_shader(true));
  nlohmann::json parameters = {{"count", {{"type", "int"}, {"default", 0}}}};
  nlohmann::json params = {{"count", kWeights}};
  for (int i = 0; i < kWeights; ++i) {
    parameters["w" + std::to_string(i)] = {{"type", "float"}, {"default", 0.0}};
    params["w" + std::to_string(i)] = weight(i);
  }
  const nlohmann::json image = {{"type", "image"}, {"format", "rgba32f"}, {"width", 8}, {"height", 8}};
  const nlohmann::json graph = {{"resources", {{"sums", image}, {"view", image}}},
                                {"passes",
                                 {{{"name", "sums"},
                                   {"type", "compute"},
                                   {"shader", "weights.comp"},
                                   {"ports", {{"sums", {{"access", "write"}}}}},
                                   {"parameters", parameters},
                                   {"params", params},
                                   {"dispatch", "sums"},
                                   {"outputs", {{"sums", "sums"}}}},
                                  {{"name", "view"},
                                   {"type", "fullscreen"},
                                   {"shader", "weights.frag"},
                                   {"ports", {{"view", {{"access", "write"}}}}},
                                   {"parameters", parameters},
                                   {"params", params},
                                   {"outputs", {{"view", "view"}}}}}},
                                {"outputs", {"sums", "view"}}};
  write(dir / "graph.json", graph.dump(2));
  test::SceneEngine e;
  e.render(load_graph_file((dir / "graph.json").string()), test::load_bundled_scene("sphere_plane"), {"sums", "view"});
  for (const char* name : {"sums", "view"}) {
    SCOPED_TRACE(name);
    const io::ImageData texels = e.executor.read_image(name);
    ASSERT_EQ(texels.rgba.size(), 4u * 64u);
    for (uint32_t t = 0; t < 64; ++t) {
      float sum = 0.0f;
      for (int i = 0; i < kWeights; ++i) sum += weight(i) * static_cast<float>((t + static_cast<uint32_t>(i)) % 5u + 1u);
      EXPECT_NEAR(texels.rgba[4 * t], sum, 1e-6 * static_cast<double>(sum)) << "texel " << t;
      EXPECT_EQ(texels.rgba[4 * t + 1], static_cast<float>(kWeights)) << "texel " << t;
    }
  }
}

// A uniform parameter block is checked as the push-constant block is, and where it binds.
TEST(UserPass, AUniformParameterBlockIsCheckedAsThePushConstantsAre) {
  const auto dir = test_dir();
  const std::string file = (dir / "scale.comp").string();
  const std::string shader = uniform_scale_shader();
  write(dir / "scale.comp", shader);
  const Plan plan = compile_in(dir, scale_graph());  // holds the pass type, and so its shader
  const UserShader& compiled = *pass_named(plan, "scale").decl->user_shader;
  ASSERT_TRUE(compiled.params_block);
  EXPECT_EQ(compiled.params_block->binding, 2u);
  EXPECT_EQ(compiled.params_bytes, 8u);
  auto refused = [&](const std::string& text, const std::vector<std::string>& expected) {
    write(dir / "scale.comp", text);
    const std::string error = error_of(dir, scale_graph());
    for (const auto& message : expected) EXPECT_NE(error.find(message), std::string::npos) << error;
  };
  // A member no parameter declares, and so a parameter the block lacks.
  refused(replaced(shader, "gain", "gane"),
          {file + ":6: member 'gane' of uniform block 'Params' is no parameter of pass 'scale' (did you mean 'gain'?)",
           "parameter 'gain' of pass 'scale' is not in uniform block 'Params' (" + file + ":5)"});
  // A member that is no 4-byte scalar.
  refused(replaced(shader, "int unused_count;", "int unused_count;\n  vec4 tint;"),
          {file + ":8: member 'tint' of uniform block 'Params' is vec4; a parameter block holds 4-byte scalars (float, int, uint, "
                  "bool), one per parameter"});
  // Parameters in two places.
  refused(replaced(shader, "layout(binding = 2) uniform Params",
                   "layout(push_constant) uniform Push { float gain; } push;\nlayout(binding = 2) uniform Params"),
          {file + ":6: uniform block 'Params' holds the parameters of pass 'scale', and so does push-constant block 'Push' (" + file +
           ":5); declare the parameters in one of them"});
  // A port at the block's binding.
  refused(replaced(shader, "layout(binding = 2) uniform Params", "layout(binding = 1) uniform Params"),
          {file + ":4: 'target' takes binding 1, which uniform block 'Params' has (" + file +
           ":5), the parameters of pass 'scale'; bind 'target' at another binding"});
  // Above what every device's uniform buffers hold.
  refused(replaced(shader, "int unused_count;", "layout(offset = 16384) int unused_count;"),
          {file + ":5: uniform block 'Params' is 16388 bytes; a parameter block may have 16384 (the uniform buffer range every device "
                  "allows)"});
}

// A shader that samples the scene's textures (set 1) and traces its acceleration structure (binding
// 14) with ray queries itself, as scene/trace_ray_query.glsl declares it, written out here so that
// each line is known.
const char* kTracingShader = R"(#version 460
#extension GL_EXT_ray_query : require
#extension GL_EXT_nonuniform_qualifier : require
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 3, rgba32f) uniform writeonly image2D hits;
layout(set = 0, binding = 14) uniform accelerationStructureEXT tlas;
layout(set = 1, binding = 0) uniform sampler2D textures[];
void main() {
  rayQueryEXT query;
  rayQueryInitializeEXT(query, tlas, gl_RayFlagsOpaqueEXT, 0xFFu, vec3(0.0, 100.0, 0.0), 0.0, vec3(0.0, -1.0, 0.0), 1e30);
  while (rayQueryProceedEXT(query)) {}
  float t = rayQueryGetIntersectionTypeEXT(query, true) == gl_RayQueryCommittedIntersectionNoneEXT ? -1.0 : rayQueryGetIntersectionTEXT(query, true);
  imageStore(hits, ivec2(gl_GlobalInvocationID.xy), vec4(t) * textureLod(textures[0], vec2(0.5), 0.0));
}
)";

// A shader that traces through the shader library (scene/trace.glsl) rather than declaring the
// acceleration structure itself: it runs with either tracer (compiled for each).
const char* kLibraryTracingShader = R"(#version 460
#extension GL_GOOGLE_include_directive : require
#include "scene/scene.glsl"
SCENE_OBJECTS
#include "scene/trace.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 3, rgba32f) uniform writeonly image2D hits;
void main() {
  SurfaceHit h = trace_surface(vec3(0.0, 100.0, 0.0), vec3(0.0, -1.0, 0.0), 0.0, CAUSTICA_ALL_INSTANCES);
  float t = h.hit ? h.t : -1.0;
  imageStore(hits, ivec2(gl_GlobalInvocationID.xy), vec4(t) * textureLod(scene_textures[0], vec2(0.5), 0.0));
}
)";

// The scene's textures and acceleration structure: a pass has them with "scene": true where its
// shader declares them at the library's places, and one that traces is refused on a device without
// ray queries as the built-in exact passes are.
TEST(UserPass, TheScenesTexturesAndAccelerationStructureAreCheckedAndNeedRayQueries) {
  const auto dir = test_dir();
  const std::string file = (dir / "trace.comp").string();
  // `shader` in a pass with or without the scene is refused with each of `expected`.
  auto refused = [&](const std::string& shader, bool scene, const std::vector<std::string>& expected) {
    write(dir / "trace.comp", shader);
    const std::string error = error_of(dir, one_image_pass("trace", "trace.comp", "hits", scene, 8, 8));
    for (const auto& message : expected) EXPECT_NE(error.find(file + message), std::string::npos) << error;
  };
  // Without the scene: both named at their lines.
  refused(kTracingShader, false,
          {":6: 'tlas' at binding 14 is an acceleration structure; a user pass has one only as the scene's, binding 14 of set 0 "
           "(shaders/scene/trace.glsl), with \"scene\": true",
           ":7: 'textures' in set 1 is the scene's texture array (shaders/scene/textures.glsl); give the pass the scene with "
           "\"scene\": true"});
  // With it, at another binding or of another kind, or a port at the scene's binding.
  refused(replaced(kTracingShader, "binding = 14", "binding = 13"), true,
          {":6: 'tlas' at binding 13 is an acceleration structure; a user pass has one only as the scene's, binding 14 of set 0 "
           "(shaders/scene/trace.glsl) (at /passes/0/scene)"});
  refused(replaced(replaced(kTracingShader, "uniform sampler2D textures[]", "uniform sampler2DArray textures[]"), "vec2(0.5), 0.0",
                   "vec3(0.5), 0.0"),
          true,
          {":7: 'textures' in set 1 at binding 0 is a sampled image (sampler2D) array, but set 1 is the scene's texture array, "
           "binding 0, sampler2D[] (shaders/scene/textures.glsl)"});
  refused(replaced(kTracingShader, "binding = 3, rgba32f", "binding = 15, rgba32f"), true,
          {":5: 'hits' takes binding 15, which the scene has (bindings 0 to 2, and 14 and 15 for ray queries, with \"scene\": true); "
           "bind port 'hits' at another binding from 3"});

  // Declaring the acceleration structure itself: a pass that traces with ray queries alone, refused
  // where the device lacks them; through the library it compiles for the compute tracer too.
  write(dir / "trace.comp", kTracingShader);
  EXPECT_EQ(compile_in(dir, one_image_pass("trace", "trace.comp", "hits", true, 8, 8)).traced_passes, std::vector<std::string>{"trace"});
  CompileOptions without;
  without.ray_queries = false;
  without.ray_queries_missing = "VK_KHR_ray_query (a test device)";
  try {
    compile_in(dir, one_image_pass("trace", "trace.comp", "hits", true, 8, 8), without);
    ADD_FAILURE() << "a user pass that traces the scene compiled for a device without ray queries";
  } catch (const InputError& e) {
    EXPECT_NE(
        std::string(e.what()).find("pass 'trace' (compute) traces exact paths with ray queries (VK_KHR_ray_query, "
                                   "VK_KHR_acceleration_structure), and this device lacks VK_KHR_ray_query (a test device); its shader " +
                                   file + " declares the scene's acceleration structure itself (binding 14"),
        std::string::npos)
        << e.what();
  }
  write(dir / "trace.comp", kLibraryTracingShader);
  EXPECT_EQ(compile_in(dir, one_image_pass("trace", "trace.comp", "hits", true, 8, 8), without).tracer, graph::Tracer::compute);
  // The textures alone need no ray queries.
  write(dir / "trace.comp", R"(#version 460
#extension GL_EXT_nonuniform_qualifier : require
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 3, rgba32f) uniform writeonly image2D hits;
layout(set = 1, binding = 0) uniform sampler2D textures[];
void main() { imageStore(hits, ivec2(gl_GlobalInvocationID.xy), textureLod(textures[0], vec2(0.5), 0.0)); }
)");
  EXPECT_TRUE(compile_in(dir, one_image_pass("trace", "trace.comp", "hits", true, 8, 8), without).traced_passes.empty());
}

// On the device, with each tracer the device has: the ray down the y axis meets the highest surface
// there (the top of sphere_plane's ball), and the scene's first texture (a white texel where the
// scene has none) multiplies it by 1.
TEST(UserPass, ATracingPassSeesTheScenesGeometryAndTexturesWithEachTracer) {
  const auto dir = test_dir();
  write(dir / "trace.comp", kLibraryTracingShader);
  write(dir / "graph.json", one_image_pass("trace", "trace.comp", "hits", true, 8, 8).dump(2));
  const auto scene = test::load_bundled_scene("sphere_plane");
  float top = -1e30f;
  for (const auto& o : scene->objects) {
    if (o.bounds_min.x <= 0.0f && o.bounds_max.x >= 0.0f && o.bounds_min.z <= 0.0f && o.bounds_max.z >= 0.0f)
      top = std::max(top, o.bounds_max.y);
  }
  test::SceneEngine e;
  std::vector<graph::Tracer> tracers{graph::Tracer::compute};
  if (e.vk.ray_queries().available) tracers.push_back(graph::Tracer::ray_query);
  for (graph::Tracer tracer : tracers) {
    SCOPED_TRACE(graph::tracer_name(tracer));
    e.tracer = tracer;
    e.render(load_graph_file((dir / "graph.json").string()), scene, {"hits"});
    const io::ImageData hits = e.executor.read_image("hits");
    // The ball is a mesh: its top lies within a fraction of a percent of its box's.
    for (int c = 0; c < 4; ++c) EXPECT_NEAR(hits.rgba[static_cast<size_t>(c)], 100.0f - top, 0.01f * (1.0f + std::abs(top))) << c;
  }
}

// Graph `path` of the data folder with `sets` applied.
GraphDesc data_graph(const std::string& path, const std::vector<std::string>& sets) {
  GraphDesc graph = load_graph_file((data_dir() / path).string());
  apply_overrides(graph, sets);
  return graph;
}

// Example (a): the regular caustic map's photon pass as a user pass, beside caustics_regular on
// every bundled scene. The same photons take the same float operations in both, so the maps
// differ only where the float atomics add a texel's photons in another order: measured bit for bit
// equal on all but glass_bunny (5e-10). The bound, 1e-6 of the map's flux in sum, is rounding's
// (a few ulps of 6e-8 per texel), while one photon lost or moved at this grid is ~1e-4.
TEST(UserPass, TheUserCausticMapEqualsTheBuiltInOnTheBundledScenes) {
  const std::vector<std::string> sets{"grid=96", "caustic_size=96", "light_size=192", "shadow_size=64"};
  const GraphDesc user = data_graph("graphs/examples/caustic_map_user.json", sets);
  const GraphDesc builtin = data_graph("graphs/caustics_regular.json", sets);
  std::vector<std::string> scenes;
  for (const auto& entry : std::filesystem::directory_iterator(data_dir() / "scenes")) {
    if (entry.path().extension() == ".json") scenes.push_back(entry.path().stem().string());
  }
  std::sort(scenes.begin(), scenes.end());
  test::SceneEngine e;
  e.width = 64;
  e.height = 36;
  size_t compared = 0;
  for (const auto& name : scenes) {
    SCOPED_TRACE(name);
    // The example is a graph made for one light: both graphs see the scene's first light alone,
    // where it throws through one caustic view (a point light among its refractors has one per cube
    // face, which the bundled graph draws each and the example the first of).
    const auto scene = test::load_bundled_scene(name);
    scene->lights.resize(1);
    if (scene->refractor_count() == 0) continue;  // the caustic passes are culled
    if (scene->lights.front().caustic_view_count() != 1) continue;
    const FrameResult ours = e.render(user, scene, {"caustics"});
    const io::ImageData map = e.executor.read_image("caustics");
    const FrameResult theirs = e.render(builtin, scene, {"caustics"});
    EXPECT_LE(test::relative_difference(map, e.executor.read_image("caustics")), 1e-6);
    for (const char* counter :
         {"photons.processed", "photons.splatted", "photons.dropped_miss", "photons.dropped_tir", "photons.processed.level0"}) {
      EXPECT_EQ(ours.counters.at(counter), theirs.counters.at(counter)) << counter;
    }
    for (const char* counter : {"caustic.flux", "caustic.flux_entering", "caustic.flux_dropped"}) {
      EXPECT_NEAR(ours.counters.at(counter), theirs.counters.at(counter), 1e-6 * std::abs(theirs.counters.at(counter))) << counter;
    }
    ++compared;
  }
  EXPECT_GE(compared, 10u);
}

// Example (a) exact: the photon pass of caustics_raytraced (distance ray_query) as a user pass that
// traces the scene's acceleration structure with the shader library's exact tracer. Same photons,
// same random numbers, same float operations: the maps and every counter agree to the float atomics'
// order, as for the image-space example above. sphere_plane, rainbow_lens (dispersive: three colour
// bands) and mask_over_lens (a MASK texture that the rays pass through where it cuts the quad out),
// at a small grid, the exact kernel's compile being most of the time. With each tracer the device
// has: the user shader is compiled for the compute tracer too (UserShader::compute_tracer).
TEST(UserPass, TheExactUserCausticMapEqualsTheBuiltInWithEachTracer) {
  const std::vector<std::string> sets{"grid=32", "caustic_size=48", "light_size=64", "shadow_size=64"};
  const GraphDesc user = data_graph("graphs/examples/caustic_map_exact_user.json", sets);
  const GraphDesc builtin = data_graph("graphs/caustics_raytraced.json", sets);
  test::SceneEngine e;
  e.width = 32;
  e.height = 18;
  std::vector<graph::Tracer> tracers{graph::Tracer::compute};
  if (e.vk.ray_queries().available) tracers.push_back(graph::Tracer::ray_query);
  const std::string mask_over_lens = (std::filesystem::path(CAUSTICA_SOURCE_DIR) / "tests/data/mask_over_lens.json").string();
  for (graph::Tracer tracer : tracers)
    for (const auto& scene : {test::load_bundled_scene("sphere_plane"), test::load_bundled_scene("rainbow_lens"),
                              std::make_shared<scene::Scene>(scene::load_scene_file(mask_over_lens))}) {
      SCOPED_TRACE(scene->name + " traced by " + graph::tracer_name(tracer));
      e.tracer = tracer;
      const FrameResult ours = e.render(user, scene, {"caustics"});
      const io::ImageData map = e.executor.read_image("caustics");
      const FrameResult theirs = e.render(builtin, scene, {"caustics"});
      EXPECT_LE(test::relative_difference(map, e.executor.read_image("caustics")), 1e-6);
      EXPECT_GT(theirs.counters.at("photons.exact"), 0.0);
      for (const auto& [counter, value] : theirs.counters) {
        if (!counter.starts_with("photons.") && !counter.starts_with("caustic.")) continue;
        if (counter == "photons.converged" || counter == "photons.peak_bytes" || counter == "photons.batches")
          continue;  // the built-in's own
        ASSERT_TRUE(ours.counters.contains(counter)) << counter;
        EXPECT_NEAR(ours.counters.at(counter), value, 1e-6 * std::abs(value)) << counter;
      }
    }
}

}  // namespace
