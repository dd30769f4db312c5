#ifndef CAUSTICA_EXACT_PATH_GLSL
#define CAUSTICA_EXACT_PATH_GLSL
// The device's one exact path tracer: photons (caustics/photon.glsl) and camera rays (the deferred
// pass, refraction.glsl) both walk the scene through it, interface by interface, so that the two
// sides cannot disagree on the physics: absorption inside, a refractor's entry and exit with the
// band's index of refraction, Fresnel reflection or transmission, total internal reflection, thin
// walls (reflected through the wall, unbent where smooth), rough surfaces (a microfacet normal drawn
// from the path's random numbers), the tint and transmission past an entry, and at most
// params.exact_max_interfaces refractor interfaces. What each side makes of the events (a photon
// lands or is counted, a camera ray shades and sums radiance) stays with the caller.
//
// Needs refraction.glsl's helpers (included before) and `params` with exact_max_interfaces and
// exact_epsilon. Each caller calls exact_path_step at one site, in its loop: lavapipe inlines every
// call, and each copy of a ray query lengthens a pipeline's first compile by seconds.
#include "scene/trace.glsl"

struct ExactPath {
  vec3 origin;
  vec3 direction;
  int inside;       // the refractor the path travels in, or -1
  uint interfaces;  // refractor interfaces met so far
  uint rng;         // the path's random numbers, in the order it draws them
  vec3 throughput;  // what is left of what it started with (absorption, tint; Fresnel when weighted)
};

const uint PATH_ESCAPED = 0u;    // met nothing: the path left the scene
const uint PATH_OPAQUE = 1u;     // ended on an opaque surface
const uint PATH_TRAPPED = 2u;    // met a refractor after exact_max_interfaces interfaces
const uint PATH_DISPERSED = 3u;  // a white path (BAND_WHITE) met a dispersive solid: trace each band instead
const uint PATH_INTERFACE = 4u;  // reflected off or passed through a refractor's surface, and goes on

// What one step met. At a refractor's surface: whether the path came from outside (`entering`; a
// thin wall is always entered), the Fresnel reflectance there (1 at total internal reflection),
// whether the path reflected, the surface's roughness, and, where it passed an entry, the tint and
// transmission that the share past the surface kept (the rest is diffuse, the caller's to shade).
struct PathEvent {
  uint kind;
  vec3 position;
  vec3 normal;  // facing the side the path came from
  uint object;
  bool entering;
  bool reflected;
  vec3 reflectance;  // per channel (refraction/interface.glsl)
  float roughness;
  vec4 tint_transmission;
};

// Traces the path to its next surface and across it. With `choose_reflection` the reflection or
// the transmission is chosen by random numbers (photons: a clear coat's reflection first, then the
// base's, each side weighted by choice_weight, so that throughput keeps its power where the
// interface is uncoloured); without, the path goes on transmitted weighted by 1 - reflectance and
// reflects only totally (camera rays: the caller adds what the entry's reflection sees). `fresnel`
// off leaves only total internal reflection.
PathEvent exact_path_step(inout ExactPath path, uint band, bool fresnel, bool choose_reflection) {
  PathEvent e;
  e.entering = path.inside < 0;
  e.reflected = false;
  e.reflectance = vec3(0.0);
  e.roughness = 0.0;
  e.tint_transmission = vec4(1.0);
  SurfaceHit h = trace_surface(path.origin, path.direction, path.interfaces == 0u ? 0.0 : params.exact_epsilon, CAUSTICA_ALL_INSTANCES);
  if (!h.hit) {
    e.kind = PATH_ESCAPED;
    return e;
  }
  if (path.inside >= 0) path.throughput *= exp(-objects[path.inside].absorption_ior.rgb * h.t);
  e.position = path.origin + path.direction * h.t;
  e.normal = dot(h.normal, path.direction) > 0.0 ? -h.normal : h.normal;
  e.object = h.object;
  ObjectData object = objects[h.object];
  if (object.albedo_refractor.a < 0.5) {
    e.kind = PATH_OPAQUE;
    return e;
  }
  if (path.interfaces == params.exact_max_interfaces) {
    e.kind = PATH_TRAPPED;
    return e;
  }
  ++path.interfaces;
  bool thin = thin_walled(object);
  if (band == BAND_WHITE && !thin && disperses(object)) {
    e.kind = PATH_DISPERSED;
    return e;
  }
  e.kind = PATH_INTERFACE;
  e.roughness = roughness_at(h);
  vec3 n = e.normal, direction = path.direction;
  vec3 m = microfacet_normal(n, direction, e.roughness, path.rng);
  float ior = band_ior(object, band);
  vec3 transmitted = thin ? through_thin(direction, m, n) : refract(direction, m, e.entering ? 1.0 / ior : ior);
  bool total_internal = dot(transmitted, transmitted) == 0.0;
  InterfaceReflection layers = InterfaceReflection(vec3(total_internal ? 1.0 : 0.0), 0.0);
  // The layers here, per texel; whether a choice draws a number is the object's (its means), so
  // that image space, which reads the object, knows how many the entry draws (entry_choice_draws).
  ObjectData surface = object;
  vec3 coat_n = n;  // the clear coat's normal: its own normal map's, per texel, where it has one
#ifdef CAUSTICA_LAYER_TEXTURES
  if (object.layer_factors.w > 0.0) {
    layers_at(h.object, h.texcoords, surface.specular, surface.layers, surface.film.x);
    coat_n = coat_normal_at(h, n);
  }
#endif
  bool layered_crossing = fresnel && !total_internal;
  if (layered_crossing) {
    // The coat is on the outside: its cosine is the light's there (after the crossing, leaving).
    float cos_outside = e.entering || thin ? -dot(direction, coat_n) : -dot(normalize(transmitted), coat_n);
    layers = interface_reflection(surface, -dot(direction, m), cos_outside, e.entering ? 1.0 : ior, e.entering ? ior : 1.0);
  }
  e.reflectance = reflectance(layers);
  path.origin = e.position;
  if (choose_reflection) {
    vec3 reflecting = m;
    if (layered_crossing && object.layers.x > 0.0 && next_uniform(path.rng) < layers.coat) {
      e.reflected = true;
      reflecting = microfacet_normal(coat_n, direction, surface.layers.y, path.rng);
    } else {
      float p = choice_probability(layers.base, band);
      bool draws = total_internal || (layered_crossing && base_reflects(object, ior));
      e.reflected = draws && next_uniform(path.rng) < p;
      path.throughput *= e.reflected ? choice_weight(layers.base, p) : choice_weight(1.0 - layers.base, 1.0 - p);
    }
    if (e.reflected) {
      path.direction = on_side(reflect(direction, reflecting), n, true);
      return e;
    }
  } else {
    e.reflected = total_internal;
    if (!total_internal) path.throughput *= 1.0 - e.reflectance;
    if (e.reflected) {
      path.direction = on_side(reflect(direction, m), n, true);
      return e;
    }
  }
  if (e.entering) {
    e.tint_transmission = tint_transmission_at(h);
    path.throughput *= e.tint_transmission.a * e.tint_transmission.rgb;
  }
  path.direction = on_side(normalize(transmitted), n, false);
  if (!thin) path.inside = e.entering ? int(h.object) : -1;
  return e;
}

#endif
