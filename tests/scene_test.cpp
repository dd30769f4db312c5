// Scenes without a device: primitives, mesh files, d_N by ray casting, scene files.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <glm/gtc/matrix_transform.hpp>
#include <map>
#include <set>
#include <sstream>

#include "core/error.h"
#include "io/json_document.h"
#include "scene/bvh_order.h"
#include "scene/scene.h"
#include "scene/translucent_samples.h"

using namespace caustica;
using namespace caustica::scene;

namespace {

const std::filesystem::path kSource = CAUSTICA_SOURCE_DIR;

// Every triangle's winding agrees with its vertices' normals: counter-clockwise seen from outside.
void expect_outward(const Mesh& m, const char* what) {
  size_t wrong = 0;
  for (size_t t = 0; t < m.indices.size(); t += 3) {
    const glm::vec3 a = m.positions[m.indices[t]], b = m.positions[m.indices[t + 1]], c = m.positions[m.indices[t + 2]];
    const glm::vec3 face = glm::cross(b - a, c - a);
    const glm::vec3 n = m.normals[m.indices[t]] + m.normals[m.indices[t + 1]] + m.normals[m.indices[t + 2]];
    if (glm::dot(face, n) <= 0) ++wrong;
  }
  EXPECT_EQ(wrong, 0u) << what;
}

std::filesystem::path write_temp(const std::string& name, const std::string& text) {
  auto path = std::filesystem::temp_directory_path() / name;
  std::ofstream(path) << text;
  return path;
}

}  // namespace

TEST(Primitives, AreWoundOutward) {
  expect_outward(make_sphere(1.0f, 32, 16), "sphere");
  expect_outward(make_box(glm::vec3(1, 2, 3)), "box");
  expect_outward(make_torus(1.0f, 0.3f, 32, 16), "torus");
  expect_outward(make_plane(2, 2), "plane");
}

TEST(NormalDistance, IsTheChordThroughTheObject) {
  // Along the inverted normal a sphere's chord passes through the centre: the diameter. A polygonal
  // sphere is slightly inside the true one, so allow the faceting error of 64 slices.
  Mesh sphere = make_sphere(2.0f, 64, 32);
  std::vector<float> d = normal_distances(sphere);
  size_t checked = 0;
  for (size_t i = 0; i < d.size(); ++i) {
    if (std::abs(sphere.normals[i].y) > 0.99f) continue;  // the poles' fan triangles are degenerate
    EXPECT_NEAR(d[i], 4.0f, 0.01f) << "vertex " << i;
    ++checked;
  }
  EXPECT_GT(checked, 1000u);
  // A box's flat faces: the distance to the opposite face, along each axis.
  Mesh box = make_box(glm::vec3(1.0f, 2.0f, 3.0f));
  std::vector<float> b = normal_distances(box);
  for (size_t i = 0; i < b.size(); ++i) {
    const glm::vec3 n = glm::abs(box.normals[i]);
    EXPECT_NEAR(b[i], glm::dot(n, glm::vec3(1, 2, 3)), 1e-4f) << "vertex " << i;
  }
}

// The hybrids trace what leaves a convex solid past every refractor (its exit ray cannot meet it
// again), so the test must say no to anything light could meet twice: a concave surface, an open
// one, two bodies in one mesh, a dent, a mesh wound inside out.
TEST(Convexity, OnlyClosedConvexBodiesAreConvexSolids) {
  EXPECT_TRUE(is_convex_solid(make_sphere(1.0f, 64, 32)));  // its seam's ends differ by float rounding: welded
  EXPECT_TRUE(is_convex_solid(make_sphere(0.5f, 8, 4)));
  EXPECT_TRUE(is_convex_solid(make_box(glm::vec3(1.0f, 0.02f, 3.0f))));  // coplanar triangles, split vertices
  EXPECT_FALSE(is_convex_solid(make_torus(1.0f, 0.3f, 32, 16)));
  EXPECT_FALSE(is_convex_solid(make_plane(2.0f, 2.0f)));
  EXPECT_FALSE(is_convex_solid(load_mesh_file("/usr/share/glmark2/models/bunny.obj")[0].mesh));

  Mesh open = make_sphere(1.0f, 32, 16);
  open.indices.resize(open.indices.size() - 3);
  EXPECT_FALSE(is_convex_solid(open)) << "a triangle missing";

  Mesh two = make_sphere(1.0f, 32, 16);
  const auto count = static_cast<uint32_t>(two.positions.size());
  const size_t index_count = two.indices.size();
  for (uint32_t i = 0; i < count; ++i) two.positions.push_back(two.positions[i] + glm::vec3(3.0f, 0.0f, 0.0f));
  for (size_t i = 0; i < index_count; ++i) two.indices.push_back(two.indices[i] + count);
  EXPECT_FALSE(is_convex_solid(two)) << "two spheres";

  Mesh dented = make_sphere(1.0f, 32, 16);
  dented.positions[8 * 33 + 10] *= 0.9f;  // stack 8 (the equator), slice 10: one vertex, no seam copy
  EXPECT_FALSE(is_convex_solid(dented)) << "a dent";

  Mesh inside_out = make_sphere(1.0f, 32, 16);
  for (size_t t = 0; t < inside_out.indices.size(); t += 3) std::swap(inside_out.indices[t + 1], inside_out.indices[t + 2]);
  EXPECT_FALSE(is_convex_solid(inside_out)) << "wound inside out";
}

namespace {

// A prism over the polygon that visits the corners of a regular heptagon `step` at a time: step 1
// is the convex heptagonal prism, step 2 the prism over the star {7/2}, which turns the same way at
// every corner but goes round twice. Each cap is a fan about its centre, wound counter-clockwise seen
// from outside like the sides.
Mesh star_prism(int step) {
  Mesh m;
  constexpr int kCorners = 7;
  for (float y : {-0.5f, 0.5f}) {
    for (int k = 0; k < kCorners; ++k) {
      const float angle = 2.0f * 3.14159265f * static_cast<float>(k * step % kCorners) / kCorners;
      m.positions.emplace_back(std::cos(angle), y, -std::sin(angle));  // counter-clockwise seen from +y
    }
  }
  const auto bottom_centre = static_cast<uint32_t>(m.positions.size());
  m.positions.emplace_back(0.0f, -0.5f, 0.0f);
  m.positions.emplace_back(0.0f, 0.5f, 0.0f);
  for (uint32_t k = 0; k < kCorners; ++k) {
    const uint32_t next = (k + 1) % kCorners;
    const uint32_t b0 = k, b1 = next, t0 = kCorners + k, t1 = kCorners + next;
    m.indices.insert(m.indices.end(), {b0, b1, t1, b0, t1, t0});     // the side, facing out
    m.indices.insert(m.indices.end(), {bottom_centre + 1, t0, t1});  // the top cap, facing +y
    m.indices.insert(m.indices.end(), {bottom_centre, b1, b0});      // the bottom cap, facing -y
  }
  m.normals.assign(m.positions.size(), glm::vec3(0.0f, 1.0f, 0.0f));
  return m;
}

}  // namespace

// Closed, wound consistently, connected and convex at every edge, yet not convex: the star prism
// overlaps itself, which only the check of every vertex against every face's plane sees.
TEST(Convexity, ASurfaceConvexAtEveryEdgeThatOverlapsItselfIsNotConvex) {
  EXPECT_TRUE(is_convex_solid(star_prism(1))) << "the heptagonal prism, built the same way";
  EXPECT_FALSE(is_convex_solid(star_prism(2))) << "the prism over the star {7/2}";
}

// Scenes' solid refractors are convex or not as their meshes are (the hybrids read it on the device).
TEST(Convexity, ScenesFlagTheirConvexRefractors) {
  auto convex_of = [](const char* file) {
    std::map<std::string, bool> out;
    for (const auto& o : load_scene_file((kSource / "scenes" / file).string()).objects) {
      if (o.material.refractor) out[o.name] = is_convex_refractor(o);
    }
    return out;
  };
  EXPECT_EQ(convex_of("sphere_plane.json"), (std::map<std::string, bool>{{"ball", true}}));
  EXPECT_EQ(convex_of("three_refractors.json"), (std::map<std::string, bool>{{"sphere", true}, {"slab", true}, {"box", true}}));
  EXPECT_EQ(convex_of("torus.json").begin()->second, false);
  EXPECT_EQ(convex_of("bunny_plane.json").begin()->second, false);
  // Thin walls are not solids: light passes them unbent, image space sees their path exactly.
  for (const auto& [name, convex] : convex_of("thin_panes.json")) EXPECT_FALSE(convex) << name;
}

// Convexity is derived from the mesh when asked, never cached at load: a ball dented after loading
// (tests change meshes so) is not taken for the convex ball it was.
TEST(Convexity, AMeshChangedAfterLoadingIsJudgedAsItIsNow) {
  Scene scene = load_scene_file((kSource / "scenes/sphere_plane.json").string());
  auto ball = std::find_if(scene.objects.begin(), scene.objects.end(), [](const Object& o) { return o.material.refractor; });
  ASSERT_NE(ball, scene.objects.end());
  EXPECT_TRUE(is_convex_refractor(*ball));
  const glm::vec3 center = ball->center();
  glm::vec3& vertex = ball->mesh.positions[ball->mesh.indices[ball->mesh.indices.size() / 2]];
  vertex = center + 0.8f * (vertex - center);
  EXPECT_FALSE(is_convex_refractor(*ball));
}

TEST(MeshFiles, LoadTheStanfordModelsDebianShips) {
  auto bunny = load_mesh_file("/usr/share/glmark2/models/bunny.obj");
  ASSERT_EQ(bunny.size(), 1u);
  EXPECT_EQ(bunny[0].mesh.positions.size(), 34835u);  // counted with grep in the file itself
  EXPECT_EQ(bunny[0].mesh.indices.size(), 3u * 69666u);
  EXPECT_EQ(bunny[0].mesh.normals.size(), bunny[0].mesh.positions.size());
  auto armadillo = load_mesh_file((kSource / "scenes/models/armadillo.off").string());
  EXPECT_EQ(armadillo[0].mesh.positions.size(), 26002u);  // the OFF header's counts
  EXPECT_EQ(armadillo[0].mesh.indices.size(), 3u * 52000u);
}

TEST(MeshFiles, GltfMaterialsBecomeRefractors) {
  // A glTF triangle with KHR_materials_transmission, _ior and _volume, and no normals.
  const std::string buffer = "AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAIAAAA=";  // 3 vec3 + 3 uint16 (+2 pad)
  const std::string gltf = R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
    "nodes": [{"mesh": 0, "translation": [0, 0, 5]}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
    "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.4, 0.6, 1], "roughnessFactor": 0.25},
                   "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1},
                                  "KHR_materials_ior": {"ior": 1.33},
                                  "KHR_materials_dispersion": {"dispersion": 0.5},
                                  "KHR_materials_volume": {"thicknessFactor": 0.5, "attenuationColor": [0.5, 1, 1],
                                                           "attenuationDistance": 2}}}],
    "extensionsUsed": ["KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_volume", "KHR_materials_dispersion"],
    "extensionsRequired": ["KHR_materials_dispersion"],
    "buffers": [{"byteLength": 44, "uri": "data:application/octet-stream;base64,)" +
                           buffer + R"("}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 6}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
                  {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}]})";
  auto parts = load_mesh_file(write_temp("caustica_scene_test.gltf", gltf).string());
  ASSERT_EQ(parts.size(), 1u);
  ASSERT_TRUE(parts[0].material.has_value());
  const Material& m = *parts[0].material;
  EXPECT_TRUE(m.refractor);
  EXPECT_FALSE(m.thin);                            // a volume with a thickness
  EXPECT_EQ(m.tint, glm::vec3(0.2f, 0.4f, 0.6f));  // transmitted light takes the base colour
  EXPECT_FLOAT_EQ(m.ior, 1.33f);
  EXPECT_FLOAT_EQ(m.dispersion, 0.5f);               // 20 / Abbe number 40: n_F - n_C = 0.33 / 40
  EXPECT_FLOAT_EQ(m.transmission_roughness, 0.25f);  // transmission is as rough as the surface
  EXPECT_NEAR(m.band_iors().z - m.band_iors().x, 0.33f / 40.0f, 1e-6f);
  EXPECT_NEAR(m.absorption.r, std::log(2.0f) / 2.0f, 1e-5f);  // half the red left after 2 units
  EXPECT_FLOAT_EQ(m.absorption.g, 0.0f);
  const Mesh& mesh = parts[0].mesh;
  ASSERT_EQ(mesh.positions.size(), 3u);
  EXPECT_FLOAT_EQ(mesh.positions[1].x, 1.0f);
  EXPECT_FLOAT_EQ(mesh.positions[1].z, 5.0f);  // the node's translation is applied
  ASSERT_EQ(mesh.normals.size(), 3u);          // computed, since the file has none
  EXPECT_NEAR(mesh.normals[0].z, 1.0f, 1e-6f);
}

// KHR_materials_transmission without a volume, or with thicknessFactor 0, is a thin wall; the
// transmission factor is kept as it is.
// KHR_texture_transform as its definition gives it (uv' = translation * rotation * scale * uv),
// checked on the texels that chosen texture coordinates reach, worked out by hand: on
// tests/data/gltf/texture_transform.gltf's 4 x 4 texture (texel (x, y) is (40 + 60 x, 40 + 60 y,
// 10), NEAREST, REPEAT). The extension's own example (offset [0, 1], rotation pi/2, scale 0.5)
// maps (u, v) to (0.5 v, 1 - 0.5 u): the lower left quadrant, turned; the other material maps it to
// (2 u + 0.25, 2 v). A rotation of the other sign, or the scale applied after the offset, reaches
// other texels. The Embree reference uses the same matrix, so this is what pins it.
TEST(MeshFiles, TextureTransformsReachTheTexelsTheExtensionDefines) {
  const Scene s = load_model_scene((kSource / "tests/data/gltf/texture_transform.gltf").string(), false);
  ASSERT_EQ(s.objects.size(), 2u);
  struct Probe {
    glm::vec2 uv;
    int x, y;  // the texel it must reach
  };
  auto check = [&](const char* which, const Object& object, std::initializer_list<Probe> probes) {
    const TextureRef& ref = object.material.base_color_texture;
    ASSERT_TRUE(ref.used()) << which;
    const Texture& texture = s.textures.at(static_cast<size_t>(ref.texture));
    ASSERT_EQ(texture.width, 4u);
    for (const auto& probe : probes) {
      const glm::vec4 got = texture.sample(glm::vec2(ref.transform * glm::vec3(probe.uv, 1.0f)));
      const glm::vec3 want(srgb_byte_to_linear(static_cast<uint8_t>(40 + 60 * probe.x)),
                           srgb_byte_to_linear(static_cast<uint8_t>(40 + 60 * probe.y)), srgb_byte_to_linear(10));
      EXPECT_NEAR(got.r, want.r, 1e-6f) << which << " at uv (" << probe.uv.x << ", " << probe.uv.y << ")";
      EXPECT_NEAR(got.g, want.g, 1e-6f) << which << " at uv (" << probe.uv.x << ", " << probe.uv.y << ")";
      EXPECT_NEAR(got.b, want.b, 1e-6f) << which;
    }
  };
  const bool floor_first = s.objects[0].bounds_max.y < 0.5f;
  const Object& floor = s.objects[floor_first ? 0 : 1];
  const Object& pane = s.objects[floor_first ? 1 : 0];
  check("the extension's example", floor,
        {{{0.1f, 0.1f}, 0, 3}, {{0.9f, 0.1f}, 0, 2}, {{0.1f, 0.9f}, 1, 3}, {{0.9f, 0.9f}, 1, 2}, {{0.3f, 0.7f}, 1, 3}});
  check("offset and scale", pane, {{{0.1f, 0.2f}, 1, 1}, {{0.45f, 0.3f}, 0, 2}, {{0.3f, 0.05f}, 3, 0}});
}

TEST(MeshFiles, GltfTransmissionWithoutThicknessIsThinWalled) {
  const std::string buffer = "AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAIAAAA=";
  for (const char* volume : {"", R"(, "KHR_materials_volume": {})", R"(, "KHR_materials_volume": {"thicknessFactor": 0})",
                             R"(, "KHR_materials_volume": {"thicknessFactor": 0.01})"}) {
    SCOPED_TRACE(volume);
    const std::string gltf = R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
      "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
      "materials": [{"extensions": {"KHR_materials_transmission": {"transmissionFactor": 0.75})" +
                             std::string(volume) + R"(}}],
      "buffers": [{"byteLength": 44, "uri": "data:application/octet-stream;base64,)" +
                             buffer + R"("}],
      "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 6}],
      "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
                    {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}]})";
    const auto parts = load_mesh_file(write_temp("caustica_thin_test.gltf", gltf).string());
    ASSERT_EQ(parts.size(), 1u);
    const Material& m = parts[0].material.value();
    EXPECT_TRUE(m.refractor);
    EXPECT_EQ(m.thin, std::string(volume).find("0.01") == std::string::npos);
    EXPECT_FLOAT_EQ(m.transmission, 0.75f);
    EXPECT_EQ(m.tint, glm::vec3(1.0f));               // the default base colour
    EXPECT_FLOAT_EQ(m.transmission_roughness, 1.0f);  // the default roughnessFactor
  }
}

TEST(SceneFiles, BundledScenesLoadWithTheirRefractors) {
  struct Expect {
    const char* file;
    size_t refractors;
  };
  for (auto [file, refractors] : {Expect{"sphere_plane.json", 1}, Expect{"bunny_plane.json", 1}, Expect{"two_refractors.json", 2},
                                  Expect{"three_refractors.json", 3}, Expect{"torus.json", 1}, Expect{"armadillo.json", 1},
                                  Expect{"dragon.json", 1}, Expect{"no_refractor.json", 0}, Expect{"glass_bunny.json", 1}}) {
    Scene s = load_scene_file((kSource / "scenes" / file).string());
    EXPECT_EQ(s.refractor_count(), refractors) << file;
    for (const auto& o : s.objects) {
      EXPECT_EQ(o.mesh.normal_distance.size(), o.material.refractor ? o.mesh.positions.size() : 0u) << file << " " << o.name;
    }
  }
  // The ball lens: R = 1 centred 1.5 above the floor, as docs/oracles.md's focus case needs.
  Scene ball = load_scene_file((kSource / "scenes/sphere_plane.json").string());
  const Object& sphere = ball.objects.back();
  EXPECT_NEAR(sphere.center().y, 1.5f, 1e-5f);
  EXPECT_NEAR(sphere.bounds_max.y - sphere.bounds_min.y, 2.0f, 1e-5f);
}

TEST(SceneFiles, TransformsAreBakedAndMirrorsKeepWinding) {
  const std::string text = R"({"camera": {"position": [0, 0, 5]}, "lights": [{"position": [0, 5, 0]}],
    "objects": [{"name": "b", "primitive": {"type": "box"}, "transform": {"translate": [1, 2, 3], "scale": [-2, 1, 1]}}]})";
  Scene s = load_scene(JsonDocument::parse(text, "mirror.json"));
  const Object& box = s.objects[0];
  EXPECT_NEAR(box.bounds_min.x, 0.0f, 1e-6f);
  EXPECT_NEAR(box.bounds_max.x, 2.0f, 1e-6f);
  EXPECT_NEAR(box.center().z, 3.0f, 1e-6f);
  expect_outward(box.mesh, "mirrored box");
}

// A TANGENT carried by a transform stays a unit direction on the surface, and its bitangent sign
// flips with a mirror: the frame (t, w n x t) must be the transformed frame, and n x t flips.
TEST(SceneFiles, TangentsFollowTheirTransformAndMirrorsFlipTheirSign) {
  const glm::vec3 n(0, 1, 0), t(1, 0, 0);
  const glm::vec3 bitangent = -1.0f * glm::cross(n, t);  // w = -1 in the file
  for (const glm::mat4& m : {glm::scale(glm::mat4(1.0f), glm::vec3(3, 1, 1)),
                             glm::scale(glm::rotate(glm::mat4(1.0f), 0.7f, glm::vec3(0, 1, 0)), glm::vec3(-2, 1, 1)),
                             glm::scale(glm::mat4(1.0f), glm::vec3(1, 1, -1))}) {
    const glm::vec4 carried = carry_tangent(m, glm::vec4(t, -1.0f));
    const glm::vec3 carried_normal = glm::normalize(glm::transpose(glm::inverse(glm::mat3(m))) * n);
    const glm::vec3 expected_tangent = glm::normalize(glm::mat3(m) * t);
    const glm::vec3 expected_bitangent = glm::normalize(glm::mat3(m) * bitangent);
    EXPECT_NEAR(glm::length(glm::vec3(carried) - expected_tangent), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::length(carried.w * glm::cross(carried_normal, glm::vec3(carried)) - expected_bitangent), 0.0f, 1e-6f);
  }
}

// The BVH order (scene/bvh_order.h) keeps every triangle, each with its vertices in their winding
// order, and at every level of the split the first half lies no further along the longest axis
// than the second: checked at the top level of a shuffled sphere, where file order would fail it.
TEST(BvhOrder, IsAPermutationSplitAtTheMedianOfTheLongestAxis) {
  Mesh sphere = make_sphere(1.0f, 32, 16);
  for (auto& p : sphere.positions) p.x *= 3.0f;  // x is the longest axis
  // Triangles interleaved from both ends, so input order says nothing about position.
  std::vector<uint32_t> shuffled;
  const size_t triangles = sphere.indices.size() / 3;
  for (size_t i = 0; i < triangles; ++i) {
    const size_t t = i % 2 == 0 ? i / 2 : triangles - 1 - i / 2;
    shuffled.insert(shuffled.end(), sphere.indices.begin() + static_cast<std::ptrdiff_t>(3 * t),
                    sphere.indices.begin() + static_cast<std::ptrdiff_t>(3 * t + 3));
  }
  const std::vector<uint32_t> ordered = bvh_triangle_order(sphere.positions, shuffled);
  ASSERT_EQ(ordered.size(), shuffled.size());
  auto key = [](const uint32_t* v) { return std::array<uint32_t, 3>{v[0], v[1], v[2]}; };
  std::multiset<std::array<uint32_t, 3>> before, after;
  for (size_t t = 0; t < shuffled.size(); t += 3) before.insert(key(&shuffled[t]));
  for (size_t t = 0; t < ordered.size(); t += 3) after.insert(key(&ordered[t]));
  EXPECT_EQ(before, after);
  auto centroid_x = [&](size_t t) {
    return (sphere.positions[ordered[3 * t]].x + sphere.positions[ordered[3 * t + 1]].x + sphere.positions[ordered[3 * t + 2]].x) / 3.0f;
  };
  const size_t middle = triangles / 2;
  float first_max = -1e30f, second_min = 1e30f;
  for (size_t t = 0; t < middle; ++t) first_max = std::max(first_max, centroid_x(t));
  for (size_t t = middle; t < triangles; ++t) second_min = std::min(second_min, centroid_x(t));
  EXPECT_LE(first_max, second_min);
  // The same within the first half, whose longest axis is still x (3 against 2 and 2).
  float quarter_max = -1e30f, quarter_min = 1e30f;
  for (size_t t = 0; t < middle / 2; ++t) quarter_max = std::max(quarter_max, centroid_x(t));
  for (size_t t = middle / 2; t < middle; ++t) quarter_min = std::min(quarter_min, centroid_x(t));
  EXPECT_LE(quarter_max, quarter_min);
}

// A model file opened as a scene of its own (--scene model.gltf): what the file holds is used as
// its author placed it; what it lacks is made up around the model.
TEST(ModelScenes, TheFilesCameraAndLightsAreUsed) {
  const Scene s = load_model_scene((kSource / "tests/data/gltf/cube_camera_spot.gltf").string());
  // The camera node: translation (0, 1.5, 4), pitched down 15 degrees; yfov 0.6 rad.
  EXPECT_NEAR(glm::distance(s.camera.position, glm::vec3(0, 1.5f, 4)), 0.0f, 1e-4f);
  const glm::vec3 forward = glm::normalize(s.camera.target - s.camera.position);
  EXPECT_NEAR(forward.y, -std::sin(glm::radians(15.0f)), 1e-3f);
  EXPECT_NEAR(forward.z, -std::cos(glm::radians(15.0f)), 1e-3f);
  EXPECT_NEAR(s.camera.fov_y_degrees, glm::degrees(0.6f), 1e-3f);
  // The spot light node: at (1, 4, 0) looking straight down, cone twice outerConeAngle.
  ASSERT_EQ(s.lights.size(), 1u);
  EXPECT_EQ(s.lights[0].type, LightType::spot);
  EXPECT_NEAR(glm::distance(s.lights[0].view.position, glm::vec3(1, 4, 0)), 0.0f, 1e-4f);
  EXPECT_NEAR(glm::normalize(s.lights[0].view.target - s.lights[0].view.position).y, -1.0f, 1e-4f);
  EXPECT_NEAR(s.lights[0].view.fov_y_degrees, glm::degrees(0.8f), 1e-3f);
  EXPECT_FLOAT_EQ(s.lights[0].intensity, 30.0f);
  EXPECT_NEAR(s.lights[0].color.z, 0.8f, 1e-6f);
  // The cube is glass (transmission 1, ior 1.5) at y 0..1, and the stage's floor lies under it.
  ASSERT_EQ(s.objects.size(), 2u);
  EXPECT_TRUE(s.objects[0].material.refractor);
  EXPECT_NEAR(s.objects[0].bounds_min.y, 0.0f, 1e-5f);
  EXPECT_FALSE(s.objects[1].material.refractor);
  EXPECT_NEAR(s.objects[1].bounds_max.y, 0.0f, 1e-2f);
  EXPECT_LE(s.objects[1].bounds_max.y, 0.0f);
  EXPECT_EQ(load_model_scene((kSource / "tests/data/gltf/cube_camera_spot.gltf").string(), false).objects.size(), 1u);
}

TEST(ModelScenes, AModelWithoutCameraOrLightIsFramedAndLitForACaustic) {
  const Scene s = load_scene_file("/usr/share/glmark2/models/bunny.obj");
  ASSERT_EQ(s.objects.size(), 2u);
  const Object& model = s.objects[0];
  // Every corner of the model's box is in the camera's view and in the light's cone.
  for (int corner = 0; corner < 8; ++corner) {
    const glm::vec3 p((corner & 1) ? model.bounds_max.x : model.bounds_min.x, (corner & 2) ? model.bounds_max.y : model.bounds_min.y,
                      (corner & 4) ? model.bounds_max.z : model.bounds_min.z);
    for (const View* view : {&s.camera, &s.lights[0].view}) {
      const glm::vec4 clip = view->view_projection(view == &s.camera ? 16.0f / 9.0f : 1.0f) * glm::vec4(p, 1.0f);
      EXPECT_GT(clip.w, 0.0f);
      EXPECT_LE(std::abs(clip.x / clip.w), 1.0f) << "corner " << corner;
      EXPECT_LE(std::abs(clip.y / clip.w), 1.0f) << "corner " << corner;
    }
  }
  // The light is above the model, and the floor under it.
  ASSERT_EQ(s.lights.size(), 1u);
  EXPECT_GT(s.lights[0].view.position.y, model.bounds_max.y);
  EXPECT_NEAR(s.objects[1].bounds_max.y, model.bounds_min.y, 0.01f * glm::length(model.bounds_max - model.bounds_min));
  EXPECT_GT(s.ambient, 0.0f);
}

// The same cube stored three ways (floats; KHR_mesh_quantization's shorts and normalized bytes; a
// sparse accessor over no buffer view) is the same geometry to the vertex.
TEST(ModelScenes, QuantizedAndSparseEncodingsReadAsTheFloatOriginal) {
  const Scene original = load_model_scene((kSource / "tests/data/gltf/cube_camera_spot.gltf").string(), false);
  for (const char* encoded : {"cube_quantized.gltf", "cube_sparse.gltf"}) {
    SCOPED_TRACE(encoded);
    const Scene s = load_model_scene((kSource / "tests/data/gltf" / encoded).string(), false);
    ASSERT_EQ(s.objects.size(), original.objects.size());
    const Mesh &a = s.objects[0].mesh, &b = original.objects[0].mesh;
    ASSERT_EQ(a.positions.size(), b.positions.size());
    EXPECT_EQ(a.indices, b.indices);
    for (size_t i = 0; i < a.positions.size(); ++i) {
      EXPECT_EQ(a.positions[i], b.positions[i]) << i;
      EXPECT_EQ(a.normals[i], b.normals[i]) << i;
    }
  }
}

// The dragon compressed by the extensions' own encoders (tests/data/gltf/make_compressed.sh):
// Draco and meshoptimizer (with KHR_mesh_quantization) decode to the OFF file's triangles, with the
// same winding, every vertex within the encoder's quantization step of the original (16 bits for
// Draco, gltfpack's 14, of the largest extent), or exactly the original for the lossless encodings.
TEST(ModelScenes, CompressedMeshesDecodeToTheOriginalTriangles) {
  const Mesh original = load_model_file((kSource / "scenes/models/ChineseDragon-10kv.off").string()).parts.at(0).mesh;
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (const auto& p : original.positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const float extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
  std::vector<uint32_t> by_x(original.positions.size());
  for (uint32_t i = 0; i < by_x.size(); ++i) by_x[i] = i;
  std::sort(by_x.begin(), by_x.end(), [&](uint32_t a, uint32_t b) { return original.positions[a].x < original.positions[b].x; });
  // A triangle as original vertex ids, rotated so the smallest comes first (winding kept).
  auto key = [](uint32_t a, uint32_t b, uint32_t c) {
    if (b < a && b < c) return std::array<uint32_t, 3>{b, c, a};
    if (c < a && c < b) return std::array<uint32_t, 3>{c, a, b};
    return std::array<uint32_t, 3>{a, b, c};
  };
  std::multiset<std::array<uint32_t, 3>> expected;
  for (size_t t = 0; t < original.indices.size(); t += 3)
    expected.insert(key(original.indices[t], original.indices[t + 1], original.indices[t + 2]));

  // bits 0: lossless, every vertex exactly an original one.
  for (const auto& [file, bits] : {std::pair{"dragon_draco.glb", 16}, std::pair{"dragon_meshopt.glb", 14},
                                   std::pair{"dragon_draco_lossless.glb", 0}, std::pair{"dragon_meshopt_lossless.glb", 0}}) {
    SCOPED_TRACE(file);
    const ModelFile model = load_model_file((kSource / "tests/data/gltf" / file).string());
    ASSERT_EQ(model.parts.size(), 1u);
    const Mesh& m = model.parts[0].mesh;
    ASSERT_EQ(m.indices.size(), original.indices.size());
    const float tolerance = bits ? extent / static_cast<float>(1 << bits) : 0.0f;
    std::vector<uint32_t> nearest(m.positions.size());
    size_t unmatched = 0;
    for (size_t v = 0; v < m.positions.size(); ++v) {
      const glm::vec3 p = m.positions[v];
      auto first =
          std::lower_bound(by_x.begin(), by_x.end(), p.x - tolerance, [&](uint32_t i, float x) { return original.positions[i].x < x; });
      float best = tolerance;
      nearest[v] = UINT32_MAX;
      for (auto it = first; it != by_x.end() && original.positions[*it].x <= p.x + tolerance; ++it) {
        const float d = glm::length(original.positions[*it] - p);
        if (d <= best) {
          best = d;
          nearest[v] = *it;
        }
      }
      unmatched += nearest[v] == UINT32_MAX;
    }
    EXPECT_EQ(unmatched, 0u) << "vertices farther than " << tolerance << " from every original vertex";
    std::multiset<std::array<uint32_t, 3>> decoded;
    for (size_t t = 0; t < m.indices.size(); t += 3)
      decoded.insert(key(nearest[m.indices[t]], nearest[m.indices[t + 1]], nearest[m.indices[t + 2]]));
    std::vector<std::array<uint32_t, 3>> missing;
    std::set_difference(expected.begin(), expected.end(), decoded.begin(), decoded.end(), std::back_inserter(missing));
    EXPECT_EQ(missing.size(), 0u) << "original triangles not decoded, of " << expected.size();
  }
}

// A directional light without an extent gets an orthographic view fitted around every object (its
// prism holds all their bounding-box corners) with a far plane past them; its projection maps the
// plane through its position to depth 0, and points along the axis to the view's centre.
TEST(SceneFiles, DirectionalLightsFitTheirViewAroundTheScene) {
  const Scene s = load_scene(JsonDocument::parse(R"({
    "camera": {"position": [0, 4, 6], "target": [0, 0, 0]},
    "lights": [{"type": "directional", "position": [1, 10, 0], "target": [1, 0, 0], "intensity": 3}],
    "objects": [{"name": "floor", "primitive": {"type": "plane", "size": [6, 4]}},
                {"name": "box", "primitive": {"type": "box", "size": [1, 1, 1]}, "transform": {"translate": [-2, 3, 1]}}]})",
                                                 "directional.json"));
  const Light& light = s.lights.at(0);
  ASSERT_EQ(light.type, LightType::directional);
  EXPECT_TRUE(light.has_caustic_view);
  // The floor's corner (-3, 0, +-2) is the farthest from the axis x = 1, z = 0: sqrt(16 + 4).
  EXPECT_NEAR(light.extent, 1.02f * std::sqrt(20.0f), 1e-4f);
  EXPECT_GE(light.view.far_plane, 10.0f);
  const glm::mat4 m = light.view_projection();
  auto project = [&](glm::vec3 p) {
    const glm::vec4 c = m * glm::vec4(p, 1.0f);
    return glm::vec3(c) / c.w;
  };
  EXPECT_NEAR(project({1, 10 - light.view.near_plane, 0}).z, 0.0f, 1e-5f);
  EXPECT_NEAR(project({1, 2, 0}).x, 0.0f, 1e-5f);
  EXPECT_NEAR(project({1, 2, 0}).y, 0.0f, 1e-5f);
  EXPECT_NEAR(std::abs(project({1 + light.extent, 5, 0}).x), 1.0f, 1e-5f);  // the view's edge, whatever the depth
  EXPECT_NEAR(std::abs(project({1 + light.extent, 1, 0}).x), 1.0f, 1e-5f);
  EXPECT_THROW(load_scene(JsonDocument::parse(R"({"camera": {"position": [0, 4, 6], "target": [0, 0, 0]},
    "lights": [{"type": "spot", "position": [0, 5, 0], "target": [0, 0, 0], "extent": 2}],
    "objects": [{"name": "floor", "primitive": {"type": "plane"}}]})",
                                              "spot_extent.json")),
               InputError);
}

// A glTF directional light stays directional: its direction from the node, the file's illuminance
// as irradiance, and an orthographic view fitted to the model (not to the stage's floor).
TEST(ModelScenes, AGltfDirectionalLightIsDirectional) {
  std::ifstream in(kSource / "tests/data/gltf/cube_camera_spot.gltf");
  std::ostringstream file;
  file << in.rdbuf();
  std::string text = file.str();
  const std::string spot = R"("type": "spot",)";
  ASSERT_NE(text.find(spot), std::string::npos);
  text.replace(text.find(spot), spot.size(), R"("type": "directional",)");
  const Scene s = load_model_scene(write_temp("caustica_directional.gltf", text).string());
  ASSERT_EQ(s.lights.size(), 1u);
  const Light& light = s.lights[0];
  EXPECT_EQ(light.type, LightType::directional);
  EXPECT_NEAR(light.axis().y, -1.0f, 1e-4f);  // the node looks straight down
  EXPECT_FLOAT_EQ(light.intensity, 30.0f);
  // The unit cube's corners lie within sqrt(0.5) of the vertical axis through its centre; the
  // 8-radius floor would need far more.
  EXPECT_NEAR(light.extent, 1.02f * std::sqrt(0.5f), 1e-3f);
}

// The translucent surfaces' patches (scene/translucent_samples.h): kTranslucentSamples of them over
// the leaf lying flat 1 above the floor (2 x 2, diffuseTransmissionFactor 0.7, colour (0.7, 1, 0.2),
// metallic 0), each a 64th of its area 4, on it, its normal vertical, passing 0.7 colour / pi; none
// over a scene without a translucent surface.
TEST(TranslucentSamples, CoverTheTranslucentAreaAndPassItsShare) {
  const Scene leaf = load_scene_file((kSource / "tests/data/surfaces/leaf_over_floor.json").string());
  const auto patches = translucent_samples(leaf);
  ASSERT_EQ(patches.size(), kTranslucentSamples);
  std::set<std::pair<int, int>> cells;  // which of the 8 x 8 cells of the leaf each patch lies in
  for (const auto& patch : patches) {
    EXPECT_NEAR(patch.position_area.w, 4.0f / 64.0f, 1e-6f);
    EXPECT_NEAR(patch.position_area.y, 1.0f, 1e-5f);
    EXPECT_LE(std::abs(patch.position_area.x), 1.0f + 1e-5f);
    EXPECT_LE(std::abs(patch.position_area.z), 1.0f + 1e-5f);
    EXPECT_NEAR(std::abs(patch.normal_object.y), 1.0f, 1e-5f);
    EXPECT_EQ(leaf.objects[size_t(patch.normal_object.w)].name, "leaf");
    const float pi = 3.14159265f;
    EXPECT_NEAR(patch.passed.r, 0.7f * 0.7f / pi, 1e-6f);
    EXPECT_NEAR(patch.passed.g, 0.7f / pi, 1e-6f);
    EXPECT_NEAR(patch.passed.b, 0.7f * 0.2f / pi, 1e-6f);
    cells.insert({std::min(7, int((patch.position_area.x + 1.0f) * 4.0f)), std::min(7, int((patch.position_area.z + 1.0f) * 4.0f))});
  }
  // Spread over the leaf, not bunched: most of the 64 cells of an 8 x 8 grid hold one (40 or more;
  // 64 points thrown at random fill 40.7 on average; the folded R2 points filled 47 when written).
  std::printf("%zu of the 64 cells hold a patch\n", cells.size());
  EXPECT_GE(cells.size(), 45u);
  EXPECT_TRUE(translucent_samples(load_scene_file((kSource / "scenes/sphere_plane.json").string())).empty());
}
