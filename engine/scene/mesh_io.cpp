// Mesh and model files by format (mesh_formats.h): what every format's meshes must satisfy, and
// the normals the files leave out.
#include <cmath>
#include <filesystem>

#include "core/error.h"
#include "io/json_reader.h"
#include "scene/mesh_formats.h"

namespace caustica::scene {
namespace formats {

[[noreturn]] void fail(const std::string& path, size_t line, const std::string& message) {
  throw InputError(path + (line ? ":" + std::to_string(line) : std::string()) + ": " + message);
}

}  // namespace formats

namespace {

void check_mesh(const std::string& path, const Mesh& mesh) {
  if (mesh.indices.empty()) formats::fail(path, 0, "the mesh has no triangles");
  for (uint32_t index : mesh.indices) {
    if (index >= mesh.positions.size())
      formats::fail(path, 0, "a triangle refers to vertex " + std::to_string(index) + " of " + std::to_string(mesh.positions.size()));
  }
  // Coordinates as large as a scene file allows (1e6); beyond that ray casting overflows (a fuzzed
  // GLB with a vertex at 6e32 tripped an assertion inside Embree).
  for (const auto& p : mesh.positions) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) formats::fail(path, 0, "a vertex position is not finite");
    if (glm::any(glm::greaterThan(glm::abs(p), glm::vec3(1e6f)))) formats::fail(path, 0, "a vertex lies farther than 1e6 from the origin");
  }
}

}  // namespace

glm::vec4 carry_tangent(const glm::mat4& transform, glm::vec4 tangent) {
  const glm::mat3 m(transform);
  const glm::vec3 t = m * glm::vec3(tangent);
  const float len = glm::length(t);
  const float sign = (tangent.w < 0.0f) != (glm::determinant(m) < 0.0f) ? -1.0f : 1.0f;
  return {len > 0 && std::isfinite(len) ? t / len : glm::vec3(0.0f), sign};
}

void compute_smooth_normals(Mesh& mesh) {
  mesh.normals.assign(mesh.positions.size(), glm::vec3(0.0f));
  for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const uint32_t a = mesh.indices[t], b = mesh.indices[t + 1], c = mesh.indices[t + 2];
    const glm::vec3 n = glm::cross(mesh.positions[b] - mesh.positions[a], mesh.positions[c] - mesh.positions[a]);  // area-weighted
    mesh.normals[a] += n;
    mesh.normals[b] += n;
    mesh.normals[c] += n;
  }
  for (auto& n : mesh.normals) {
    const float len = glm::length(n);
    n = len > 0 ? n / len : glm::vec3(0, 1, 0);
  }
}

std::vector<MeshPart> load_mesh_file(const std::string& path) {
  return load_model_file(path).parts;
}

ModelFile load_model_file(const std::string& path) {
  const std::string extension = std::filesystem::path(path).extension().string();
  ModelFile model;
  std::vector<MeshPart>& parts = model.parts;
  if (extension == ".gltf" || extension == ".glb") {
    if (!std::filesystem::is_regular_file(path)) formats::fail(path, 0, "no such mesh file");
    model = formats::load_gltf(path);
  } else if (extension == ".obj" || extension == ".off") {
    const std::string text = read_text_file(path, formats::kMaxMeshFileBytes);
    parts.push_back({std::filesystem::path(path).stem().string(),
                     extension == ".obj" ? formats::load_obj(path, text) : formats::load_off(path, text), std::nullopt});
  } else {
    formats::fail(path, 0, "unknown mesh format '" + extension + "' (expected .gltf, .glb, .obj or .off)");
  }
  for (auto& part : parts) {
    check_mesh(path, part.mesh);
    if (part.mesh.normals.size() != part.mesh.positions.size()) compute_smooth_normals(part.mesh);
  }
  return model;
}

}  // namespace caustica::scene