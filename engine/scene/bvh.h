#pragma once
// The compute tracer's structure (shaders/scene/trace_bvh.glsl): the scene's triangles in one
// binary BVH built on the host with a binned surface-area heuristic, laid out for a GLSL stack
// traversal. Built without a device, so that tests check it on the CPU; GpuScene uploads it.
//
// One array of vec4 words (the shader's BvhBlock):
//   word 0: x = the first triangle's word, as uint bits (the nodes end there);
//   node n at words 1 + 4n .. 4 + 4n, both children's boxes in their parent (one fetch tests both):
//     (child 0's min xyz, link 0), (child 0's max xyz, info 0), (child 1's min, link 1), (child 1's max, info 1)
//     info: bits 0-7 the union of the instance masks beneath (scene_types.h), bits 8-31 a leaf's
//     triangle count (0: link is a node); link: that node, or the leaf's first triangle.
//     An empty child (a one-leaf tree's second) has an inverted box and mask 0.
//   triangle t at words base + 3t .. base + 3t + 2: its vertices' positions in xyz; w of the first,
//     as uint bits: its instance mask in bits 0-7, kBvhMaskedMaterial where a MASK material cuts it.
// `triangle_vertices` (the shader's TriangleBlock, three per triangle, in the same order) index the
// GpuScene's vertex buffer for normals, texture coordinates and the object.
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"

namespace caustica::scene {

inline constexpr uint32_t kBvhMaskedMaterial = 1u << 8;
// The deepest tree the builder makes (a deeper range becomes one leaf): the shader's stack size.
inline constexpr uint32_t kBvhMaxDepth = 48;  // CAUSTICA_BVH_MAX_DEPTH (shaders/common/scene_types.h)

// One triangle to build from: its corners and what the traversal tests about it.
struct BvhInputTriangle {
  glm::vec3 v0, v1, v2;
  uint32_t flags = 0;         // the instance mask and kBvhMaskedMaterial, as stored
  uint32_t vertices[3] = {};  // carried into triangle_vertices
};

struct TracerBvh {
  std::vector<glm::vec4> words;
  std::vector<uint32_t> triangle_vertices;
  uint32_t node_count = 0, triangle_count = 0, depth = 0, leaf_count = 0;
  uint32_t first_triangle_word() const;
  uint64_t bytes() const { return words.size() * sizeof(glm::vec4) + triangle_vertices.size() * sizeof(uint32_t); }
};

TracerBvh build_bvh(std::vector<BvhInputTriangle> triangles);
// Every object's triangles, `vertex_base[o]` being where object o's vertices start in the
// GpuScene's vertex buffer; masks as the ray-query structures' (engine/scene/acceleration.cpp).
TracerBvh build_scene_bvh(const Scene& scene, const std::vector<uint32_t>& vertex_base);

// What is wrong with `bvh`, or "": each of `triangle_count` input triangles stored once, every box
// holding what lies beneath it, every mask the union of those beneath, no node reached twice,
// nothing deeper than kBvhMaxDepth. The tests' check of the builder, and of the checker itself.
std::string check_bvh(const TracerBvh& bvh, uint32_t triangle_count);

}  // namespace caustica::scene
