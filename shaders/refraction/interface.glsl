#ifndef CAUSTICA_INTERFACE_GLSL
#define CAUSTICA_INTERFACE_GLSL
// A refractor's interface: how much light it reflects, per colour channel, and the colour bands
// that dispersion traces. One model for every device path that meets a refractor's surface (camera
// refraction, image-space and exact photons, both exact tracers); the references' copy is
// reference/interface_physics.h, written apart from this one (docs/gltf.md, "The interface").
//
// The base is exact unpolarised Fresnel. glTF's material extensions layer on it, in this order:
// - KHR_materials_iridescence: a thin film (index layers.w, film.x nm thick) between the outside
//   and the base reflects what its two interfaces' waves add up to (Airy's sum, s and p averaged)
//   at each channel's wavelength, the Fraunhofer C, d and F lines as dispersion's bands; the
//   material's weight layers.z mixes it with the bare Fresnel.
// - KHR_materials_specular: the curve is rescaled from its normal-incidence value F0 to F0 times
//   the specular colour (at most 1), keeping its angular shape (and 1 at total internal
//   reflection), then weighted by specular.a.
// - KHR_materials_clearcoat: a coat of index 1.5 (the extension's F0 of 0.04, Schlick's curve
//   about the surface's normal, on the outside) of weight layers.x reflects first; the rest meets
//   the base.
// What is not reflected crosses, channel by channel: a film's reflected colour leaves its
// complement in the caustic (the specification's max() over channels is a rasteriser's way to keep
// energy over a diffuse base; per channel is what light does).

// Unpolarised Fresnel reflectance from medium eta_i into eta_t; 1 under total internal reflection.
float fresnel_dielectric(float cos_i, float eta_i, float eta_t) {
  cos_i = clamp(cos_i, 0.0, 1.0);
  float sin_t = eta_i / eta_t * sqrt(max(0.0, 1.0 - cos_i * cos_i));
  if (sin_t >= 1.0) return 1.0;
  float cos_t = sqrt(max(0.0, 1.0 - sin_t * sin_t));
  float rs = (eta_i * cos_i - eta_t * cos_t) / (eta_i * cos_i + eta_t * cos_t);
  float rp = (eta_t * cos_i - eta_i * cos_t) / (eta_t * cos_i + eta_i * cos_t);
  return 0.5 * (rs * rs + rp * rp);
}

// Colour bands (KHR_materials_dispersion): BAND_WHITE is one path for every channel with the index
// n_d; bands 0, 1, 2 (red, green, blue) refract with the index of the C, d and F lines. Where each
// band's index lies, in units of n_F - n_C above n_d: (1/lambda^2 - 1/lambda_d^2) / (1/lambda_F^2 -
// 1/lambda_C^2), from the lines in common/scene_types.h (as scene::Material::band_iors).
const uint BAND_WHITE = 3u;
const vec3 BAND_WAVELENGTHS_NM = vec3(CAUSTICA_LINE_C_NM, CAUSTICA_LINE_D_NM, CAUSTICA_LINE_F_NM);
const vec3 BAND_INV2 = 1.0 / (BAND_WAVELENGTHS_NM * BAND_WAVELENGTHS_NM);
const vec3 BAND_SPREAD = (BAND_INV2 - BAND_INV2.y) / (BAND_INV2.z - BAND_INV2.x);
bool disperses(ObjectData object) {
  return object.bounds_max_spread.w > 0.0;
}
float band_ior(ObjectData object, uint band) {
  return band == BAND_WHITE ? object.absorption_ior.a : object.absorption_ior.a + BAND_SPREAD[band] * object.bounds_max_spread.w;
}

// Amplitude reflection coefficients (s, p) from medium a into b at cosines cos_a, cos_b.
vec2 amplitude_reflection(float n_a, float cos_a, float n_b, float cos_b) {
  return vec2((n_a * cos_a - n_b * cos_b) / (n_a * cos_a + n_b * cos_b), (n_b * cos_a - n_a * cos_b) / (n_b * cos_a + n_a * cos_b));
}

// A film of index n_film and `thickness_nm` between eta_i (the light's side) and eta_t: its
// reflectance at each channel's wavelength, where the wave reflected off its top and the waves
// that cross it and come back add up with the phase 4 pi n_film d cos_film / lambda. The caller
// has ruled out total internal reflection into eta_t; a film of index 1 or more cannot reflect
// totally before it (one side is air).
vec3 film_reflectance(float cos_i, float eta_i, float n_film, float eta_t, float thickness_nm) {
  float sin2_i = 1.0 - cos_i * cos_i;
  float cos_film = sqrt(max(0.0, 1.0 - (eta_i / n_film) * (eta_i / n_film) * sin2_i));
  float cos_t = sqrt(max(0.0, 1.0 - (eta_i / eta_t) * (eta_i / eta_t) * sin2_i));
  vec2 r12 = amplitude_reflection(eta_i, cos_i, n_film, cos_film), r23 = amplitude_reflection(n_film, cos_film, eta_t, cos_t);
  vec3 phase = 4.0 * 3.14159265358979 * n_film * thickness_nm * cos_film / BAND_WAVELENGTHS_NM;
  vec3 reflectance;
  for (int c = 0; c < 3; ++c) {
    vec2 cross_term = 2.0 * r12 * r23 * cos(phase[c]);
    vec2 r = (r12 * r12 + r23 * r23 + cross_term) / max(1.0 + r12 * r12 * r23 * r23 + cross_term, vec2(1e-12));
    reflectance[c] = 0.5 * (r.x + r.y);
  }
  return reflectance;
}

// What an interface reflects: `base`, per channel, of the light past the coat, which reflects the
// share `coat` of all of it first. reflectance() is the whole: what does not reflect crosses.
struct InterfaceReflection {
  vec3 base;
  float coat;
};
vec3 reflectance(InterfaceReflection r) {
  return r.coat + (1.0 - r.coat) * r.base;
}

// The interface of `object` met at cosine cos_i to the facet normal, from index eta_i into eta_t;
// cos_outside is the light's cosine to the surface's normal on the outside (where the coat is).
InterfaceReflection interface_reflection(ObjectData object, float cos_i, float cos_outside, float eta_i, float eta_t) {
  InterfaceReflection r;
  r.coat = 0.0;
  float f = fresnel_dielectric(cos_i, eta_i, eta_t);
  if (f >= 1.0) {  // total internal reflection: no layer changes it
    r.base = vec3(1.0);
    return r;
  }
  vec3 base = vec3(f);
  if (object.layers.z > 0.0)
    base = mix(base, film_reflectance(clamp(cos_i, 0.0, 1.0), eta_i, object.layers.w, eta_t, object.film.x), object.layers.z);
  float f0 = (eta_t - eta_i) * (eta_t - eta_i) / ((eta_t + eta_i) * (eta_t + eta_i));
  if (object.specular.rgb != vec3(1.0) && f0 < 1.0) {
    vec3 tinted_f0 = min(f0 * object.specular.rgb, vec3(1.0));
    base = clamp(tinted_f0 + (1.0 - tinted_f0) * (base - f0) / (1.0 - f0), 0.0, 1.0);
  }
  r.base = object.specular.a * base;
  if (object.layers.x > 0.0) r.coat = object.layers.x * (0.04 + 0.96 * pow(1.0 - clamp(cos_outside, 0.0, 1.0), 5.0));
  return r;
}

// The light's cosine to the coat's normal where a ray along v meets a surface whose normal n faces
// the ray's origin: the coat's own where its normal map bends it (ObjectData::coat_normal.yzw, which
// image space's at_front_texel and forward refraction set from the map at the entry's texel),
// turned to n's side; else n's.
float coat_cos_outside(ObjectData object, vec3 v, vec3 n) {
  vec3 coat = object.coat_normal.yzw;
  if (dot(coat, coat) == 0.0) return -dot(v, n);
  return -dot(v, dot(coat, n) < 0.0 ? -coat : coat);
}

// Whether an extension layers the interface (a coat, a film, a coloured or weighted specular): the
// photons' choices there draw more than one number and weight their powers.
bool layered(ObjectData object) {
  return object.layers.x > 0.0 || object.layers.z > 0.0 || object.specular != vec4(1.0);
}

// Whether a refractor's base reflects anything at an interface into index ior (a film reflects
// even where the indices match), from the object's values: where a layer texture makes it reflect
// nothing at some texels, a photon there still draws its choice (and never reflects), so that
// every photon at an object draws alike.
bool base_reflects(ObjectData object, float ior) {
  return object.specular.a > 0.0 && (ior != 1.0 || object.layers.z > 0.0);
}

// How many random numbers a photon's choices at a refractor's entry draw (refraction/exact_path.glsl:
// the coat's where it has one, then the base's where it reflects at all).
uint entry_choice_draws(ObjectData object, float ior, bool fresnel) {
  if (!fresnel) return 0u;
  return (object.layers.x > 0.0 ? 1u : 0u) + (base_reflects(object, ior) ? 1u : 0u);
}

// Photons choose one side of an interface at random: the probability of a path of colour band
// `band` taking `share` (per channel), and the weight that keeps its expectation (exactly 1 where
// the share is the same in every channel, so that an uncoloured interface leaves powers as they are).
float choice_probability(vec3 share, uint band) {
  if (band != BAND_WHITE) return share[band];
  return share.r == share.g && share.g == share.b ? share.r : (share.r + share.g + share.b) / 3.0;
}
vec3 choice_weight(vec3 share, float probability) {
  return share == vec3(probability) ? vec3(1.0) : share / max(probability, 1e-12);
}

#endif
