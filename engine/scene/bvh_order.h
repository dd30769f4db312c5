#pragma once
// Triangle order for acceleration-structure builds. Mesa's lavapipe (25.0) builds its BVH by
// splitting the primitive list at the index midpoint in input order, without any spatial sort, so
// the order decides the tree: the bunny in file order traces 180-230 times slower than sorted.
// Sorting by a recursive longest-axis object-median split whose split index is (first + last) / 2
// makes lavapipe's tree that median-split BVH (measured best; Morton order was 1.2-2x slower). On
// other drivers, which sort themselves, the order costs nothing.
#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

namespace caustica::scene {

// The triangles of `indices` (three per triangle) reordered as above; the same triangles, each
// with its vertices in their original order.
std::vector<uint32_t> bvh_triangle_order(const std::vector<glm::vec3>& positions, const std::vector<uint32_t>& indices);

}  // namespace caustica::scene
