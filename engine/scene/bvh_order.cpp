#include "scene/bvh_order.h"

#include <algorithm>
#include <numeric>

namespace caustica::scene {
namespace {

struct Triangle {
  glm::vec3 centroid;
  uint32_t index;
};

// Sorts [first, last) into median-split order, with an explicit stack so that a degenerate mesh
// cannot exhaust the call stack.
void median_split(std::vector<Triangle>& triangles) {
  struct Range {
    size_t first, last;
  };
  std::vector<Range> stack{{0, triangles.size()}};
  while (!stack.empty()) {
    const Range r = stack.back();
    stack.pop_back();
    if (r.last - r.first < 2) continue;
    glm::vec3 lo(triangles[r.first].centroid), hi(lo);
    for (size_t i = r.first; i < r.last; ++i) {
      lo = glm::min(lo, triangles[i].centroid);
      hi = glm::max(hi, triangles[i].centroid);
    }
    const glm::vec3 extent = hi - lo;
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    const size_t middle = (r.first + r.last) / 2;
    // Ties broken by the original index, so the order is the same on every standard library.
    std::nth_element(triangles.begin() + static_cast<std::ptrdiff_t>(r.first), triangles.begin() + static_cast<std::ptrdiff_t>(middle),
                     triangles.begin() + static_cast<std::ptrdiff_t>(r.last), [axis](const Triangle& a, const Triangle& b) {
                       return a.centroid[axis] != b.centroid[axis] ? a.centroid[axis] < b.centroid[axis] : a.index < b.index;
                     });
    stack.push_back({r.first, middle});
    stack.push_back({middle, r.last});
  }
}

}  // namespace

std::vector<uint32_t> bvh_triangle_order(const std::vector<glm::vec3>& positions, const std::vector<uint32_t>& indices) {
  std::vector<Triangle> triangles(indices.size() / 3);
  for (uint32_t t = 0; t < triangles.size(); ++t) {
    const uint32_t* v = &indices[size_t{t} * 3];
    triangles[t] = {(positions[v[0]] + positions[v[1]] + positions[v[2]]) / 3.0f, t};
  }
  median_split(triangles);
  std::vector<uint32_t> out;
  out.reserve(triangles.size() * 3);
  for (const Triangle& t : triangles) {
    for (int k = 0; k < 3; ++k) out.push_back(indices[size_t{t.index} * 3 + static_cast<size_t>(k)]);
  }
  return out;
}

}  // namespace caustica::scene
