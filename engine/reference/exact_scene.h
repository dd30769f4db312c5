#pragma once
// What both reference tracers share: the scene's meshes in Embree, interpolated normals, exact
// Fresnel, and the engine's spot-light cone.
#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>
#include <glm/gtc/constants.hpp>
#include <optional>
#include <utility>

#include "reference/ray_scene.h"
#include "reference/surface_physics.h"
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

// A splitmix64 stream per (seed, stream): deterministic wherever a tracer's work is split.
class Random {
 public:
  Random(uint64_t seed, uint64_t stream) : state_(seed * 0xD1B54A32D192ED03ull ^ stream) { next(); }
  // Counter-based: item `index` of a seed takes numbers index * 2^16 onwards of the seed's one
  // splitmix64 sequence (splitmix's state is a counter, so it jumps there at once). Its numbers
  // depend on (seed, index) alone, however the items are split among threads or processes, and no
  // two items share one while each draws fewer than 2^16 (a photon draws at most a few hundred).
  static Random keyed(uint64_t seed, uint64_t index) {
    Random random(0, 0);
    random.state_ = finalize(seed) + (index << 16) * kGolden;
    return random;
  }
  float uniform() { return static_cast<float>(next() >> 40) * (1.0f / 16777216.0f); }  // [0, 1)

 private:
  static constexpr uint64_t kGolden = 0x9E3779B97F4A7C15ull;
  static uint64_t finalize(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  uint64_t next() { return finalize(state_ += kGolden); }
  uint64_t state_;
};

// Rough transmission as the engine draws it (refraction/refraction.glsl, microfacet_normal): a
// microfacet normal around n (facing the ray) from GGX's D(m) (m.n) with alpha = roughness^2, one
// that faces `direction`; no shadowing-masking weight. A smooth surface draws no numbers.
inline glm::vec3 microfacet_normal(glm::vec3 n, glm::vec3 direction, float roughness, Random& random) {
  if (roughness <= 0.0f) return n;
  const float a2 = roughness * roughness * roughness * roughness;
  const float s = n.z >= 0.0f ? 1.0f : -1.0f, k = -1.0f / (s + n.z);
  const glm::vec3 t(1.0f + s * n.x * n.x * k, s * n.x * n.y * k, -s * n.x), b(n.x * n.y * k, s + n.y * n.y * k, -n.y);
  for (int attempt = 0; attempt < 4; ++attempt) {
    const float u1 = random.uniform(), u2 = random.uniform();
    const float cos2 = (1.0f - u1) / (1.0f + (a2 - 1.0f) * u1);
    const float sin_theta = std::sqrt(std::max(0.0f, 1.0f - cos2)), phi = glm::two_pi<float>() * u2;
    const glm::vec3 m = t * (sin_theta * std::cos(phi)) + b * (sin_theta * std::sin(phi)) + n * std::sqrt(cos2);
    if (glm::dot(m, direction) < 0.0f) return m;
  }
  return n;
}
// A scattered direction kept on its side of the surface (n faces the incoming ray): reflected
// light above it, transmitted light below; one on the wrong side is mirrored across the surface.
inline glm::vec3 on_side(glm::vec3 direction, glm::vec3 n, bool above) {
  return (glm::dot(direction, n) > 0.0f) == above ? direction : direction - 2.0f * glm::dot(direction, n) * n;
}
// Through a thin wall about facet m: its mirror direction mirrored through the wall.
inline glm::vec3 through_thin(glm::vec3 direction, glm::vec3 m, glm::vec3 n) {
  return on_side(glm::reflect(direction, m), n, false);
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

// What the engine's G-buffer holds of an opaque surface point, and its lighting model
// (scene/lighting.frag with scene/surface.glsl): Lambertian reflection for scene-file materials,
// glTF's metallic-roughness BRDF with its sheen, anisotropy and diffuse transmission
// (reference/surface_physics.h) for glTF materials.
struct SurfacePoint {
  glm::vec3 normal{0.0f, 1.0f, 0.0f};  // shading normal, facing the viewer
  glm::vec3 base{1.0f};
  float metallic = 0.0f;
  float roughness = -1.0f;  // below 0: Lambertian
  SurfaceLayers layers;
  glm::vec3 emitted{0.0f};
  float occlusion = 1.0f;  // of the ambient sky light (glTF's occlusionTexture with its strength)

  // The diffuse light that stays on the lit side (what a caustic lights).
  glm::vec3 diffuse_reflected() const {
    return diffuse_reflected_color(base, roughness < 0.0f ? 0.0f : metallic, layers.diffuse_transmission);
  }
  // Reflected radiance per unit irradiance from direction l (unit, towards the light) seen from v;
  // from behind the surface, what its diffuse transmission passes.
  glm::vec3 brdf(glm::vec3 v, glm::vec3 l) const { return layered_brdf(normal, base, metallic, roughness, layers, v, l); }
  // Reflected sky light per unit of the scene's ambient sky radiance.
  glm::vec3 ambient_reflectance(glm::vec3 v) const {
    return layered_ambient(std::max(glm::dot(normal, v), 1e-4f), base, metallic, roughness, layers,
                           std::max(glm::dot(layers.clearcoat_normal, v), 1e-4f));
  }
};

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
    return glm::vec4(m.albedo, m.alpha) * scene::texel_at(scene_, object, m.base_color_texture, triangle, u, v);
  }
  glm::vec4 base_color(const RayHit& hit) const { return base_color(scene_.objects[hit.geometry], hit.triangle, hit.u, hit.v); }

  // The G-buffer's view of an opaque surface where a ray along `direction` meets it: textures
  // sampled, the normal map applied in the tangent frame, the anisotropy's direction in it.
  SurfacePoint surface(const RayHit& hit, glm::vec3 direction) const {
    const scene::Object& object = scene_.objects[hit.geometry];
    const scene::Material& m = object.material;
    SurfacePoint s;
    s.base = glm::vec3(base_color(hit));
    const glm::vec3 geometric = smooth_normal(hit);
    // In the front face's frame; seen from behind, all of it flips.
    s.normal = mapped_normal(hit, geometric, m.normal_texture, m.normal_scale);
    // The extensions' values, per texel where textures set them (as the G-buffer's layers target
    // holds them for the lighting pass), the anisotropy's strength and direction and the coat's normal.
    const bool per_texel = scene::has_surface_textures(m);
    scene::Material textured;
    if (per_texel) {
      textured = m;
      layers_at(object, hit, textured);
      surface_extensions_at(object, hit, textured);
    }
    const scene::Material& e = per_texel ? textured : m;
    s.layers = {.sheen_color = e.sheen_color,
                .sheen_roughness = e.sheen_roughness,
                .diffuse_transmission = e.diffuse_transmission,
                .diffuse_transmission_color = e.diffuse_transmission_color,
                .specular = e.specular,
                .specular_color = e.specular_color,
                .ior = m.ior,
                .clearcoat = e.clearcoat,
                .clearcoat_roughness = e.clearcoat_roughness,
                .clearcoat_normal = coat_normal(hit, geometric),
                .iridescence = e.iridescence,
                .film_ior = m.film_ior,
                .film_thickness_nm = e.film_thickness_nm};
    if (m.anisotropy > 0.0f) s.layers.anisotropy_direction = anisotropy(hit, s.normal, s.layers.anisotropy);
    if (glm::dot(geometric, direction) > 0.0f) {  // seen from behind, the normals flip
      s.normal = -s.normal;
      s.layers.clearcoat_normal = -s.layers.clearcoat_normal;
    }
    if (m.metallic_roughness) {
      const glm::vec4 mr = sample(object, m.metallic_roughness_texture, hit);
      s.metallic = m.metallic * mr.b;
      s.roughness = m.roughness * mr.g;
    }
    s.emitted = m.emissive;
    if (m.emissive_texture.used()) s.emitted *= glm::vec3(sample(object, m.emissive_texture, hit));
    if (m.occlusion_texture.used()) s.occlusion = 1.0f + m.occlusion_strength * (sample(object, m.occlusion_texture, hit).r - 1.0f);
    return s;
  }

  // A refractor's transmission roughness where a ray meets it: per texel where its material has a
  // metallic-roughness texture (roughnessFactor times the green channel, as the engine's exact paths
  // read it; its image-space methods take the object's mean); else the material's.
  float transmission_roughness(const RayHit& hit) const {
    const scene::Object& object = scene_.objects[hit.geometry];
    const scene::Material& m = object.material;
    if (m.transmission_roughness <= 0.0f || !m.metallic_roughness_texture.used()) return m.transmission_roughness;
    return m.roughness * sample(object, m.metallic_roughness_texture, hit).g;
  }

  // A refractor's tint and transmission where a ray meets it: per texel where its material has a
  // base colour or a transmission texture (the factor times the texture, and a BLEND surface's
  // uncovered share, as the engine's shaders read them: tint_transmission_from).
  struct Transmittance {
    glm::vec3 tint;
    float transmission;
  };
  Transmittance transmittance(const RayHit& hit) const {
    const scene::Object& object = scene_.objects[hit.geometry];
    const scene::Material& m = object.material;
    Transmittance result{m.tint, m.transmission};
    if (m.base_color_texture.used()) {
      const glm::vec4 base_color = sample(object, m.base_color_texture, hit);
      result.tint = m.tint_factor * glm::vec3(base_color);
      if (m.coverage_transmits) result.transmission = 1.0f - m.alpha * base_color.a;
    }
    if (m.transmission_texture.used()) result.transmission = m.transmission_factor * sample(object, m.transmission_texture, hit).r;
    return result;
  }

  // A refractor's material with its interface layers where a ray meets it: per texel where it has a
  // layer texture (as the engine's exact paths read them: trace.glsl's layers_at), written into
  // `storage`; else the object's own material.
  const scene::Material& interface_material(const RayHit& hit, scene::Material& storage) const {
    const scene::Object& object = scene_.objects[hit.geometry];
    if (!object.material.refractor || !object.material.layer_textures.used()) return object.material;
    storage = object.material;
    layers_at(object, hit, storage);
    return storage;
  }

  // KHR_materials_clearcoat's normal where a ray meets a surface whose coat has its own normal map
  // (clearcoatNormalTexture): the smooth normal bent by it, turned to the side of `facing`; without
  // one, `facing` (as trace.glsl's coat_normal_at).
  glm::vec3 coat_normal(const RayHit& hit, glm::vec3 facing) const {
    const scene::SurfaceTextures& t = scene_.objects[hit.geometry].material.surface_textures;
    if (!t.clearcoat_normal.used()) return facing;
    const glm::vec3 n = smooth_normal(hit);
    const glm::vec3 coat = mapped_normal(hit, n, t.clearcoat_normal, t.clearcoat_normal_scale);
    return glm::dot(n, facing) < 0.0f ? -coat : coat;
  }

  glm::vec3 smooth_normal(const RayHit& hit) const {
    const auto& mesh = scene_.objects[hit.geometry].mesh;
    const uint32_t* tri = &mesh.indices[3 * hit.triangle];
    const glm::vec3 n = (1 - hit.u - hit.v) * mesh.normals[tri[0]] + hit.u * mesh.normals[tri[1]] + hit.v * mesh.normals[tri[2]];
    const float len = glm::length(n);
    return len > 0 ? n / len : hit.geometric_normal;
  }

 private:
  // The interface layers' values (KHR_materials_specular, _clearcoat, _iridescence) where a ray
  // meets the object: each factor times its texture, into `m`.
  void layers_at(const scene::Object& object, const RayHit& hit, scene::Material& m) const {
    const scene::LayerTextures& t = object.material.layer_textures;
    m.specular = t.specular_factor * sample(object, t.specular, hit).a;
    m.specular_color = t.specular_color_factor * glm::vec3(sample(object, t.specular_color, hit));
    m.clearcoat = t.clearcoat_factor * sample(object, t.clearcoat, hit).r;
    m.clearcoat_roughness = t.clearcoat_roughness_factor * sample(object, t.clearcoat_roughness, hit).g;
    m.iridescence = t.iridescence_factor * sample(object, t.iridescence, hit).r;
    m.film_thickness_nm =
        t.thickness.used() ? glm::mix(t.thickness_min, t.thickness_max, sample(object, t.thickness, hit).g) : t.thickness_max;
  }
  // The sheen's and the diffuse transmission's values where a ray meets the object, likewise.
  void surface_extensions_at(const scene::Object& object, const RayHit& hit, scene::Material& m) const {
    const scene::SurfaceTextures& t = object.material.surface_textures;
    m.sheen_color = t.sheen_color_factor * glm::vec3(sample(object, t.sheen_color, hit));
    m.sheen_roughness = t.sheen_roughness_factor * sample(object, t.sheen_roughness, hit).a;
    m.diffuse_transmission = t.diffuse_transmission_factor * sample(object, t.diffuse_transmission, hit).a;
    m.diffuse_transmission_color = t.diffuse_transmission_color_factor * glm::vec3(sample(object, t.diffuse_transmission_color, hit));
  }
  // The geometry's normal n bent by tangent-space normal map `map` with its scale, where there is
  // one and a tangent frame for it: the base's normalTexture, or the clear coat's own
  // clearcoatNormalTexture (the base's map does not reach the coat).
  glm::vec3 mapped_normal(const RayHit& hit, glm::vec3 n, const scene::TextureRef& map, float scale) const {
    if (!map.used()) return n;
    const auto frame = tangent_frame(hit, n, map);
    if (!frame) return n;
    const glm::vec3 sampled = glm::vec3(sample(scene_.objects[hit.geometry], map, hit)) * 2.0f - 1.0f;
    const glm::vec3 mapped = glm::normalize(glm::vec3(sampled.x * scale, sampled.y * scale, sampled.z));
    return glm::normalize(frame->first * mapped.x + frame->second * mapped.y + n * mapped.z);
  }

  static glm::vec2 texcoord(const scene::Object& object, const scene::TextureRef& ref, uint32_t vertex) {
    return scene::texture_coordinates(ref, object.mesh.texcoords.empty() ? glm::vec4(0.0f) : object.mesh.texcoords[vertex]);
  }
  // The tangent frame (tangent, bitangent) at a hit with normal n: the mesh's TANGENT
  // interpolated, or without one the frame the engine derives from texture `ref`'s coordinates'
  // screen derivatives (tangent along increasing u, bitangent = normal x tangent); none where
  // neither gives one.
  std::optional<std::pair<glm::vec3, glm::vec3>> tangent_frame(const RayHit& hit, glm::vec3 n, const scene::TextureRef& ref) const {
    const scene::Object& object = scene_.objects[hit.geometry];
    const uint32_t* tri = &object.mesh.indices[3 * hit.triangle];
    glm::vec3 t(0.0f);
    float sign = 1.0f;
    if (!object.mesh.tangents.empty()) {
      const glm::vec4 tangent =
          (1 - hit.u - hit.v) * object.mesh.tangents[tri[0]] + hit.u * object.mesh.tangents[tri[1]] + hit.v * object.mesh.tangents[tri[2]];
      t = glm::vec3(tangent) - n * glm::dot(n, glm::vec3(tangent));
      sign = tangent.w < 0.0f ? -1.0f : 1.0f;
    }
    if (glm::dot(t, t) <= 1e-20f) {
      const glm::vec2 uv0 = texcoord(object, ref, tri[0]), uv1 = texcoord(object, ref, tri[1]), uv2 = texcoord(object, ref, tri[2]);
      const glm::vec3 e1 = object.mesh.positions[tri[1]] - object.mesh.positions[tri[0]];
      const glm::vec3 e2 = object.mesh.positions[tri[2]] - object.mesh.positions[tri[0]];
      const glm::vec2 d1 = uv1 - uv0, d2 = uv2 - uv0;
      const float det = d1.x * d2.y - d2.x * d1.y;
      t = det != 0.0f ? (e1 * d2.y - e2 * d1.y) / det : glm::vec3(0.0f);
      t -= n * glm::dot(n, t);
      sign = 1.0f;
    }
    if (glm::dot(t, t) <= 1e-20f) return std::nullopt;
    t = glm::normalize(t);
    return std::make_pair(t, sign * glm::cross(n, t));
  }

  // KHR_materials_anisotropy's direction at a hit (unit, in the surface of normal n) and its
  // strength: the texture's rg ((1, 0) without one) turned by the rotation, its blue times the
  // strength; strength 0 where the surface has no tangent frame.
  glm::vec3 anisotropy(const RayHit& hit, glm::vec3 n, float& strength) const {
    const scene::Object& object = scene_.objects[hit.geometry];
    const scene::Material& m = object.material;
    const glm::vec4 texel = m.anisotropy_texture.used() ? sample(object, m.anisotropy_texture, hit) : glm::vec4(1.0f, 0.5f, 1.0f, 1.0f);
    const glm::vec2 d = anisotropy_direction(glm::vec2(texel), m.anisotropy_rotation);
    const auto frame = tangent_frame(hit, n, m.anisotropy_texture.used() ? m.anisotropy_texture : m.normal_texture);
    strength = frame ? m.anisotropy * texel.b : 0.0f;
    return frame ? glm::normalize(frame->first * d.x + frame->second * d.y) : glm::vec3(1.0f, 0.0f, 0.0f);
  }

  // Texture `ref` where the ray met the object; 1 where `ref` is unused.
  glm::vec4 sample(const scene::Object& object, const scene::TextureRef& ref, const RayHit& hit) const {
    return scene::texel_at(scene_, object, ref, hit.triangle, hit.u, hit.v);
  }

  const scene::Scene& scene_;
  RayScene rays_;
  float epsilon_ = 1e-4f;
};

}  // namespace caustica::reference
