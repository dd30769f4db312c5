#include "scene/translucent_samples.h"

#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>
#include <glm/gtc/constants.hpp>

namespace caustica::scene {
namespace {

struct AreaTriangle {
  uint32_t object, first_index;
  float area;
};

bool translucent(const Object& o) {
  return !o.material.refractor && o.material.diffuse_transmission > 0.0f;
}

}  // namespace

std::vector<gpu::TranslucentSample> translucent_samples(const Scene& scene) {
  std::vector<AreaTriangle> triangles;
  double total = 0.0;
  for (uint32_t i = 0; i < scene.objects.size(); ++i) {
    const Object& o = scene.objects[i];
    if (!translucent(o)) continue;
    const auto& p = o.mesh.positions;
    for (uint32_t t = 0; t + 2 < o.mesh.indices.size(); t += 3) {
      const glm::vec3 a = p[o.mesh.indices[t]], b = p[o.mesh.indices[t + 1]], c = p[o.mesh.indices[t + 2]];
      const float area = 0.5f * glm::length(glm::cross(b - a, c - a));
      if (area <= 0.0f) continue;
      triangles.push_back({i, t, area});
      total += static_cast<double>(area);
    }
  }
  std::vector<gpu::TranslucentSample> samples;
  if (triangles.empty()) return samples;
  const float share = static_cast<float>(total / kTranslucentSamples);
  double below = 0.0;  // the area of the triangles before `next`
  size_t next = 0;
  uint32_t in_triangle = 0;  // the patches placed in triangle `next` so far
  for (uint32_t k = 0; k < kTranslucentSamples; ++k) {
    const double at = (k + 0.5) / kTranslucentSamples * total;
    while (next + 1 < triangles.size() && below + static_cast<double>(triangles[next].area) < at) {
      below += static_cast<double>(triangles[next++].area);
      in_triangle = 0;
    }
    const AreaTriangle& t = triangles[next];
    const Mesh& mesh = scene.objects[t.object].mesh;
    const glm::vec3 a = mesh.positions[mesh.indices[t.first_index]], b = mesh.positions[mesh.indices[t.first_index + 1]],
                    c = mesh.positions[mesh.indices[t.first_index + 2]];
    // The R2 sequence (Roberts 2018) in the unit square, each triangle's patches its first points,
    // folded onto the triangle (a point past the diagonal mirrored back), which keeps them spread
    // evenly: on a 2 x 2 square seen from 1 under its centre, 64 patches give its view factor to
    // 0.1%, where the square root's map gave 2.5% and one sequence run on across triangles 6%.
    ++in_triangle;
    double u = std::fmod(0.5 + in_triangle * 0.7548776662466927, 1.0), v = std::fmod(0.5 + in_triangle * 0.5698402909980532, 1.0);
    if (u + v > 1.0) {
      u = 1.0 - u;
      v = 1.0 - v;
    }
    const glm::vec3 point = a + static_cast<float>(u) * (b - a) + static_cast<float>(v) * (c - a);
    const glm::vec3 normal = glm::normalize(glm::cross(b - a, c - a));
    // The Lambertian BTDF of the lighting pass's back-lit surface (scene/surface.glsl) with the
    // patch's own texels, as the G-buffer reads them there (a leaf's veins pass less than its blade):
    // each factor times its texture, metal passing nothing.
    const Object& object = scene.objects[t.object];
    const Material& m = object.material;
    const SurfaceTextures& st = m.surface_textures;
    auto texel = [&](const TextureRef& ref) {
      return texel_at(scene, object, ref, t.first_index / 3, static_cast<float>(u), static_cast<float>(v));
    };
    const float metallic = m.metallic_roughness ? m.metallic * texel(m.metallic_roughness_texture).b : 0.0f;
    const float share_passed =
        factor_or(st.diffuse_transmission, st.diffuse_transmission_factor, m.diffuse_transmission) * texel(st.diffuse_transmission).a;
    const glm::vec3 colour = factor_or(st.diffuse_transmission_color, st.diffuse_transmission_color_factor, m.diffuse_transmission_color) *
                             glm::vec3(texel(st.diffuse_transmission_color));
    const glm::vec3 passed = (1.0f - metallic) * share_passed * colour / glm::pi<float>();
    samples.push_back({glm::vec4(point, share), glm::vec4(normal, static_cast<float>(t.object)), glm::vec4(passed, 0.0f)});
  }
  return samples;
}

}  // namespace caustica::scene
