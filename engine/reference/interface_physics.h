#pragma once
// What a refractor's interface reflects once glTF's material layers are on it (docs/gltf.md, "The
// interface"): KHR_materials_specular's scaled Fresnel curve, KHR_materials_iridescence's thin film
// and KHR_materials_clearcoat's coat, per colour channel. The host's own implementation for the
// reference tracers, written from the model's text alone: a second opinion on the device's.
#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>
#include <glm/gtc/constants.hpp>

#include "reference/exact_scene.h"
#include "reference/thin_film.h"
#include "scene/scene.h"

namespace caustica::reference {

// What a refractor's interface reflects, per colour channel (red, green, blue); 1 - reflectance crosses.
struct InterfaceReflectance {
  glm::vec3 reflectance{0.0f};
  float coat = 0.0f;  // the clear coat's share (clearcoat * Fc), part of every channel of `reflectance`
};

// KHR_materials_specular on one channel: the dielectric's curve F (from f0 at normal incidence to 1
// at grazing) rescaled to start at min(f0 * colour, 1) instead, still reaching 1 at grazing.
inline float specular_curve(float fresnel, float f0, float colour) {
  // An interface that reflects everything keeps doing so; an uncoloured one keeps its curve exactly
  // (the rescaling's rounding would make the channels differ, and photons' weights with them).
  if (1.0f - f0 < 1e-6f || colour == 1.0f) return fresnel;
  const float f0_coloured = std::min(f0 * colour, 1.0f);
  return std::clamp(f0_coloured + (1.0f - f0_coloured) * (fresnel - f0) / (1.0f - f0), 0.0f, 1.0f);
}

// KHR_materials_clearcoat's coat Fresnel: Schlick's with F0 = 0.04 (a coat of index 1.5), at the
// angle the ray makes outside with the surface's normal, as the extension gives it.
inline float clearcoat_fresnel(float cos_outside) {
  const float x = 1.0f - std::clamp(cos_outside, 0.0f, 1.0f);
  return 0.04f + 0.96f * x * x * x * x * x;
}

// The interface's reflectance for a ray from index eta_i into eta_t: cos_i is measured against the
// (micro)facet normal on the incident side, cos_outside against the geometric normal on the air
// side (the coat faces the air from either side).
inline InterfaceReflectance interface_reflectance(const scene::Material& m, float cos_i, float cos_outside, float eta_i, float eta_t) {
  cos_i = std::clamp(cos_i, 0.0f, 1.0f);
  InterfaceReflectance out;
  const float sin_i = std::sqrt(std::max(0.0f, 1.0f - cos_i * cos_i));
  if (eta_i * sin_i > eta_t) {  // total internal reflection: no layer lets anything through
    out.reflectance = glm::vec3(1.0f);
    return out;
  }
  const float fresnel = fresnel_dielectric(cos_i, eta_i, eta_t);
  const float f0_root = (eta_t - eta_i) / (eta_t + eta_i);
  const float f0 = f0_root * f0_root;
  for (int c = 0; c < 3; ++c) {
    float f = fresnel;
    if (m.iridescence > 0.0f) {
      const float film = thin_film_reflectance(cos_i, eta_i, m.film_ior, m.film_thickness_nm, eta_t, kChannelWavelengthsNm[c]);
      f = glm::mix(fresnel, film, m.iridescence);
    }
    out.reflectance[c] = m.specular * specular_curve(f, f0, m.specular_color[c]);
  }
  if (m.clearcoat > 0.0f) {
    // The coat reflects its share first; what it passes meets the base below.
    out.coat = m.clearcoat * clearcoat_fresnel(cos_outside);
    out.reflectance = out.coat + (1.0f - out.coat) * out.reflectance;
  }
  return out;
}

// A ray meeting refractor material `m`'s interface, from index eta_i into eta_t, at facet m of the
// surface whose normal n faces the ray, under a clear coat whose normal coat_n (n, or its own normal
// map's: ExactScene::coat_normal) faces it too: the one model of an interface that both references use
// (photons choose a side, camera rays weight both). `fresnel` false: no reflection except total
// internal reflection (docs/oracles.md's "no Fresnel" oracles).
struct InterfaceCrossing {
  glm::vec3 reflected;          // kept on the ray's side of the surface
  glm::vec3 transmitted;        // kept on the far side; zero under total internal reflection
  glm::vec3 reflectance{0.0f};  // per channel; 1 under total internal reflection
  float coat = 0.0f;            // the clear coat's share of it, reflected before the base
  glm::vec3 coat_normal{0.0f};  // the coat's normal (its own normal map's), on the ray's side
  // What the base reflects of the light past the coat.
  glm::vec3 base() const { return coat < 1.0f ? (reflectance - coat) / (1.0f - coat) : glm::vec3(0.0f); }
  bool total_internal() const { return transmitted == glm::vec3(0.0f); }
};
inline InterfaceCrossing cross_interface(const scene::Material& material, glm::vec3 direction, glm::vec3 m, glm::vec3 n, glm::vec3 coat_n,
                                         float eta_i, float eta_t, bool fresnel = true) {
  InterfaceCrossing c;
  c.coat_normal = coat_n;
  c.reflected = on_side(glm::reflect(direction, m), n, true);
  const glm::vec3 refracted = glm::refract(direction, m, eta_i / eta_t);
  if (glm::dot(refracted, refracted) == 0.0f) {
    c.transmitted = glm::vec3(0.0f);
    c.reflectance = glm::vec3(1.0f);
    return c;
  }
  c.transmitted = on_side(glm::normalize(refracted), n, false);
  if (!fresnel) return c;
  // The coat is on the air's side: the light's cosine there, before an entry or after an exit.
  const float cos_outside = eta_i < eta_t ? -glm::dot(direction, coat_n) : -glm::dot(c.transmitted, coat_n);
  const InterfaceReflectance r = interface_reflectance(material, -glm::dot(direction, m), cos_outside, eta_i, eta_t);
  c.reflectance = r.reflectance;
  c.coat = r.coat;
  return c;
}

// Photons choose one side of an interface at random: the probability that a photon of colour band
// `band` (-1: white) takes `share`, and the weight that keeps its expected power.
inline float choice_probability(glm::vec3 share, int band) {
  if (band >= 0 || (share.x == share.y && share.y == share.z)) return share[std::max(band, 0)];
  return (share.x + share.y + share.z) / 3.0f;
}
// (Exactly 1 where the share is the same in every channel: an uncoloured interface leaves powers as they are.)
inline glm::vec3 choice_weight(glm::vec3 share, float probability) {
  return share == glm::vec3(probability) ? glm::vec3(1.0f) : share / std::max(probability, 1e-12f);
}

}  // namespace caustica::reference
