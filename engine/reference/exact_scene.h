#pragma once
// What both reference tracers share: the scene's meshes in Embree, interpolated normals, exact
// Fresnel, and the engine's spot-light cone.
#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>

#include "reference/ray_scene.h"
#include "scene/scene.h"

namespace caustica::reference {

// Unpolarised Fresnel reflectance from medium eta_i into eta_t; 1 under total internal reflection.
inline float fresnel_dielectric(float cos_i, float eta_i, float eta_t) {
  if (eta_i == eta_t) return 0.0f;  // no interface at all, even at grazing incidence
  cos_i = std::clamp(cos_i, 0.0f, 1.0f);
  const float sin_t = eta_i / eta_t * std::sqrt(std::max(0.0f, 1.0f - cos_i * cos_i));
  if (sin_t >= 1.0f) return 1.0f;
  const float cos_t = std::sqrt(std::max(0.0f, 1.0f - sin_t * sin_t));
  const float rs = (eta_i * cos_i - eta_t * cos_t) / (eta_i * cos_i + eta_t * cos_t);
  const float rp = (eta_t * cos_i - eta_i * cos_t) / (eta_t * cos_i + eta_i * cos_t);
  return 0.5f * (rs * rs + rp * rp);
}

// The spot's cone along `direction` (unit, from the light), with the soft edge of
// scene/lighting.frag; 1 for point lights.
inline float spot_cone(const scene::Light& light, glm::vec3 direction) {
  if (light.type != scene::LightType::spot) return 1.0f;
  const float cos_cut = std::cos(glm::radians(light.view.fov_y_degrees) * 0.5f);
  const float c = glm::dot(direction, glm::normalize(light.view.target - light.view.position));
  const float edge = cos_cut + (1.0f - cos_cut) * 0.02f;
  const float x = std::clamp((c - cos_cut) / (edge - cos_cut), 0.0f, 1.0f);
  return x * x * (3 - 2 * x);
}

class ExactScene {
 public:
  explicit ExactScene(const scene::Scene& scene) : scene_(scene) {
    for (const auto& o : scene.objects) {
      RayScene::CutOut cut_out;
      if (o.material.alpha_mode == scene::AlphaMode::mask) {
        cut_out = [this, &o](uint32_t triangle, float u, float v) { return base_color(o, triangle, u, v).a < o.material.alpha_cutoff; };
      }
      rays_.add_mesh(o.mesh.positions, o.mesh.indices, std::move(cut_out));
    }
    rays_.commit();
    epsilon_ = scene.ray_epsilon();
  }

  const scene::Scene& scene() const { return scene_; }
  const RayScene& rays() const { return rays_; }
  // Ray offsets that keep a ray from hitting the surface it leaves, scaled to the scene.
  float epsilon() const { return epsilon_; }

  // The material's base colour and alpha where a ray meets triangle `triangle` at barycentric
  // (u, v), its texture sampled as the engine's sampler reads the full-resolution level.
  glm::vec4 base_color(const scene::Object& object, uint32_t triangle, float u, float v) const {
    const scene::Material& m = object.material;
    glm::vec4 color(m.albedo, m.alpha);
    if (!m.base_color_texture.used()) return color;
    glm::vec4 uv(0.0f);
    if (!object.mesh.texcoords.empty()) {
      const uint32_t* tri = &object.mesh.indices[3 * triangle];
      uv = (1 - u - v) * object.mesh.texcoords[tri[0]] + u * object.mesh.texcoords[tri[1]] + v * object.mesh.texcoords[tri[2]];
    }
    const scene::TextureRef& ref = m.base_color_texture;
    const glm::vec3 at = ref.transform * glm::vec3(ref.texcoord == 1 ? glm::vec2(uv.z, uv.w) : glm::vec2(uv.x, uv.y), 1.0f);
    return color * scene_.textures[static_cast<size_t>(ref.texture)].sample(glm::vec2(at));
  }
  glm::vec4 base_color(const RayHit& hit) const { return base_color(scene_.objects[hit.geometry], hit.triangle, hit.u, hit.v); }

  glm::vec3 smooth_normal(const RayHit& hit) const {
    const auto& mesh = scene_.objects[hit.geometry].mesh;
    const uint32_t* tri = &mesh.indices[3 * hit.triangle];
    const glm::vec3 n = (1 - hit.u - hit.v) * mesh.normals[tri[0]] + hit.u * mesh.normals[tri[1]] + hit.v * mesh.normals[tri[2]];
    const float len = glm::length(n);
    return len > 0 ? n / len : hit.geometric_normal;
  }

 private:
  const scene::Scene& scene_;
  RayScene rays_;
  float epsilon_ = 1e-4f;
};

}  // namespace caustica::reference
