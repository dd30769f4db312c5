// Refraction on the device (lavapipe, validation and synchronization validation on; any message
// fails): forward against deferred, the engine against the exact ray-traced reference, the
// multi-layer order, and scenes without refractors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <utility>

#include "picture_change.h"
#include "reference/refraction_reference.h"
#include "scene_engine.h"

using namespace caustica;

namespace {

constexpr uint32_t kWidth = 320, kHeight = 180;

// SceneEngine renders at kWidth x kHeight (320 x 180).
struct Engine : test::SceneEngine {
  struct Result {
    io::ImageData refracted;  // linear HDR, before tonemapping
    io::ImageData lit;
    graph::FrameResult frame;
  };

  Result render(const std::string& graph_name, std::shared_ptr<const scene::Scene> scene, const std::vector<std::string>& sets = {}) {
    Result r;
    r.frame = SceneEngine::render(graph_name, std::move(scene), sets, {"refracted", "lit"});
    r.refracted = executor.read_image("refracted");
    r.lit = executor.read_image("lit");
    return r;
  }
};

std::shared_ptr<const scene::Scene> load(const std::string& name) {
  return test::load_bundled_scene(name);
}

float luminance(const float* p) {
  return 0.2126f * p[0] + 0.7152f * p[1] + 0.0722f * p[2];
}

size_t non_finite(const io::ImageData& image) {
  size_t n = 0;
  for (float v : image.rgba) n += std::isfinite(v) ? 0 : 1;
  return n;
}

struct Difference {
  double mean_relative;  // mean |a - b| / mean |b|, luminance
  double fraction_over;  // pixels whose luminance differs by more than 5% of b (and 0.01 absolute)
};

Difference compare(const io::ImageData& a, const io::ImageData& b) {
  double diff = 0, total = 0;
  size_t over = 0, pixels = size_t{a.width} * a.height;
  for (size_t i = 0; i < pixels; ++i) {
    const float la = luminance(&a.rgba[i * 4]), lb = luminance(&b.rgba[i * 4]);
    diff += static_cast<double>(std::abs(la - lb));
    total += static_cast<double>(std::abs(lb));
    if (std::abs(la - lb) > std::max(0.05f * std::abs(lb), 0.01f)) ++over;
  }
  return {diff / std::max(total, 1e-12), static_cast<double>(over) / static_cast<double>(pixels)};
}

const char* kScenes[] = {"sphere_plane", "bunny_plane", "two_refractors", "three_refractors", "torus",
                         "armadillo",    "dragon",      "no_refractor",   "thin_panes"};

}  // namespace

// Every refraction graph on every bundled scene renders without a validation message and without
// NaN or Inf. The forward and deferred graphs share the shading code; they differ in where the front surface comes from (a
// rasterized fragment, or the refractor buffer with its normal packed in one float's bits). The stated
// tolerance: mean luminance difference under 0.2%, and under 0.5% of pixels off by more than 5%.
TEST(Refraction, ForwardMatchesDeferredOnEveryScene) {
  Engine e;
  for (const char* name : kScenes) {
    auto scene = load(name);
    auto deferred = e.render("refraction_deferred", scene);
    auto forward = e.render("refraction_forward", scene);
    auto layers = e.render("refraction_multilayer", scene);
    if (scene->refractor_count() > 0) {
      EXPECT_EQ(layers.frame.counters.at("refraction.layers"), static_cast<double>(scene->refractor_count())) << name;
    }
    EXPECT_EQ(non_finite(layers.refracted), 0u) << name;
    EXPECT_EQ(non_finite(deferred.refracted), 0u) << name;
    EXPECT_EQ(non_finite(forward.refracted), 0u) << name;
    Difference d = compare(forward.refracted, deferred.refracted);
    EXPECT_LT(d.mean_relative, 0.002) << name;
    EXPECT_LT(d.fraction_over, 0.005) << name;
    std::printf("%-18s forward vs deferred: mean relative %.5f, pixels over 5%%: %.4f%%\n", name, d.mean_relative, 100 * d.fraction_over);
  }
}

// Relative L1 of luminance over the pixels where the camera sees a refractor, against exact ray
// tracing through every interface. Thresholds are the errors measured when this test was written
// (docs/refraction.md: sphere 0.201 d_V, 0.154 d_V/d_N; bunny 0.532, 0.482) plus about 8%; the test
// fails if the error grows.
TEST(Refraction, CloseToTheRayTracedReference) {
  Engine e;
  struct Case {
    const char* scene;
    const char* distance;
    double limit;
  };
  double sphere_dv = 0, sphere_dvdn = 0;
  for (auto [name, distance, limit] : {Case{"sphere_plane", "dv", 0.22}, Case{"sphere_plane", "dv_dn", 0.17},
                                       Case{"bunny_plane", "dv", 0.57}, Case{"bunny_plane", "dv_dn", 0.52}}) {
    auto scene = load(name);
    auto engine = e.render("refraction_deferred", scene, {std::string("distance=") + distance});
    auto reference = reference::render_refraction_reference(*scene, kWidth, kHeight);
    const double error = reference::refraction_relative_l1(engine.refracted, reference);
    std::printf("%-14s %-6s relative L1 against the reference: %.4f\n", name, distance, error);
    EXPECT_LT(error, limit) << name << " " << distance;
    if (std::string(name) == "sphere_plane") (std::string(distance) == "dv" ? sphere_dv : sphere_dvdn) = error;
  }
  // docs/oracles.md: on a sphere the d_V/d_N blend is the better distance estimate; measured 0.154 against
  // 0.201 (d_V) at 320x180 when this was written.
  EXPECT_LT(sphere_dvdn, sphere_dv);
}

// The image-space search finds where a ray leaves a smooth refractor to within a fraction of a
// pixel, so what is left of its error is the surface normal there: the back-surface buffer holds one
// normal per pixel, and taking the nearest one turns a smooth surface into pixel-wide facets, which
// a lens magnifies. The search blends the normals of the four nearest pixels of the same surface
// (refraction.glsl, smooth_normal). Measured at 320x180 when written: sphere 0.0105 (nearest normals:
// 0.0343), torus 0.0302 (0.0848).
TEST(Refraction, TheSearchSeesSmoothSurfacesAsSmooth) {
  Engine e;
  struct Case {
    const char* scene;
    double limit;
  };
  for (auto [name, limit] : {Case{"sphere_plane", 0.016}, Case{"torus", 0.042}}) {
    auto scene = load(name);
    auto engine = e.render("refraction_deferred", scene, {"distance=search"});
    const double error =
        reference::refraction_relative_l1(engine.refracted, reference::render_refraction_reference(*scene, kWidth, kHeight));
    std::printf("%-14s search, relative L1 against the reference: %.4f\n", name, error);
    EXPECT_LT(error, limit) << name;
  }
}

// Thin walls (glTF transmission without a volume) pass the view unbent, tinted, less their Fresnel
// reflection, with the share 1 - transmission reflected diffusely: image space sees that path
// exactly, so every refraction graph matches the ray-traced reference closely, one pane seen from
// its back face included. Treating the panes as solids is far off the same reference.
TEST(Refraction, ThinWallsMatchTheRayTracedReference) {
  Engine e;
  auto scene = load("thin_panes");
  const auto reference = reference::render_refraction_reference(*scene, kWidth, kHeight);
  for (const char* graph : {"refraction_deferred", "refraction_forward", "refraction_multilayer", "refraction_hybrid"}) {
    auto engine = e.render(graph, scene);
    const double error = reference::refraction_relative_l1(engine.refracted, reference);
    std::printf("thin_panes %-22s relative L1 against the reference: %.4f\n", graph, error);
    EXPECT_LT(error, 0.02) << graph;
  }
  // A closed thin object has two walls along each ray: the ball lens as a thin-walled tinted bubble.
  auto bubble = test::load_bundled_scene("sphere_plane");
  bubble->objects.back().material.thin = true;
  bubble->objects.back().material.tint = glm::vec3(0.5f, 0.8f, 1.0f);
  const auto bubble_reference = reference::render_refraction_reference(*bubble, kWidth, kHeight);
  for (const char* graph : {"refraction_deferred", "refraction_forward", "refraction_multilayer"}) {
    const double error = reference::refraction_relative_l1(e.render(graph, bubble).refracted, bubble_reference);
    std::printf("thin bubble %-22s relative L1 against the reference: %.4f\n", graph, error);
    EXPECT_LT(error, 0.02) << graph;
  }
  auto solid = test::load_bundled_scene("thin_panes");
  for (auto& object : solid->objects) object.material.thin = false;
  const auto solid_reference = reference::render_refraction_reference(*solid, kWidth, kHeight);
  const double against_solid = reference::refraction_relative_l1(e.render("refraction_deferred", scene).refracted, solid_reference);
  std::printf("thin_panes as thin walls against the solid reference: %.4f\n", against_solid);
  EXPECT_GT(against_solid, 0.1);
}

// glTF base colour textures through KHR_texture_transform, a texture on TEXCOORD_1, and MASK
// coverage cutting a quad into a checker, seen directly and in its shadow (tests/data/gltf/
// make_textured.py): the engine's picture against the ray-traced reference, which samples the same
// textures on the host and lets rays through where the mask cuts out. The same reference with the
// mask switched off, or without the textures, is far from the engine's picture: each feature shows.
TEST(Materials, TexturesTransformsAndMaskMatchTheRayTracedReference) {
  Engine e;
  const std::string file = (std::filesystem::path(CAUSTICA_SOURCE_DIR) / "tests/data/gltf/textured_mask.gltf").string();
  auto scene = std::make_shared<scene::Scene>(scene::load_model_scene(file, false));
  ASSERT_EQ(scene->textures.size(), 2u);  // the file's third image is used by nothing: never decoded
  const auto engine = e.render("refraction_deferred", scene);
  EXPECT_EQ(non_finite(engine.refracted), 0u);
  const Difference d = compare(engine.refracted, reference::render_refraction_reference(*scene, kWidth, kHeight).radiance);
  std::printf("textured_mask against the reference: mean relative %.4f, pixels over 5%%: %.4f%%\n", d.mean_relative, 100 * d.fraction_over);
  EXPECT_LT(d.mean_relative, 0.01);  // 0.0011 when this was written (320x180)
  EXPECT_LT(d.fraction_over, 0.02);

  auto unmasked = std::make_shared<scene::Scene>(*scene);
  for (auto& o : unmasked->objects) o.material.alpha_mode = scene::AlphaMode::opaque;
  const Difference without_mask = compare(engine.refracted, reference::render_refraction_reference(*unmasked, kWidth, kHeight).radiance);
  auto untextured = std::make_shared<scene::Scene>(*scene);
  for (auto& o : untextured->objects) o.material.base_color_texture = {};
  const Difference without_textures =
      compare(engine.refracted, reference::render_refraction_reference(*untextured, kWidth, kHeight).radiance);
  std::printf("against the reference without the mask %.4f, without textures %.4f\n", without_mask.mean_relative,
              without_textures.mean_relative);
  EXPECT_GT(without_mask.mean_relative, 10 * d.mean_relative);      // 0.050
  EXPECT_GT(without_textures.mean_relative, 10 * d.mean_relative);  // 0.216
}

// glTF's metallic-roughness BRDF with its texture, a normal map in a TANGENT frame, an occlusion map, emission (with
// KHR_materials_emissive_strength) and a single-sided quad turned away from the camera: the engine
// against the ray-traced reference, which evaluates the same model on the host. The reference with
// any one of them dropped is far from the engine's picture.
TEST(Materials, MetallicRoughnessNormalMapsOcclusionEmissionAndCullingMatchTheRayTracedReference) {
  Engine e;
  const std::string file = (std::filesystem::path(CAUSTICA_SOURCE_DIR) / "tests/data/gltf/textured_surfaces.gltf").string();
  auto scene = std::make_shared<scene::Scene>(scene::load_model_scene(file, false));
  ASSERT_TRUE(scene->objects[0].material.occlusion_texture.used());  // the floor's, with its strength
  EXPECT_FLOAT_EQ(scene->objects[0].material.occlusion_strength, 0.9f);
  const auto engine = e.render("refraction_deferred", scene);
  EXPECT_EQ(non_finite(engine.refracted), 0u);
  const Difference d = compare(engine.refracted, reference::render_refraction_reference(*scene, kWidth, kHeight).radiance);
  std::printf("textured_surfaces against the reference: mean relative %.4f, pixels over 5%%: %.4f%%\n", d.mean_relative,
              100 * d.fraction_over);
  EXPECT_LT(d.mean_relative, 0.01);  // 0.0026 when this was written; each ablation 0.039 or more
  EXPECT_LT(d.fraction_over, 0.02);
  struct Ablation {
    const char* what;
    void (*change)(scene::Material&);
  };
  for (const Ablation& ablation : {
           Ablation{"Lambertian", [](scene::Material& m) { m.metallic_roughness = false; }},
           Ablation{"no metallic-roughness texture", [](scene::Material& m) { m.metallic_roughness_texture = {}; }},
           Ablation{"no normal map", [](scene::Material& m) { m.normal_texture = {}; }},
           Ablation{"no occlusion map", [](scene::Material& m) { m.occlusion_texture = {}; }},
           Ablation{"no emission", [](scene::Material& m) { m.emissive = glm::vec3(0.0f); }},
           Ablation{"double-sided", [](scene::Material& m) { m.double_sided = true; }},
       }) {
    auto changed = std::make_shared<scene::Scene>(*scene);
    for (auto& o : changed->objects) ablation.change(o.material);
    const Difference off = compare(engine.refracted, reference::render_refraction_reference(*changed, kWidth, kHeight).radiance);
    std::printf("  against the reference with %-30s %.4f\n", ablation.what, off.mean_relative);
    EXPECT_GT(off.mean_relative, 10 * d.mean_relative) << ablation.what;
  }
  ASSERT_FALSE(scene->objects[0].mesh.tangents.empty());  // the floor's TANGENT frame, a quarter turn from its UVs'
  auto untangented = std::make_shared<scene::Scene>(*scene);
  for (auto& o : untangented->objects) o.mesh.tangents.clear();
  const Difference without_tangents =
      compare(engine.refracted, reference::render_refraction_reference(*untangented, kWidth, kHeight).radiance);
  std::printf("  against the reference with %-30s %.4f\n", "no TANGENT", without_tangents.mean_relative);
  EXPECT_GT(without_tangents.mean_relative, 10 * d.mean_relative);
}

TEST(Refraction, MultilayerIgnoresTheOrderOfObjectsInTheFile) {
  Engine e;
  std::ifstream in(data_dir() / "scenes/two_refractors.json");
  nlohmann::json scene_json = nlohmann::json::parse(in);
  auto& objects = scene_json["objects"];
  std::reverse(objects.begin(), objects.end());
  auto swapped = std::make_shared<const scene::Scene>(scene::load_scene(JsonDocument::parse(scene_json.dump(), "swapped.json")));
  auto a = e.render("refraction_multilayer", load("two_refractors"));
  auto b = e.render("refraction_multilayer", swapped);
  EXPECT_EQ(a.frame.counters.at("refraction.layers"), 2.0);
  Difference d = compare(a.refracted, b.refracted);
  EXPECT_EQ(d.fraction_over, 0.0);
  EXPECT_LT(d.mean_relative, 1e-6);
}

// The bundled graphs leave back_depth unbound, so the back-surface draw clears and reuses the
// front's depth image: the same surfaces as with a depth image of its own, bit for bit.
TEST(Refraction, OneSharedDepthDrawsTheSameSurfacesAsTwo) {
  Engine e;
  for (const auto& [graph_name, pass] :
       {std::pair{"refraction_multilayer", "refraction"}, std::pair{"refraction_deferred", "refractors"}}) {
    std::ifstream in(data_dir() / "graphs" / (std::string(graph_name) + ".json"));
    nlohmann::json graph_json = nlohmann::json::parse(in);
    int bound = 0;
    for (auto& p : graph_json["passes"]) {
      if (p["name"] != pass) continue;
      ASSERT_FALSE(p["outputs"].contains("back_depth")) << graph_name;
      p["outputs"]["back_depth"] = "own_back_depth";
      ++bound;
    }
    ASSERT_EQ(bound, 1) << graph_name;
    graph_json["resources"]["own_back_depth"] = {{"type", "image"}, {"format", "d32f"}};
    const auto two_depths = graph::load_graph(JsonDocument::parse(graph_json.dump(), "two_depths.json"));
    auto shared = e.render(graph_name, load("two_refractors"));
    e.SceneEngine::render(two_depths, load("two_refractors"), {"refracted", "lit"});
    const io::ImageData separate = e.executor.read_image("refracted");
    ASSERT_EQ(shared.refracted.rgba.size(), separate.rgba.size());
    EXPECT_EQ(shared.refracted.rgba, separate.rgba) << graph_name;
  }
}

// A refractor buffer holds its normal in the bits of one float (scene.glsl, pack_normal), which a
// colour attachment and a sampled fetch keep only for ordinary floats: a NaN or a denormal may be
// quieted or flushed by a GPU (lavapipe keeps them, so only the bits themselves can be checked
// here). A sphere, seen by the camera and by the light, shows normals of every direction; with two
// snorm16 values in the bits, 528 and 590 of the light buffers' texels were NaNs or denormals.
TEST(Refraction, RefractorBuffersHoldNormalsAsOrdinaryFloats) {
  Engine e;
  const std::vector<std::string> buffers = {"front", "back", "light_front", "light_back"};
  e.SceneEngine::render("caustics_adaptive", load("sphere_plane"), {}, {buffers.begin(), buffers.end()});
  for (const auto& name : buffers) {
    const io::ImageData image = e.executor.read_image(name);
    size_t covered = 0, not_ordinary = 0;
    for (size_t i = 0; i < image.rgba.size() / 4; ++i) {
      if (image.rgba[i * 4 + 1] <= 0.0f) continue;  // no refractor in this texel
      ++covered;
      not_ordinary += std::isnormal(image.rgba[i * 4]) ? 0 : 1;
    }
    EXPECT_GT(covered, 1000u) << name;
    EXPECT_EQ(not_ordinary, 0u) << name << ": of " << covered << " texels";
  }
}

// The default picture has no pure black: the sky's ambient fill lights what the spot light does
// not reach (the bunny's shadow, the dark tiles). Its darkest 1% of lit pixels stays above 0.02
// (about 0.033 for a dark tile in full shadow); bunny_plane, with the default 0.03 ambient, is at 0.0065.
TEST(Refraction, TheDefaultSceneHasNoBlackShadows) {
  Engine e;
  auto frame = e.render("caustics_adaptive", load("glass_bunny"));
  std::vector<float> lum;
  for (size_t i = 0; i < frame.lit.rgba.size() / 4; ++i) lum.push_back(luminance(&frame.lit.rgba[i * 4]));
  std::nth_element(lum.begin(), lum.begin() + static_cast<std::ptrdiff_t>(lum.size() / 100), lum.end());
  const float darkest = lum[lum.size() / 100];
  std::printf("glass_bunny: 1st percentile of lit luminance %.4f\n", static_cast<double>(darkest));
  EXPECT_GT(darkest, 0.02f);
}

TEST(Refraction, AHiddenRefractorShowsThroughTheNearOne) {
  Engine e;
  auto both = load("two_refractors");
  auto near_only_scene = std::make_shared<scene::Scene>(*both);
  auto& objects = near_only_scene->objects;
  objects.erase(std::remove_if(objects.begin(), objects.end(), [](const scene::Object& o) { return o.name == "far"; }), objects.end());
  auto with_far = e.render("refraction_multilayer", both);
  auto without_far = e.render("refraction_multilayer", near_only_scene);
  // Where the near sphere covers the screen, removing the far sphere behind it changes what is seen.
  auto near_mask = reference::render_refraction_reference(*near_only_scene, kWidth, kHeight).refractor;
  size_t near_pixels = 0, changed = 0;
  for (size_t i = 0; i < near_mask.size(); ++i) {
    if (!near_mask[i]) continue;
    ++near_pixels;
    const float a = luminance(&with_far.refracted.rgba[i * 4]), b = luminance(&without_far.refracted.rgba[i * 4]);
    if (std::abs(a - b) > 0.05f * std::max(b, 0.01f)) ++changed;
  }
  ASSERT_GT(near_pixels, 1000u);
  EXPECT_GT(changed, near_pixels / 20) << changed << " of " << near_pixels;
}

// "Model no more than a scene needs": without refractors the refraction passes are disabled by
// their "enabled": "scene.refractors", their images are never allocated, and "refracted" falls
// back to "lit".
TEST(Refraction, NoRefractorMeansNoRefractionPassAndNoRefractionMemory) {
  Engine e;
  for (const char* graph : {"refraction_multilayer", "refraction_deferred", "refraction_forward"}) {
    auto with = e.render(graph, load("two_refractors"));
    const uint64_t memory_with = e.executor.plan().transient_bytes_unaliased;
    auto r = e.render(graph, load("no_refractor"));
    const auto& plan = e.executor.plan();
    for (const auto& pass : plan.passes) EXPECT_NE(pass.name, "refraction") << graph;
    EXPECT_EQ(r.frame.counters.count("refraction.tir_pixels"), 0u) << graph;
    EXPECT_EQ(plan.resolve("refracted"), "lit") << graph;
    EXPECT_LT(plan.transient_bytes_unaliased, memory_with) << graph;
    EXPECT_EQ(r.refracted.rgba, r.lit.rgba) << graph;
  }
}

// Grazing light on a floor is where a shadow map's depth comparison self-shadows in stripes (shadow
// acne). Against the reference's exact shadow rays, over the floor pixels that the reference shows
// lit by the spot (more than twice the ambient level), the engine may darken by more than 20% only
// at shadow edges (the shadow map's 3x3 filter): under 0.5% of them (measured with a constant bias
// alone: 2.2%, in stripes; with the normal offset: 0.17%). Nor may the fix detach shadows: no more
// floor pixels brighter than the reference's than that.
TEST(Refraction, NoShadowAcneAtGrazingLight) {
  Engine e;
  auto scene = load("stability/grazing_light");
  auto engine = e.render("refraction_deferred", scene);
  const auto reference = reference::render_refraction_reference(*scene, kWidth, kHeight);
  // The darkest floor pixel: lit by the ambient term alone.
  size_t lit = 0, darkened = 0, brightened = 0;
  float floor_min = 1e30f;
  for (size_t i = 0; i < reference.refractor.size(); ++i) {
    if (reference.refractor[i]) continue;
    floor_min = std::min(floor_min, luminance(&reference.radiance.rgba[i * 4]));
  }
  for (size_t i = 0; i < reference.refractor.size(); ++i) {
    if (reference.refractor[i]) continue;
    const float r = luminance(&reference.radiance.rgba[i * 4]), g = luminance(&engine.lit.rgba[i * 4]);
    if (g > 1.2f * r + 0.01f) ++brightened;  // a shadow the engine lost or detached from its caster
    if (r <= 2.0f * floor_min) continue;
    ++lit;
    if (g < 0.8f * r) ++darkened;
  }
  std::printf("grazing light: %zu of %zu lit floor pixels darkened by more than 20%%, %zu floor pixels brightened\n", darkened, lit,
              brightened);
  ASSERT_GT(lit, 1000u);
  EXPECT_LT(static_cast<double>(darkened), 0.005 * static_cast<double>(lit));
  EXPECT_LT(static_cast<double>(brightened), 0.005 * static_cast<double>(lit));
}

// Dispersion splits the view through the glass by colour band (scenes/rainbow_lens.json, a flint
// ball lens), as the ray-traced reference does: per channel over the refractor's pixels, the
// engine's dispersed picture is nearer the dispersed reference than its undispersed picture is. The
// exact tracer gets a third of the error (0.0047 against 0.0144 when this was written), the hybrid
// less (0.024 against 0.037); in the image-space methods their exit estimate's error dominates and
// dispersion takes off only a little (0.1346 against 0.1364).
TEST(Refraction, DispersionSplitsTheViewByColourBand) {
  Engine e;
  auto dispersed = test::load_bundled_scene("rainbow_lens");
  auto clear = test::load_bundled_scene("rainbow_lens");
  ASSERT_GT(dispersed->objects.back().material.dispersion, 0.0f);
  clear->objects.back().material.dispersion = 0.0f;
  const auto reference = reference::render_refraction_reference(*dispersed, kWidth, kHeight);
  const auto reference_clear = reference::render_refraction_reference(*clear, kWidth, kHeight);
  struct Case {
    const char* graph;
    double at_most;     // of the undispersed picture's error
    double max_error;   // against the dispersed reference: under twice the error measured when written
    double min_cosine;  // between what dispersion changes in the picture and in the reference's
  };
  // The image-space exit estimate's own error at the rim, where the bands part, is far larger than
  // the bands' parting, so their picture with dispersion is no nearer the dispersed reference than
  // without (0.1159 against 0.1157 deferred, 0.1149 both forward): dispersion may cost them at most
  // 1% of that error, the error itself is bounded, and the change dispersion makes must go the
  // reference's way (cosine 0.13 to 0.18). The exact paths: 0.0047 and 0.0049 against 0.0144, cosine 0.90.
  for (auto [graph, at_most, max_error, min_cosine] :
       {Case{"refraction_raytraced", 0.5, 0.009, 0.8}, Case{"refraction_hybrid", 0.8, 0.009, 0.5},
        Case{"refraction_deferred", 1.01, 0.2, 0.1}, Case{"refraction_forward", 1.01, 0.2, 0.1},
        Case{"refraction_multilayer", 1.01, 0.2, 0.1}}) {
    const auto [error_with, error_without, cosine] =
        test::picture_change(e.render(graph, dispersed).refracted, e.render(graph, clear).refracted, reference.radiance,
                             reference_clear.radiance, &reference.refractor);
    std::printf(
        "dispersion %-22s per-channel relative L1 against the dispersed reference: %.4f dispersed, %.4f not; cosine of the "
        "changes %.4f\n",
        graph, error_with, error_without, cosine);
    EXPECT_LT(error_with, at_most * error_without) << graph;
    EXPECT_LT(error_with, max_error) << graph;
    EXPECT_GT(cosine, min_cosine) << graph;
  }
}

// glTF's interface layers change the view through the glass as the ray-traced reference does: the
// ball lens made of each of scenes/materials' clearcoat_ball, specular_ball and iridescent_ball
// (tests/data/layered), against the same ball without its layers. Over the refractor's pixels the
// layered picture is nearer the layered reference than the plain picture is, and the change the
// layers make goes the reference's way. When written: the exact camera paths 0.005 to 0.006 of
// per-channel relative L1 against 0.047 to 0.118 without the layers, cosine 0.997 to 0.998; image
// space (deferred, whose exit estimate errs by 0.14 to 0.15 itself) 0.144 to 0.153 against 0.183 to
// 0.228, cosine 0.74 to 0.93.
TEST(Refraction, InterfaceLayersChangeTheViewAsTheReferenceDoes) {
  Engine e;
  for (const char* ball : {"clearcoat_ball", "specular_ball", "iridescent_ball"}) {
    const auto file = std::filesystem::path(CAUSTICA_SOURCE_DIR) / "tests/data/layered" / (std::string(ball) + ".json");
    auto layered = std::make_shared<scene::Scene>(scene::load_scene_file(file.string()));
    auto plain = std::make_shared<scene::Scene>(*layered);
    scene::Material& glass = plain->objects.back().material;
    ASSERT_TRUE(glass.refractor);
    glass.specular = 1.0f;
    glass.specular_color = glm::vec3(1.0f);
    glass.clearcoat = glass.iridescence = 0.0f;
    const auto reference = reference::render_refraction_reference(*layered, kWidth, kHeight);
    const auto reference_plain = reference::render_refraction_reference(*plain, kWidth, kHeight);
    struct Case {
      const char* graph;
      double at_most;  // of the plain picture's error against the layered reference
      double min_cosine;
    };
    for (auto [graph, at_most, min_cosine] : {Case{"refraction_raytraced", 0.2, 0.95}, Case{"refraction_deferred", 0.9, 0.6}}) {
      const auto [error_with, error_without, cosine] =
          test::picture_change(e.render(graph, layered).refracted, e.render(graph, plain).refracted, reference.radiance,
                               reference_plain.radiance, &reference.refractor);
      std::printf("%s %-22s per-channel relative L1 against the layered reference: %.4f layered, %.4f not; cosine of the changes %.4f\n",
                  ball, graph, error_with, error_without, cosine);
      EXPECT_LT(error_with, at_most * error_without) << ball << " " << graph;
      EXPECT_GT(cosine, min_cosine) << ball << " " << graph;
    }
  }
}

// The interface layers' textures are read per texel in image space too, where the refractor buffers
// hold them (the front_layers port): tests/data/gltf/layered_pane.gltf's -x half reflects red whole
// (a specular colour, under a coat and a film) and its +x half nothing, so the floor seen through the
// -x half loses its red and through the +x half keeps it; coat_normal_glass.gltf's coat has its own
// normal map, tilted 70 degrees over the -x half, where the coat then reflects more of the view.
// Over the pane's pixels, against the same scene with the textures replaced by their means (the
// object's values, which a graph without front_layers takes; no coat normal map), each method's
// textured picture is much nearer the textured reference, and its change goes the reference's way.
TEST(Refraction, InterfaceLayerTexturesAreReadPerTexelInImageSpace) {
  Engine e;
  for (const char* asset : {"layered_pane.gltf", "coat_normal_glass.gltf"}) {
    const auto file = std::filesystem::path(CAUSTICA_SOURCE_DIR) / "tests/data/gltf" / asset;
    auto textured = std::make_shared<scene::Scene>(scene::load_model_scene(file.string(), false));
    auto means = std::make_shared<scene::Scene>(*textured);
    for (scene::Object& o : means->objects) {
      o.material.layer_textures = {};
      o.material.surface_textures.clearcoat_normal = {};
    }
    ASSERT_TRUE(textured->has_layer_textures()) << asset;
    ASSERT_FALSE(means->has_layer_textures()) << asset;
    const auto reference = reference::render_refraction_reference(*textured, kWidth, kHeight);
    const auto reference_means = reference::render_refraction_reference(*means, kWidth, kHeight);
    for (const char* graph : {"refraction_deferred", "refraction_multilayer", "refraction_forward"}) {
      const auto [error_with, error_without, cosine] =
          test::picture_change(e.render(graph, textured).refracted, e.render(graph, means).refracted, reference.radiance,
                               reference_means.radiance, &reference.refractor);
      std::printf("%-22s %-22s per-channel relative L1 against the textured reference: %.4f per texel, %.4f by the means; cosine %.4f\n",
                  asset, graph, error_with, error_without, cosine);
      EXPECT_LT(error_with, 0.1 * error_without) << asset << " " << graph;
      EXPECT_GT(cosine, 0.99) << asset << " " << graph;
    }
  }
}

// Rough transmission blurs the view through the glass as the ray-traced reference does: the glass
// bunny on its tiled floor (a solid) and thin_panes.json (thin walls) at roughness 0.3. Over the
// refractor's pixels, every method's rough picture is much nearer the rough reference than its
// smooth picture is (when this was written: 0.43 to 0.48 of the error with the exact paths, 0.48
// to 0.57 in image space), and the change roughness makes goes the reference's way (the cosine
// between the two changes, per channel and pixel: 0.76 to 0.88 with exact paths, whose 8 paths per
// pixel are noisier than the reference's 64; in image space only 0.10 on the bunny, whose exit
// estimate's own error moves the blurred picture elsewhere, 0.88 on the panes).
//
// The error itself is bounded too, under twice what was measured when written (bunny: exact paths
// 0.197 and 0.196, image space 0.281; panes: every method 0.118).
TEST(Refraction, RoughGlassBlursTheViewThroughIt) {
  Engine e;
  struct Case {
    const char* graph;
    double at_most;  // of the smooth picture's error against the rough reference
    double min_cosine;
    bool exact;  // traces every pixel's path (else image space)
  };
  const std::map<std::pair<std::string, bool>, double> max_error{
      {{"glass_bunny", true}, 0.3}, {{"glass_bunny", false}, 0.4}, {{"thin_panes", true}, 0.17}, {{"thin_panes", false}, 0.17}};
  for (const char* name : {"glass_bunny", "thin_panes"}) {
    auto smooth = test::load_bundled_scene(name);
    auto rough = test::load_bundled_scene(name);
    for (auto& object : rough->objects) {
      if (object.material.refractor) object.material.transmission_roughness = 0.3f;
    }
    const auto reference = reference::render_refraction_reference(*rough, kWidth, kHeight);
    const auto reference_smooth = reference::render_refraction_reference(*smooth, kWidth, kHeight);
    for (auto [graph, at_most, min_cosine, exact] :
         {Case{"refraction_raytraced", 0.55, 0.6, true}, Case{"refraction_hybrid", 0.55, 0.5, true},
          Case{"refraction_deferred", 0.7, 0.05, false}, Case{"refraction_forward", 0.7, 0.05, false},
          Case{"refraction_multilayer", 0.7, 0.05, false}}) {
      const auto [error_with, error_without, cosine] =
          test::picture_change(e.render(graph, rough).refracted, e.render(graph, smooth).refracted, reference.radiance,
                               reference_smooth.radiance, &reference.refractor);
      std::printf("rough glass %-12s %-22s relative L1 against the rough reference: %.4f rough, %.4f smooth; cosine of the changes %.4f\n",
                  name, graph, error_with, error_without, cosine);
      EXPECT_LT(error_with, at_most * error_without) << name << " " << graph;
      EXPECT_LT(error_with, max_error.at({name, exact})) << name << " " << graph;
      EXPECT_GT(cosine, min_cosine) << name << " " << graph;
    }
  }
}
