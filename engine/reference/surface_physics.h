#pragma once
// What an opaque surface reflects once glTF's surface extensions are on it: KHR_materials_sheen's
// "Charlie" sheen (Estevez & Kulla 2017, with Ashikhmin's visibility, which the extension allows),
// KHR_materials_anisotropy's anisotropic GGX, KHR_materials_diffuse_transmission's thin-surface
// transmission, KHR_materials_specular's (and KHR_materials_ior's) Fresnel, KHR_materials_iridescence's
// film and KHR_materials_clearcoat's coat, over the engine's metallic-roughness BRDF. The host's own implementation for the
// reference renderer, written from the model's text alone: a second opinion on the device's.
//
// Conventions: n is the unit shading normal, facing the viewer; v points to the viewer, l to the
// light, all unit and in world space.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <glm/glm.hpp>
#include <glm/gtc/constants.hpp>

#include "reference/thin_film.h"
#include "scene/sheen_albedo.h"

namespace caustica::reference {

inline float max_component(glm::vec3 c) {
  return std::max({c.x, c.y, c.z});
}

// ---- KHR_materials_sheen ----

// The lobe's distribution, visibility and directional albedo E (and the device's table of E) are
// scene/sheen_albedo.h's: the scene uploads E's table with each sheen material.
using scene::sheen_albedo;
using scene::sheen_albedo_from_table;
using scene::sheen_albedo_table;
using scene::sheen_alpha;
using scene::sheen_distribution;
using scene::sheen_visibility;

// What the sheen leaves to the layers beneath it, the lesser of what it lets through toward the
// viewer and toward the light, 1 - max(sheen colour) E. E approximates the sheen's energy by its
// brightest channel, as the extension does, so that no channel gains energy.
inline float sheen_scaling(glm::vec3 sheen_color, float e_view, float e_light) {
  const float c = max_component(sheen_color);
  return std::clamp(std::min(1.0f - c * e_view, 1.0f - c * e_light), 0.0f, 1.0f);
}

// ---- KHR_materials_anisotropy ----

// (alpha_t, alpha_b): the strength stretches the lobe along the tangent toward alpha 1, as the
// extension gives it; alpha is kept at 1e-3 or more, where the GGX lobe is still finite.
inline glm::vec2 anisotropic_alphas(float roughness, float strength) {
  const float alpha = std::max(roughness * roughness, 1e-3f);
  return {glm::mix(alpha, 1.0f, strength * strength), alpha};
}

// The anisotropic GGX distribution, from h's components along the tangent t, bitangent b and normal n.
inline float anisotropic_distribution(float alpha_t, float alpha_b, float t_h, float b_h, float n_h) {
  const float f = t_h * t_h / (alpha_t * alpha_t) + b_h * b_h / (alpha_b * alpha_b) + n_h * n_h;
  return 1.0f / (glm::pi<float>() * alpha_t * alpha_b * f * f);
}

// The height-correlated Smith visibility of the anisotropic lobe; v_tbn and l_tbn are the
// directions' (t., b., n.) components. n.v is kept at 1e-4 or more because a view at grazing would
// otherwise zero the denominator with a light at grazing; a light below the horizon counts as at it.
inline float anisotropic_visibility(float alpha_t, float alpha_b, glm::vec3 v_tbn, glm::vec3 l_tbn) {
  const float n_v = std::max(v_tbn.z, 1e-4f);
  const float n_l = std::clamp(l_tbn.z, 0.0f, 1.0f);
  const glm::vec2 a2(alpha_t * alpha_t, alpha_b * alpha_b);
  const float lambda_v = std::sqrt(a2.x * v_tbn.x * v_tbn.x + a2.y * v_tbn.y * v_tbn.y + n_v * n_v);
  const float lambda_l = std::sqrt(a2.x * l_tbn.x * l_tbn.x + a2.y * l_tbn.y * l_tbn.y + n_l * n_l);
  return 0.5f / std::max(n_l * lambda_v + n_v * lambda_l, 1e-8f);
}

// The tangent-space anisotropy direction: the texture's red-green mapped to [-1, 1], turned
// counter-clockwise by `rotation` radians. A texel at the centre (rg = 0.5) names no direction:
// it then stands for the untextured one, (1, 0), turned by the rotation.
inline glm::vec2 anisotropy_direction(glm::vec2 texture_rg, float rotation) {
  glm::vec2 d = texture_rg * 2.0f - 1.0f;
  if (glm::dot(d, d) < 1e-12f) d = glm::vec2(1.0f, 0.0f);
  const float c = std::cos(rotation), s = std::sin(rotation);
  return glm::normalize(glm::vec2(c * d.x - s * d.y, s * d.x + c * d.y));
}

// ---- KHR_materials_diffuse_transmission ----
// Each colour below is a BRDF or BTDF times pi: the caller divides by pi.

// What the diffuse lobe reflects once the share d is transmitted instead.
inline glm::vec3 diffuse_reflected_color(glm::vec3 base, float metallic, float transmission) {
  return base * (1.0f - metallic) * (1.0f - transmission);
}

// What the diffuse lobe passes to the other side; a metal has no diffuse lobe to transmit. The
// extension weights this side too with a Fresnel mix, which needs a reflection's half-vector that
// v and a light behind the surface do not define: it is not modelled, so the back passes up to F
// more than the extension's.
inline glm::vec3 diffuse_transmitted_color(float metallic, float transmission, glm::vec3 transmission_color) {
  return (1.0f - metallic) * transmission * transmission_color;
}

// Under a uniform sky of radiance 1 the back hemisphere's cosine-weighted integral of the BTDF
// (the colour above over pi) is pi times it over pi: the colour itself.
inline glm::vec3 ambient_transmitted(float metallic, float transmission, glm::vec3 transmission_color) {
  return diffuse_transmitted_color(metallic, transmission, transmission_color);
}

// ---- The combined surface ----

struct SurfaceLayers {
  glm::vec3 sheen_color{0.0f};
  float sheen_roughness = 0.0f;
  float anisotropy = 0.0f;                           // strength in [0, 1]
  glm::vec3 anisotropy_direction{1.0f, 0.0f, 0.0f};  // world space; made perpendicular to n here
  float diffuse_transmission = 0.0f;
  glm::vec3 diffuse_transmission_color{1.0f};
  float specular = 1.0f;  // KHR_materials_specular's weight and F0 colour
  glm::vec3 specular_color{1.0f};
  float ior = 1.5f;
  float clearcoat = 0.0f;  // KHR_materials_clearcoat's weight and roughness
  float clearcoat_roughness = 0.0f;
  glm::vec3 clearcoat_normal{0.0f};  // the coat's own normal (unit, facing the viewer); 0: the surface's
  float iridescence = 0.0f;          // KHR_materials_iridescence's weight, the film's index and thickness
  float film_ior = 1.3f;
  float film_thickness_nm = 0.0f;
};

// ---- KHR_materials_specular and KHR_materials_clearcoat ----

// The Fresnel curve's ends over the metallic-roughness base. A dielectric reflects ((n - 1) /
// (n + 1))^2 at normal incidence (0.04 at n = 1.5); the specular colour tints that, each channel
// capped at 1, and the specular weight scales both it and the grazing end (1 without the
// extension). Metal keeps its base colour at normal incidence and 1 at grazing; metallic mixes.
struct FresnelEnds {
  glm::vec3 normal;
  float grazing;
};
inline FresnelEnds fresnel_ends(glm::vec3 base, float metallic, const SurfaceLayers& layers) {
  const float root = (layers.ior - 1.0f) / (layers.ior + 1.0f);
  const glm::vec3 dielectric = glm::min(root * root * layers.specular_color, glm::vec3(1.0f)) * layers.specular;
  return {dielectric + (base - dielectric) * metallic, layers.specular + (1.0f - layers.specular) * metallic};
}

// KHR_materials_iridescence over the base: what a film of the layers' index and thickness reflects
// at cosine cos_i, per channel at its wavelength (thin_film.h's Airy sum), on a substrate
// whose index each channel's normal-incidence reflectance names: R = ((n - 1) / (n + 1))^2, so n =
// (1 + sqrt(R)) / (1 - sqrt(R)), with R the curve's F0 over its grazing end (the dielectric's own
// index; for metal the index of a dielectric that reflects as much head-on). The film's reflectance
// is then scaled by the grazing end, as the curve it mixes with is.
inline glm::vec3 film_over_base(const FresnelEnds& ends, const SurfaceLayers& layers, float cos_i) {
  glm::vec3 out;
  for (int c = 0; c < 3; ++c) {
    const float head_on = std::clamp(ends.normal[c] / std::max(ends.grazing, 1e-6f), 0.0f, 0.9999f);
    const float substrate = (1.0f + std::sqrt(head_on)) / (1.0f - std::sqrt(head_on));
    out[c] = ends.grazing * thin_film_reflectance(std::clamp(cos_i, 0.0f, 1.0f), 1.0f, layers.film_ior, layers.film_thickness_nm, substrate,
                                                  kChannelWavelengthsNm[c]);
  }
  return out;
}

// The share of the light that the coat takes at the viewer, the extension's blend factor: its
// weight times Schlick's reflectance of index 1.5 (0.04 at normal incidence) at cos_v.
inline float coat_blend(const SurfaceLayers& layers, float cos_v) {
  const float x = 1.0f - std::clamp(cos_v, 0.0f, 1.0f);
  return layers.clearcoat * (0.04f + 0.96f * x * x * x * x * x);
}

// A unit tangent perpendicular to n from the layers' direction: the lobe at strength 0 is the
// isotropic one only in an orthonormal frame, and the default direction (1, 0, 0) need not be
// perpendicular to n. Along n itself it names no tangent; any perpendicular then serves.
inline glm::vec3 surface_tangent(glm::vec3 n, glm::vec3 direction) {
  glm::vec3 t = direction - n * glm::dot(n, direction);
  if (glm::dot(t, t) < 1e-12f) t = glm::cross(n, std::abs(n.x) < 0.9f ? glm::vec3(1.0f, 0.0f, 0.0f) : glm::vec3(0.0f, 1.0f, 0.0f));
  return glm::normalize(t);
}

// The metallic-roughness base under the sheen, for a light on the normal's side: Schlick's Fresnel
// splits the light between the diffuse lobe, less its transmitted share, and the anisotropic GGX.
inline glm::vec3 base_layer_brdf(glm::vec3 n, glm::vec3 base, float metallic, float roughness, const SurfaceLayers& layers, glm::vec3 v,
                                 glm::vec3 l) {
  const glm::vec3 h = glm::normalize(v + l);
  const float x = 1.0f - std::clamp(glm::dot(v, h), 0.0f, 1.0f);
  const FresnelEnds ends = fresnel_ends(base, metallic, layers);
  glm::vec3 fresnel = ends.normal + (ends.grazing - ends.normal) * (x * x * x * x * x);
  if (layers.iridescence > 0.0f) fresnel = glm::mix(fresnel, film_over_base(ends, layers, glm::dot(v, h)), layers.iridescence);
  const glm::vec3 t = surface_tangent(n, layers.anisotropy_direction), b = glm::cross(n, t);
  const glm::vec2 alphas = anisotropic_alphas(roughness, layers.anisotropy);
  const float d = anisotropic_distribution(alphas.x, alphas.y, glm::dot(t, h), glm::dot(b, h), glm::dot(n, h));
  const glm::vec3 v_tbn(glm::dot(t, v), glm::dot(b, v), glm::dot(n, v));
  const glm::vec3 l_tbn(glm::dot(t, l), glm::dot(b, l), glm::dot(n, l));
  const float vis = anisotropic_visibility(alphas.x, alphas.y, v_tbn, l_tbn);
  const glm::vec3 diffuse = diffuse_reflected_color(base, metallic, layers.diffuse_transmission);
  return (1.0f - fresnel) * diffuse / glm::pi<float>() + fresnel * (d * vis);
}

// The BRDF (BTDF for a light behind the surface) the caller weights with |n.l| and the light's
// irradiance. Roughness below 0 is the engine's Lambertian surface: the diffuse lobe alone, with
// its transmitted share, and no metal, specular, sheen or coat (they need a microfacet roughness).
// The sheen's albedo is the quadrature's, not the device's table: this is the reference. The coat
// lies over everything, the light through the surface included: its blend factor's share of what
// leaves toward the viewer is the coat's own GGX lobe (about its own normal) instead; a light
// behind the surface (n.l <= 0, base normal n) or behind the coat meets no lobe.
inline glm::vec3 coat_over(glm::vec3 under, glm::vec3 surface_n, const SurfaceLayers& layers, glm::vec3 v, glm::vec3 l) {
  if (layers.clearcoat <= 0.0f) return under;
  const glm::vec3 n = layers.clearcoat_normal == glm::vec3(0.0f) ? surface_n : layers.clearcoat_normal;
  const float blend = coat_blend(layers, glm::dot(n, v));
  if (glm::dot(surface_n, l) <= 0.0f || glm::dot(n, l) <= 0.0f) return under * (1.0f - blend);
  const float alpha = std::max(layers.clearcoat_roughness * layers.clearcoat_roughness, 1e-3f);
  const glm::vec3 t = surface_tangent(n, glm::vec3(1.0f, 0.0f, 0.0f)), b = glm::cross(n, t), h = glm::normalize(v + l);
  const float lobe = anisotropic_distribution(alpha, alpha, glm::dot(t, h), glm::dot(b, h), glm::dot(n, h)) *
                     anisotropic_visibility(alpha, alpha, glm::vec3(glm::dot(t, v), glm::dot(b, v), glm::dot(n, v)),
                                            glm::vec3(glm::dot(t, l), glm::dot(b, l), glm::dot(n, l)));
  return under * (1.0f - blend) + glm::vec3(blend * lobe);
}

inline glm::vec3 layered_brdf(glm::vec3 n, glm::vec3 base, float metallic, float roughness, const SurfaceLayers& layers, glm::vec3 v,
                              glm::vec3 l) {
  const float n_l = glm::dot(n, l), n_v = glm::dot(n, v), pi = glm::pi<float>();
  const float d = layers.diffuse_transmission;
  const bool lambertian = roughness < 0.0f, sheen = !lambertian && max_component(layers.sheen_color) > 0.0f;
  const float e_view = sheen ? sheen_albedo(n_v, layers.sheen_roughness) : 0.0f;
  if (n_l <= 0.0f) {
    // Only the view's side of the sheen is modelled on the way through.
    const glm::vec3 through = diffuse_transmitted_color(lambertian ? 0.0f : metallic, d, layers.diffuse_transmission_color) / pi;
    return coat_over(through * sheen_scaling(layers.sheen_color, e_view, 0.0f), n, layers, v, l);
  }
  if (lambertian) return (1.0f - d) * base / pi;
  const glm::vec3 beneath = base_layer_brdf(n, base, metallic, roughness, layers, v, l);
  if (!sheen) return coat_over(beneath, n, layers, v, l);
  const float e_light = sheen_albedo(n_l, layers.sheen_roughness);
  const glm::vec3 h = glm::normalize(v + l);
  const glm::vec3 lobe = layers.sheen_color * sheen_distribution(layers.sheen_roughness, glm::dot(n, h)) * sheen_visibility(n_l, n_v);
  return coat_over(beneath * sheen_scaling(layers.sheen_color, e_view, e_light) + lobe, n, layers, v, l);
}

// What the surface returns toward the viewer under a uniform sky of radiance 1 (both hemispheres).
// The specular lobe's share is taken as f0, the sheen's as C E(n.v) over what it leaves beneath.
// The transmitted part is the model's, unscaled: layered_brdf scales it by the sheen's view-side
// share, so this term is up to that factor brighter than the BRDF's integral. The coat reflects
// its blend factor's share of the sky whole and passes the rest, at the cosine coat_v of the view to
// its own normal (n_v where negative); a film's F0 is its reflectance head-on.
inline glm::vec3 layered_ambient(float n_v, glm::vec3 base, float metallic, float roughness, const SurfaceLayers& layers,
                                 float coat_v = -1.0f) {
  const float d = layers.diffuse_transmission;
  if (roughness < 0.0f) return (1.0f - d) * base + ambient_transmitted(0.0f, d, layers.diffuse_transmission_color);
  const FresnelEnds ends = fresnel_ends(base, metallic, layers);
  glm::vec3 f0 = ends.normal;
  if (layers.iridescence > 0.0f) f0 = glm::mix(f0, film_over_base(ends, layers, 1.0f), layers.iridescence);
  const bool sheen = max_component(layers.sheen_color) > 0.0f;
  const float e = sheen ? sheen_albedo(n_v, layers.sheen_roughness) : 0.0f;
  const glm::vec3 reflected = (diffuse_reflected_color(base, metallic, d) + f0) * sheen_scaling(layers.sheen_color, e, e);
  const float coat = coat_blend(layers, coat_v < 0.0f ? n_v : coat_v);
  return (reflected + layers.sheen_color * e + ambient_transmitted(metallic, d, layers.diffuse_transmission_color)) * (1.0f - coat) + coat;
}

}  // namespace caustica::reference
