#pragma once
// Exact ray casting against triangle meshes with Embree: d_N at load time now, the reference
// tracers later. One geometry per added mesh; hits report which.
#include <functional>
#include <glm/glm.hpp>
#include <memory>
#include <optional>
#include <vector>

namespace caustica::reference {

struct RayHit {
  float distance;
  uint32_t geometry;  // in the order meshes were added
  uint32_t triangle;
  glm::vec3 geometric_normal;  // unit length, facing where the triangle's winding says
  float u, v;                  // barycentric coordinates of vertices 1 and 2 of the triangle
};

class RayScene {
 public:
  RayScene();
  ~RayScene();
  RayScene(const RayScene&) = delete;
  RayScene& operator=(const RayScene&) = delete;

  // `cut_out(triangle, u, v)`, when given, says where a ray passes through the surface as if it
  // were not there (a MASK material's coverage below its cutoff); it must be thread-safe.
  using CutOut = std::function<bool(uint32_t triangle, float u, float v)>;
  uint32_t add_mesh(const std::vector<glm::vec3>& positions, const std::vector<uint32_t>& indices, CutOut cut_out = nullptr);
  void commit();
  // The nearest hit with distance in (near, far); thread-safe after commit().
  std::optional<RayHit> intersect(glm::vec3 origin, glm::vec3 direction, float near, float far) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::vector<std::unique_ptr<CutOut>> cut_outs_;  // Embree holds pointers to them
};

}  // namespace caustica::reference
