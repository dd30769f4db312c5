// Primitives with smooth normals where the surface is smooth and split vertices at creases.
#include <cmath>
#include <glm/gtc/constants.hpp>

#include "reference/ray_scene.h"
#include "scene/scene.h"

namespace caustica::scene {

Mesh make_sphere(float radius, int slices, int stacks) {
  Mesh m;
  for (int j = 0; j <= stacks; ++j) {
    const float theta = glm::pi<float>() * static_cast<float>(j) / static_cast<float>(stacks);
    for (int i = 0; i <= slices; ++i) {
      const float phi = glm::two_pi<float>() * static_cast<float>(i) / static_cast<float>(slices);
      const glm::vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta), -std::sin(theta) * std::sin(phi));
      m.positions.push_back(radius * n);
      m.normals.push_back(n);
    }
  }
  const auto row = static_cast<uint32_t>(slices + 1);
  for (uint32_t j = 0; j < static_cast<uint32_t>(stacks); ++j) {
    for (uint32_t i = 0; i < static_cast<uint32_t>(slices); ++i) {
      const uint32_t a = j * row + i, b = a + row;
      if (j != 0) m.indices.insert(m.indices.end(), {a, b, a + 1});
      if (j + 1 != static_cast<uint32_t>(stacks)) m.indices.insert(m.indices.end(), {a + 1, b, b + 1});
    }
  }
  return m;
}

Mesh make_plane(float width, float depth) {
  Mesh m;
  const float x = width / 2, z = depth / 2;
  m.positions = {{-x, 0, -z}, {-x, 0, z}, {x, 0, z}, {x, 0, -z}};
  m.normals.assign(4, glm::vec3(0, 1, 0));
  m.indices = {0, 1, 2, 0, 2, 3};
  return m;
}

Mesh make_box(glm::vec3 size) {
  Mesh m;
  const glm::vec3 h = size * 0.5f;
  for (int axis = 0; axis < 3; ++axis) {
    for (float sign : {1.0f, -1.0f}) {
      glm::vec3 n(0.0f);
      n[axis] = sign;
      const glm::vec3 u = axis == 1 ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
      const glm::vec3 v = glm::cross(n, u);
      const auto base = static_cast<uint32_t>(m.positions.size());
      for (auto [a, b] : {std::pair{-1.0f, -1.0f}, {1.0f, -1.0f}, {1.0f, 1.0f}, {-1.0f, 1.0f}}) {
        m.positions.push_back(h * (n + a * u + b * v));
        m.normals.push_back(n);
      }
      // Counter-clockwise seen from outside (u x v = n).
      m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    }
  }
  return m;
}

Mesh make_torus(float major_radius, float minor_radius, int segments, int sides) {
  Mesh m;
  for (int i = 0; i <= segments; ++i) {
    const float u = glm::two_pi<float>() * static_cast<float>(i) / static_cast<float>(segments);
    const glm::vec3 ring(std::cos(u), 0.0f, -std::sin(u));
    for (int j = 0; j <= sides; ++j) {
      const float v = glm::two_pi<float>() * static_cast<float>(j) / static_cast<float>(sides);
      const glm::vec3 n = std::cos(v) * ring + std::sin(v) * glm::vec3(0, 1, 0);
      m.positions.push_back(major_radius * ring + minor_radius * n);
      m.normals.push_back(n);
    }
  }
  const auto row = static_cast<uint32_t>(sides + 1);
  for (uint32_t i = 0; i < static_cast<uint32_t>(segments); ++i) {
    for (uint32_t j = 0; j < static_cast<uint32_t>(sides); ++j) {
      const uint32_t a = i * row + j, b = a + row;
      m.indices.insert(m.indices.end(), {a, b, b + 1, a, b + 1, a + 1});
    }
  }
  return m;
}

std::pair<glm::vec3, glm::vec3> mesh_bounds(const Mesh& mesh) {
  if (mesh.positions.empty()) return {glm::vec3(0.0f), glm::vec3(0.0f)};
  glm::vec3 lo = mesh.positions[0], hi = mesh.positions[0];
  for (const auto& p : mesh.positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  return {lo, hi};
}

std::vector<float> normal_distances(const Mesh& mesh) {
  reference::RayScene rays;
  rays.add_mesh(mesh.positions, mesh.indices);
  rays.commit();
  std::vector<float> out(mesh.positions.size(), 0.0f);
  const auto [lo, hi] = mesh_bounds(mesh);
  // Skip the triangles around the vertex itself: start a small fraction of the mesh's size inside.
  const float epsilon = 1e-4f * glm::length(hi - lo);
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    // A ray aimed exactly at a vertex of the far side can still pass between its triangles in
    // single precision; a slightly tilted ray finds the same surface.
    const glm::vec3 n = mesh.normals[i];
    const glm::vec3 tangent = glm::normalize(std::abs(n.x) < 0.9f ? glm::cross(n, glm::vec3(1, 0, 0)) : glm::cross(n, glm::vec3(0, 1, 0)));
    for (float tilt : {0.0f, 1e-3f, -1e-3f}) {
      if (auto hit = rays.intersect(mesh.positions[i], glm::normalize(-n + tilt * tangent), epsilon, std::numeric_limits<float>::infinity())) {
        out[i] = hit->distance;
        break;
      }
    }
  }
  return out;
}

}  // namespace caustica::scene
