#pragma once
// The light a diffusely-transmitting surface (glTF's KHR_materials_diffuse_transmission on an
// opaque, non-refracting material: a leaf) passes on to what lies behind it, single scattered: a
// light's direct irradiance E_i(q) on one side of the surface leaves its far side as Lambertian
// radiance (1 - metallic) d c / pi E_i(q), which an opaque receiver p gathers over the translucent
// surfaces' area,
//   E_t(p) = sum_i integral L_i(q) max(0, cos_p) |cos_q| / r^2 V(p, q) dA,
// counting only the q whose far side from light i faces p. Without it the leaf would cast a full
// shadow: the reference is the ground truth the engine's own approximation is to be measured by.
// The integral is estimated by Monte Carlo over area, the random numbers the shaded pixel's own
// (refraction_reference.cpp), so that a picture is the same on any number of threads.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <glm/glm.hpp>
#include <glm/gtc/constants.hpp>
#include <limits>
#include <vector>

#include "reference/exact_scene.h"

namespace caustica::reference {

// Area samples per shaded point. At 256 the floor point 1 below the centre of a 2 x 2 leaf has a
// relative standard deviation of 2.2% (64: 5%, 1024: 1%; translucent_light_test.cpp measures it):
// a faint grain on a soft light. Each sample costs up to one shadow ray per light and a visibility
// ray, only where the point faces a translucent surface's far side: tests/data/surfaces/
// translucent_leaf.json's 320 x 180 reference took 0.6 s on two cores instead of 0.06 s.
inline constexpr int kTranslucentAreaSamples = 256;

// How a light reaches point p, as shade_opaque lights a surface: the unit direction towards it, the
// squared distance its intensity falls off with (1 for a directional light, which has no falloff),
// how far a shadow ray from p may go before it meets the light, and the spot's cone.
struct LightArrival {
  glm::vec3 l;
  float d2;
  float reach;
  float cone;
};
inline LightArrival light_arrival(const scene::Light& light, glm::vec3 p, float epsilon) {
  const bool directional = light.type == scene::LightType::directional;
  const glm::vec3 to_light = directional ? -light.axis() : light.view.position - p;
  const float d2 = directional ? 1.0f : std::max(glm::dot(to_light, to_light), 1e-8f);
  const glm::vec3 l = to_light / std::sqrt(d2);
  const float reach = directional ? std::numeric_limits<float>::infinity() : std::sqrt(d2) - epsilon;
  return {l, d2, reach, spot_cone(light, -l)};
}

class TranslucentLight {
 public:
  explicit TranslucentLight(const ExactScene& exact) : exact_(exact) {
    const auto& objects = exact.scene().objects;
    passed_.resize(objects.size(), glm::vec3(0.0f));
    per_texel_.resize(objects.size(), false);
    double total = 0.0;
    for (uint32_t o = 0; o < objects.size(); ++o) {
      const scene::Material& m = objects[o].material;
      if (m.refractor || m.diffuse_transmission <= 0.0f) continue;
      // A Lambertian material (layered_brdf's roughness below 0) has no metal to take it away.
      const bool lambertian = !m.metallic_roughness || m.roughness < 0.0f;
      passed_[o] = diffuse_transmitted_color(lambertian ? 0.0f : m.metallic, m.diffuse_transmission, m.diffuse_transmission_color) /
                   glm::pi<float>();
      per_texel_[o] = scene::has_surface_textures(m) || m.metallic_roughness_texture.used();
      const auto& mesh = objects[o].mesh;
      for (uint32_t t = 0; t < mesh.indices.size() / 3; ++t) {
        const glm::vec3 a = mesh.positions[mesh.indices[3 * t]], b = mesh.positions[mesh.indices[3 * t + 1]],
                        c = mesh.positions[mesh.indices[3 * t + 2]];
        const double area = 0.5 * double(glm::length(glm::cross(b - a, c - a)));
        if (area <= 0.0) continue;
        total += area;
        triangles_.push_back({o, t});
        cdf_.push_back(total);
      }
    }
    for (double& c : cdf_) c /= total;
    area_ = float(total);
  }

  // Whether the scene has a translucent surface at all: without one, irradiance costs nothing.
  bool empty() const { return triangles_.empty(); }

  // E_t at p, whose unit normal n_p faces the side it receives on; `receiver` is the object p lies
  // on, whose own transmitted light is skipped. Draws 2 kTranslucentAreaSamples numbers from `random`
  // where the scene has a translucent surface, none where it has not.
  glm::vec3 irradiance(glm::vec3 p, glm::vec3 n_p, uint32_t receiver, Random& random) const {
    if (empty()) return glm::vec3(0.0f);
    const float epsilon = exact_.epsilon();
    glm::vec3 sum(0.0f);
    for (int k = 0; k < kTranslucentAreaSamples; ++k) {
      const AreaSample s = sample(k, random);
      if (s.object == receiver || s.cut_out) continue;
      const glm::vec3 to_q = s.q - p;
      const float r2 = glm::dot(to_q, to_q);
      if (r2 <= epsilon * epsilon) continue;
      const glm::vec3 w = to_q / std::sqrt(r2);
      const float cos_p = glm::dot(n_p, w), cos_q = -glm::dot(s.n, w);  // cos_q > 0: p on the side n faces
      if (cos_p <= 0.0f || cos_q == 0.0f) continue;
      const glm::vec3 arriving = far_side_irradiance(s.q, s.n, cos_q > 0.0f ? 1.0f : -1.0f);
      if (arriving == glm::vec3(0.0f)) continue;
      // Both ends leave their surfaces on the side that faces the other, so neither meets its own.
      const glm::vec3 from = p + n_p * epsilon, to = s.q + s.n * (cos_q > 0.0f ? epsilon : -epsilon);
      const float length = glm::distance(from, to);
      if (length > 0.0f && exact_.rays().intersect(from, (to - from) / length, 0.0f, length)) continue;
      sum += s.passed * arriving * (cos_p * std::abs(cos_q) / r2);
    }
    return sum * (area_ / float(kTranslucentAreaSamples));
  }

 private:
  struct Triangle {
    uint32_t object, triangle;
  };
  struct AreaSample {
    glm::vec3 q, n;  // the point and its smooth normal (the model's: no normal map)
    uint32_t object;
    bool cut_out;      // where a MASK material's coverage is below its cutoff: no surface there
    glm::vec3 passed;  // its far side's radiance per unit irradiance, from the textures' texels there
  };

  // Sample k of the N stratified ones: uniform in area over every translucent triangle (pdf 1 / the
  // total area). Stratum k of the unit interval picks the triangle by the area CDF; where in its
  // triangle's share the number fell is the first of the sqrt-barycentric coordinates, so that the
  // strata spread the points over each triangle too, not only among triangles. In double: a large
  // mesh's triangles each hold a sliver of the interval, and the remainder needs its bits.
  AreaSample sample(int k, Random& random) const {
    const double u = (double(k) + double(random.uniform())) / double(kTranslucentAreaSamples);
    const float r2 = random.uniform();
    const size_t i = std::min(size_t(std::upper_bound(cdf_.begin(), cdf_.end(), u) - cdf_.begin()), cdf_.size() - 1);
    const double low = i > 0 ? cdf_[i - 1] : 0.0;
    const float r1 = float(std::clamp((u - low) / (cdf_[i] - low), 0.0, 1.0));
    const Triangle& t = triangles_[i];
    const scene::Object& object = exact_.scene().objects[t.object];
    const uint32_t* tri = &object.mesh.indices[3 * t.triangle];
    const float root = std::sqrt(r1), b1 = root * (1.0f - r2), b2 = root * r2, b0 = 1.0f - b1 - b2;
    const auto& positions = object.mesh.positions;
    AreaSample s{.q = b0 * positions[tri[0]] + b1 * positions[tri[1]] + b2 * positions[tri[2]],
                 .n = glm::vec3(0.0f),
                 .object = t.object,
                 .cut_out = false,
                 .passed = passed_[t.object]};
    const glm::vec3 face = glm::cross(positions[tri[1]] - positions[tri[0]], positions[tri[2]] - positions[tri[0]]);
    s.n = glm::normalize(face);
    if (!object.mesh.normals.empty()) {
      const glm::vec3 n = b0 * object.mesh.normals[tri[0]] + b1 * object.mesh.normals[tri[1]] + b2 * object.mesh.normals[tri[2]];
      if (glm::length(n) > 0.0f) s.n = glm::normalize(n);
    }
    if (object.material.alpha_mode == scene::AlphaMode::mask) {
      s.cut_out = exact_.base_color(object, t.triangle, b1, b2).a < object.material.alpha_cutoff;
    }
    if (per_texel_[t.object]) {
      // As the G-buffer sees the surface there; which side it is seen from does not change the texels.
      const SurfacePoint at =
          exact_.surface({.distance = 0.0f, .geometry = t.object, .triangle = t.triangle, .geometric_normal = s.n, .u = b1, .v = b2}, -s.n);
      s.passed = diffuse_transmitted_color(at.roughness < 0.0f ? 0.0f : at.metallic, at.layers.diffuse_transmission,
                                           at.layers.diffuse_transmission_color) /
                 glm::pi<float>();
    }
    return s;
  }

  // The lights' direct irradiance at q (normal n) from the side opposite `side` (+1: the side n
  // faces, -1: the other): what leaves on `side`. Each light shadowed by an exact ray from its own
  // side of the surface, as shade_opaque shadows the surface's own light.
  glm::vec3 far_side_irradiance(glm::vec3 q, glm::vec3 n, float side) const {
    const auto& lights = exact_.scene().lights;
    const float epsilon = exact_.epsilon();
    glm::vec3 e(0.0f);
    for (const scene::Light& light : lights) {
      const LightArrival a = light_arrival(light, q, epsilon);
      const float n_l = glm::dot(n, a.l);
      if (n_l * side >= 0.0f || a.cone <= 0.0f) continue;
      if (exact_.rays().intersect(q + (n_l > 0.0f ? n : -n) * epsilon, a.l, 0.0f, a.reach)) continue;
      e += light.color * light.intensity * std::abs(n_l) / a.d2 * a.cone;
    }
    return e;
  }

  const ExactScene& exact_;
  std::vector<glm::vec3> passed_;  // per object: its far side's radiance per unit irradiance, 0 where it passes none
  std::vector<bool> per_texel_;    // per object: whether textures set what it passes (then each sample reads its texels)
  std::vector<Triangle> triangles_;
  std::vector<double> cdf_;  // over triangles_, by area, ending at 1
  float area_ = 0.0f;
};

}  // namespace caustica::reference
