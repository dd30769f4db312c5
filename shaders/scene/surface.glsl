#ifndef CAUSTICA_SURFACE_GLSL
#define CAUSTICA_SURFACE_GLSL
// An opaque surface as the lighting pass shades it: Lambertian (roughness below 0) or glTF's
// metallic-roughness BRDF (GGX with Smith height-correlated visibility and Schlick's Fresnel, the
// specification's appendix B), with what glTF's extensions put on it (docs/gltf.md, "Opaque
// surfaces"): KHR_materials_anisotropy stretches the GGX lobe along a direction in the surface,
// KHR_materials_diffuse_transmission passes a share of the diffuse light to the other side,
// KHR_materials_specular scales and colours the dielectric's Fresnel curve (its F0 from the index,
// KHR_materials_ior), KHR_materials_iridescence mixes a thin film's reflectance into it (the
// refractors' film, refraction/interface.glsl), KHR_materials_sheen lays a Charlie sheen over the
// rest, which it dims by its own albedo, and KHR_materials_clearcoat a clear GGX coat over all of it.
// reference/exact_scene.h's SurfacePoint (with reference/surface_physics.h) is the same model on
// the host, written apart. The extensions' terms are compiled where SURFACE_LAYERS is defined
// (lighting.frag: where the scene has such a surface): without them the lighting pass compiles
// as before they existed, and lavapipe compiled it about a tenth slower with them.

const float PI = 3.14159265358979;

#ifdef SURFACE_LAYERS
#include "common/scene_types.h"
#include "refraction/interface.glsl"
#endif

struct Surface {
  vec3 n;  // shading normal, facing the viewer
  vec3 base;
  float metallic;
  float roughness;
#ifdef SURFACE_LAYERS
  vec3 sheen_color;
  float sheen_roughness;
  vec4 sheen_albedo[4];  // the sheen's directional albedo at cosines (k / 15)^2 (ObjectData::sheen_albedo)
  vec3 anisotropy_t;     // the direction the lobe stretches along, in the surface (unit)
  float anisotropy;      // its strength, 0: round
  vec3 transmission_color;
  float transmission;   // the share of the diffuse light that passes to the other side
  vec4 specular;        // KHR_materials_specular: rgb the colour of the dielectric's F0, a its weight
  float dielectric_f0;  // ((ior - 1) / (ior + 1))^2: 0.04 at the default index 1.5
  float coat;           // the clear coat's weight
  float coat_roughness;
  vec3 coat_n;  // the coat's normal, facing the viewer: the geometry's, or its own normal map's
  float film;  // KHR_materials_iridescence: the film's weight, index and thickness in nm
  float film_ior;
  float film_thickness;
#endif
};

// A surface without extensions: what the G-buffer's normal and albedo targets hold.
Surface plain_surface(vec3 n, vec3 base, float metallic, float roughness) {
#ifdef SURFACE_LAYERS
  vec4 none = vec4(0.0);
  return Surface(n, base, metallic, roughness, vec3(0.0), 0.0, vec4[4](none, none, none, none), vec3(0.0), 0.0, vec3(0.0), 0.0, vec4(1.0),
                 0.04, 0.0, 0.0, n, 0.0, 1.3, 0.0);
#else
  return Surface(n, base, metallic, roughness);
#endif
}

// Whether light from behind the surface passes through it.
bool transmits_diffusely(Surface s) {
#ifdef SURFACE_LAYERS
  return s.transmission > 0.0;
#else
  return false;
#endif
}

float max3(vec3 v) {
  return max(v.r, max(v.g, v.b));
}

vec3 diffuse_color(Surface s) {
  return s.roughness < 0.0 ? s.base : s.base * (1.0 - s.metallic);
}
// The diffuse light that stays on the lit side.
vec3 diffuse_reflected(Surface s) {
#ifdef SURFACE_LAYERS
  return diffuse_color(s) * (1.0 - s.transmission);
#else
  return diffuse_color(s);
#endif
}
// Schlick's curve from F0 at normal incidence to F90 at grazing: the dielectric's F0 is its index's
// reflectance times the specular colour (at most 1), and both ends are scaled by the specular
// weight (KHR_materials_specular); metal's F0 is the base colour, its F90 1.
vec3 specular_f0(Surface s) {
  if (s.roughness < 0.0) return vec3(0.0);
#ifdef SURFACE_LAYERS
  return mix(min(s.dielectric_f0 * s.specular.rgb, vec3(1.0)) * s.specular.a, s.base, s.metallic);
#else
  return mix(vec3(0.04), s.base, s.metallic);
#endif
}
float specular_f90(Surface s) {
#ifdef SURFACE_LAYERS
  return mix(s.specular.a, 1.0, s.metallic);
#else
  return 1.0;
#endif
}

#ifdef SURFACE_LAYERS
// The sheen's directional albedo at cosine mu, interpolated in the object's table (sampled at
// cosines (k / 15)^2) linearly in sqrt(mu), as reference/surface_physics.h's sheen_albedo_from_table does.
float sheen_albedo(Surface s, float mu) {
  float x = sqrt(clamp(mu, 0.0, 1.0)) * 15.0;
  int i = min(int(x), 14);
  float f = x - float(i);
  return mix(s.sheen_albedo[i / 4][i % 4], s.sheen_albedo[(i + 1) / 4][(i + 1) % 4], f);
}
// What the sheen leaves of the light beneath it: the lesser of what it leaves at the view and at
// the light (the specification's albedo scaling).
float sheen_scaling(Surface s, float n_v, float n_l) {
  float strongest = max3(s.sheen_color);
  if (strongest <= 0.0) return 1.0;
  return clamp(min(1.0 - strongest * sheen_albedo(s, n_v), 1.0 - strongest * sheen_albedo(s, n_l)), 0.0, 1.0);
}
// Charlie's distribution (Estevez and Kulla 2017) with Ashikhmin's visibility, as the extension
// allows.
vec3 sheen_lobe(Surface s, float n_h, float n_l, float n_v) {
  float alpha = max(s.sheen_roughness * s.sheen_roughness, 1e-3);
  float distribution = (2.0 + 1.0 / alpha) * pow(max(1.0 - n_h * n_h, 0.0), 0.5 / alpha) / (2.0 * PI);
  float den = 4.0 * (n_l + n_v - n_l * n_v);
  return den > 0.0 ? s.sheen_color * distribution / den : vec3(0.0);
}
#endif

// GGX's distribution times its height-correlated visibility for alpha = roughness^2.
float ggx_lobe(float roughness, float n_h, float n_l, float n_v) {
  float a2 = max(roughness * roughness, 1e-3);
  a2 *= a2;
  float d = n_h * n_h * (a2 - 1.0) + 1.0;
  float visibility = 0.5 / max(n_l * sqrt(n_v * n_v * (1.0 - a2) + a2) + n_v * sqrt(n_l * n_l * (1.0 - a2) + a2), 1e-8);
  return a2 / (PI * d * d) * visibility;
}

// GGX's lobe (above); stretched to alpha_t = mix(alpha, 1,
// strength^2) along the anisotropy's direction (KHR_materials_anisotropy), round without one.
float specular_lobe(Surface s, vec3 v, vec3 l, vec3 h, float n_l, float n_v) {
  float n_h = max(dot(s.n, h), 0.0);
#ifdef SURFACE_LAYERS
  if (s.anisotropy <= 0.0) return ggx_lobe(s.roughness, n_h, n_l, n_v);
  float a = max(s.roughness * s.roughness, 1e-3);
  float at = mix(a, 1.0, s.anisotropy * s.anisotropy), ab = a;
  vec3 t = s.anisotropy_t, b = cross(s.n, t);
  float f = pow(dot(t, h) / at, 2.0) + pow(dot(b, h) / ab, 2.0) + n_h * n_h;
  float distribution = 1.0 / (PI * at * ab * f * f);
  float view = length(vec3(at * dot(t, v), ab * dot(b, v), n_v)), light = length(vec3(at * dot(t, l), ab * dot(b, l), n_l));
  return distribution * 0.5 / max(n_l * view + n_v * light, 1e-8);
#else
  return ggx_lobe(s.roughness, n_h, n_l, n_v);
#endif
}

#ifdef SURFACE_LAYERS
// KHR_materials_iridescence: a film of the material's index and thickness over a base whose index
// each channel's F0 gives, (1 + sqrt(F0 / F90)) / (1 - sqrt(F0 / F90)) (the dielectric's own index,
// or a metal's equivalent), at each channel's wavelength (interface.glsl's film_reflectance),
// scaled by F90 as the curve it replaces is.
vec3 film_fresnel(Surface s, vec3 f0, float f90, float cos_i) {
  vec3 root = sqrt(clamp(f0 / max(f90, 1e-6), 0.0, 0.9999));
  vec3 base_ior = (1.0 + root) / (1.0 - root);
  cos_i = clamp(cos_i, 0.0, 1.0);
  // A dielectric's substrate is one index for every channel: one Airy sum gives all three.
  if (base_ior.r == base_ior.g && base_ior.g == base_ior.b) return film_reflectance(cos_i, 1.0, s.film_ior, base_ior.r, s.film_thickness) * f90;
  vec3 film;
  for (int c = 0; c < 3; ++c) film[c] = film_reflectance(cos_i, 1.0, s.film_ior, base_ior[c], s.film_thickness)[c];
  return film * f90;
}

// The clear coat's share of the light at cosine cos_v to the normal: its weight times Schlick's
// curve from 0.04 (index 1.5), as the extension's blend factor takes it, at the view.
float coat_share(Surface s, float cos_v) {
  return s.coat * (0.04 + 0.96 * pow(1.0 - clamp(cos_v, 0.0, 1.0), 5.0));
}
#endif

// Radiance reflected toward v per unit irradiance arriving along l (unit, toward the light); light
// from behind the surface (n.l < 0) passes only through its diffuse transmission, Lambertian on
// the far side, without a Fresnel term (docs/gltf.md).
vec3 brdf(Surface s, vec3 v, vec3 l) {
  float n_l = dot(s.n, l), n_v = max(dot(s.n, v), 1e-4);
#ifdef SURFACE_LAYERS
  if (n_l < 0.0) {
    float strongest = max3(s.sheen_color);
    float sheen_left = strongest > 0.0 ? clamp(1.0 - strongest * sheen_albedo(s, n_v), 0.0, 1.0) : 1.0;
    return (s.roughness < 0.0 ? 1.0 : 1.0 - s.metallic) * s.transmission * s.transmission_color / PI * sheen_left *
           (1.0 - coat_share(s, dot(s.coat_n, v)));
  }
#else
  n_l = max(n_l, 0.0);
#endif
  if (s.roughness < 0.0) return diffuse_reflected(s) / PI;
  vec3 h = normalize(v + l);
  float v_h = max(dot(v, h), 0.0);
  vec3 f0 = specular_f0(s);
  vec3 fresnel = f0 + (specular_f90(s) - f0) * pow(1.0 - v_h, 5.0);
#ifdef SURFACE_LAYERS
  if (s.film > 0.0) fresnel = mix(fresnel, film_fresnel(s, f0, specular_f90(s), v_h), s.film);
#endif
  vec3 beneath = (1.0 - fresnel) * diffuse_reflected(s) / PI + fresnel * specular_lobe(s, v, l, h, n_l, n_v);
#ifdef SURFACE_LAYERS
  if (max3(s.sheen_color) > 0.0) beneath = beneath * sheen_scaling(s, n_v, n_l) + sheen_lobe(s, max(dot(s.n, h), 0.0), n_l, n_v);
  if (s.coat <= 0.0) return beneath;
  // The coat's lobe about its own normal (KHR_materials_clearcoat's clearcoatNormalTexture).
  float coat_v = dot(s.coat_n, v), coat_l = dot(s.coat_n, l);
  float coat = coat_share(s, coat_v);
  float lobe = coat_l > 0.0 ? ggx_lobe(s.coat_roughness, max(dot(s.coat_n, h), 0.0), coat_l, max(coat_v, 1e-4)) : 0.0;
  return beneath * (1.0 - coat) + coat * lobe;
#else
  return beneath;
#endif
}

// Radiance reflected toward v per unit of a uniform sky's radiance: the diffuse and F0 terms as
// before (the split-sum's crude form), beneath the sheen's albedo at the view, plus the diffuse
// transmission's share from the sky behind, all beneath the coat, which reflects its share whole. A
// film's F0 is its reflectance at normal incidence.
vec3 ambient_reflectance(Surface s, vec3 v) {
#ifndef SURFACE_LAYERS
  return diffuse_color(s) + specular_f0(s);
#else
  float e = max3(s.sheen_color) > 0.0 ? sheen_albedo(s, max(dot(s.n, v), 1e-4)) : 0.0;
  vec3 transmitted = (s.roughness < 0.0 ? 1.0 : 1.0 - s.metallic) * s.transmission * s.transmission_color;
  vec3 f0 = specular_f0(s);
  if (s.film > 0.0 && s.roughness >= 0.0) f0 = mix(f0, film_fresnel(s, f0, specular_f90(s), 1.0), s.film);
  vec3 beneath = (diffuse_reflected(s) + f0) * (1.0 - max3(s.sheen_color) * e) + s.sheen_color * e + transmitted;
  float coat = coat_share(s, dot(s.coat_n, v));
  return beneath * (1.0 - coat) + coat;
#endif
}

#endif
