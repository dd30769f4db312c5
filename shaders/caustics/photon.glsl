#ifndef CAUSTICA_PHOTON_GLSL
#define CAUSTICA_PHOTON_GLSL
// One photon from a spot light through the light-view refractor buffers to the receivers, shared by
// every caustic method. Needs, declared before inclusion: SCENE_FRAME, SCENE_OBJECTS, front_tex,
// back_tex, receiver_depth, caustic_map, and `params` with distance_mode, search (search_steps()),
// search_distance, fresnel (see refraction.glsl) and exact_seed (photon_rng); with
// CAUSTICA_RAY_QUERY also `counters`, `sums` and the exact-path fields exact_max_interfaces,
// exact_counters, exact_epsilon, hybrid_packed (hybrid_tolerance and hybrid_reflections as two
// halves: the push constants have no room for another word). What image space needs is what a
// user pass can give (docs/shader_api.md).
//
// With CAUSTICA_RAY_QUERY defined (the pass compiles it so when its `distance` is ray_query, hybrid
// or material; CAUSTICA_HYBRID too for hybrid), photons can also be traced exactly through the scene's acceleration structures: every
// interface, Fresnel reflection or transmission chosen by a deterministic random number, total
// internal reflection followed, absorption, up to exact_max_interfaces refractor interfaces.
#extension GL_EXT_shader_atomic_float : require
#define REFRACTION_NO_CAMERA
#define REFRACTION_FRONT_TEX
#include "refraction/refraction.glsl"

// Exact-path counters, at consecutive slots from params.exact_counters (passes/refraction.cpp,
// add_exact_path_counters, names them in this order).
const uint EXACT_TRACED = 0u, EXACT_ESCAPED = 1u, EXACT_TRAPPED = 2u, EXACT_OFF_MAP = 3u, EXACT_REFLECTED_OUTSIDE = 4u;
const uint RETRACED_FIRST = 5u;             // photons.retraced.*: one slot per EXIT_* reason of refraction.glsl, in its order,
const uint RETRACED_NO_LANDING = 9u;        // then one for a trusted exit ray that lands nowhere on the caustic map,
const uint RETRACED_REFRACTOR_AHEAD = 10u;  // one for a trusted exit ray that meets a refractor,
const uint RETRACED_REFLECTION = 11u;       // and one for a Fresnel reflection split off a trusted path (traced from the split)
const uint EXACT_FLUX_ESCAPED = 12u, EXACT_FLUX_TRAPPED = 13u, EXACT_FLUX_OFF_MAP = 14u, EXACT_FLUX_ABSORBED = 15u;
// Where exact-path counter k goes: the built-ins' slot from params.exact_counters; a user pass
// defines EXACT_COUNTER_SLOT(k) as the place of that counter among its own (docs/shader_api.md).
#ifndef EXACT_COUNTER_SLOT
#define EXACT_COUNTER_SLOT(k) (params.exact_counters + (k))
#endif
#ifdef CAUSTICA_RAY_QUERY
void exact_count(uint k) {
  atomicAdd(counters[EXACT_COUNTER_SLOT(k)], 1u);
}
#endif
// Photons are white (BAND_WHITE: one path carries all three channels), or, when the scene has a
// dispersive refractor, the pass traces every photon once per colour band (photon_band, which the
// kernel sets before begin_photon), each with that band's index of refraction (refraction.glsl's
// band_ior) and its power in that channel only.
// Flux counters hold the mean of a photon's three channels: the light's own units for a white photon.
uint photon_band = BAND_WHITE;
float channel_mean(vec3 power) {
  return dot(power, vec3(1.0 / 3.0));
}

#ifdef CAUSTICA_RAY_QUERY
void exact_sum(uint k, vec3 v) {
  atomicAdd(sums[EXACT_COUNTER_SLOT(k)], channel_mean(v));
}
#include "refraction/exact_path.glsl"
#endif
#ifdef CAUSTICA_HYBRID
#include "refraction/hybrid.glsl"
#endif

// The random numbers of the photon through `uv` (its position on the light's image plane), in the
// order its Fresnel choices and rough surfaces draw them: the same on every device and in every run.
// photon_stream picks an independent second set for the same photons (the adaptive traversals'
// second look at a cluster, adaptive_photons.comp).
uint photon_stream = 0u;
uint photon_rng(vec2 uv) {
  return pcg_hash(floatBitsToUint(uv.x) ^ pcg_hash(floatBitsToUint(uv.y) ^ pcg_hash(params.exact_seed + photon_stream * 0x9E3779B9u)));
}

struct Photon {
  vec3 power;      // per caustic-map channel, after Fresnel, tint and absorption; as it left the light when it missed
  float entering;  // the channels' mean of its power before the refractor, when it met one (else 0)
  bool hit;        // met a refractor
  bool tir;        // dropped: total internal reflection at the back surface
  bool landed;     // reached a receiver at `texel` of the caustic map
  ivec2 texel;
  vec2 landing;   // where it landed, in caustic-map texels (texel = floor(landing), clamped)
  bool random;    // its path drew random numbers (Fresnel choices, rough facets)
  bool bounced;   // its exact path reflected inside a refractor
  bool followed;  // its image-space search followed total internal reflection inside
  // The hybrid's Fresnel reflection split off an image-space path (below): traced exactly, it
  // lands at side_texel with side_power when side_landed. It draws its own random numbers, which
  // do not touch the photon's own path, so the adaptive traversals decide on that path alone.
  bool side_landed;
  ivec2 side_texel;
  vec3 side_power;
};

// Where an exact path starts: at the light, or where the hybrid splits a Fresnel reflection off an
// image-space path (on the entry, outside; at the exit, inside `inside` after `interfaces` of them).
struct ExactStart {
  vec3 origin;
  vec3 direction;
  int inside;
  uint interfaces;
  uint rng;
};

// Lands a photon at `uv` on the light's image plane: its caustic-map texel.
void land_on_map(inout Photon ph, vec2 uv) {
  ivec2 size = imageSize(caustic_map).xy;
  ph.landing = uv * vec2(size);
  ph.texel = clamp(ivec2(ph.landing), ivec2(0), size - 1);
  ph.landed = true;
}

// Whether a ray from `origin` along `direction` meets the bounding box of a receiver (an opaque
// object) ahead of it.
bool receiver_box_ahead(vec3 origin, vec3 direction) {
  vec3 inverse_direction = slab_inverse(direction);
  for (uint o = 0u; o < uint(objects.length()); ++o) {
    if (objects[o].albedo_refractor.a != 0.0) continue;
    vec3 t0 = (objects[o].bounds_min_thin.xyz - origin) * inverse_direction, t1 = (objects[o].bounds_max_spread.xyz - origin) * inverse_direction;
    vec3 near = min(t0, t1), far = max(t0, t1);
    if (max(max(near.x, near.y), max(near.z, 0.0)) <= min(min(far.x, far.y), far.z)) return true;
  }
  return false;
}

// Where a photon leaving a refractor at `origin` along `direction` lands in image space: where its
// ray meets the receivers the light sees (march_depth), or, where it slips behind the outline of
// one, on that outline (the light's texel of whatever hides the rest of its path) when a receiver's
// box lies ahead of it, for the surface hidden from the light that it meets there. With no receiver
// ahead (a photon past a floor's far edge) it escapes, as it does on the exact paths and in the
// photon reference.
bool lands_in_image_space(LightData light, vec3 origin, vec3 direction, out vec2 landing) {
  uint found = march_depth(receiver_depth, light.view_proj, origin, direction, landing);
  return found == MARCH_HIT || (found == MARCH_HIDDEN && receiver_box_ahead(origin, direction));
}

#ifdef CAUSTICA_RAY_QUERY
// Lands a photon at world point p seen from the light: in the caustic map, or off it.
void land_at(inout Photon ph, LightData light, vec3 p) {
  vec2 uv;
  float depth;
  if (!project_with(light.view_proj, p, uv, depth) || any(greaterThanEqual(uv, vec2(1.0)))) {
    exact_count(EXACT_OFF_MAP);
    exact_sum(EXACT_FLUX_OFF_MAP, ph.power);
    return;
  }
  land_on_map(ph, uv);
}

// The photon's path from `start` (its whole path from the light, or the rest of one), exact, by
// refraction/exact_path.glsl with Fresnel choices drawn. Sets hit, entering, power, landed, texel,
// landing; what does not land is counted by where it went (escaped, trapped, off the map, absorbed).
void trace_photon_exact(inout Photon ph, LightData light, ExactStart start) {
  ExactPath path = ExactPath(start.origin, start.direction, start.inside, start.interfaces, start.rng, ph.power);
  for (;;) {
    vec3 before = path.throughput;
    PathEvent e = exact_path_step(path, photon_band, params.fresnel != 0u, true);
    if (e.kind == PATH_ESCAPED) {
      if (ph.hit) {
        exact_count(EXACT_ESCAPED);
        exact_sum(EXACT_FLUX_ESCAPED, ph.power);
      }
      return;
    }
    // Absorbed inside, or at an entry left to the diffuse share by the tint and transmission.
    if (path.throughput != before) exact_sum(EXACT_FLUX_ABSORBED, before - path.throughput);
    ph.power = path.throughput;
    if (e.kind == PATH_OPAQUE) {
      if (ph.hit) land_at(ph, light, e.position);  // else direct light, not a caustic
      return;
    }
    if (!ph.hit) {
      ph.hit = true;
      ph.entering = channel_mean(before);
      exact_count(EXACT_TRACED);
    }
    if (e.kind == PATH_TRAPPED) {
      exact_count(EXACT_TRAPPED);
      exact_sum(EXACT_FLUX_TRAPPED, ph.power);
      return;
    }
    ph.random = ph.random || e.roughness > 0.0 || (e.reflectance != vec3(0.0) && e.reflectance != vec3(1.0));
    if (e.reflected) {
      if (e.entering) exact_count(EXACT_REFLECTED_OUTSIDE);
      ph.bounced = ph.bounced || !e.entering;
    }
  }
}
#endif

// What a photon needs after its image-space part: nothing more, an exact trace from the light
// instead (distance modes hybrid and material), or an exact trace of the Fresnel reflection split
// off its path (hybrid) from `start`. finish_photon traces, and it alone, so that the exact tracer,
// which the compiler inlines, is in the shader once (each copy of it added tens of seconds to
// lavapipe's first compile under the sanitizers).
const uint IMAGE_SPACE_DONE = 0u, TRACE_FROM_LIGHT = 1u, TRACE_SIDE_PATH = 2u;

// Through a thin wall, or a closed thin object's two, unbent: image space sees the exact path.
uint thin_wall_photon(inout Photon ph, LightData light, vec2 uv, vec3 eye, vec3 direction, vec4 front, ObjectData object, float receiver,
                      float receiver_distance, vec3 p1) {
  float ior = band_ior(object, photon_band);
  vec4 back = texture(back_tex, uv);
  bool far_wall = thin_far_wall(front, back) && back.y < receiver_distance;
  vec3 n_near = unpack_normal(front.x);
  float cos_near = abs(dot(direction, n_near)), cos_far = abs(dot(direction, unpack_normal(back.x)));
  ObjectData near = at_front_texel(object, uv);  // the near wall's texels; the far wall keeps the means
  vec3 facing = dot(direction, n_near) > 0.0 ? -n_near : n_near;
  vec3 reflect_near =
      params.fresnel != 0u ? reflectance(interface_reflection(near, cos_near, coat_cos_outside(near, direction, facing), 1.0, ior)) : vec3(0.0);
  vec3 reflect_far = far_wall && params.fresnel != 0u ? reflectance(interface_reflection(object, cos_far, cos_far, 1.0, ior)) : vec3(0.0);
#if defined(CAUSTICA_RAY_QUERY) && !defined(PHOTON_CLUSTERS)
  if (DISTANCE_MODE == DISTANCE_MATERIAL) {
    // Light a wall reflects lands too, where image space cannot follow it: the exact tracer's
    // Fresnel choices are replayed (the same random numbers), a photon that one of the walls
    // reflects is traced exactly, and the rest pass both walls in image space at full weight.
    // Not in the adaptive traversals: there a cluster whose photons all happened to pass
    // converges with their whole power while one that reflected refines on, which biases the
    // map upward (thin panes 1.033 of the reference at 2048^2); they keep the Fresnel weights.
    uint rng = photon_rng(uv);
    // (image_space_is_exact: a plain interface, whose reflectance is the same in every channel)
    if ((reflect_near.r > 0.0 && next_uniform(rng) < reflect_near.r) || (reflect_far.r > 0.0 && next_uniform(rng) < reflect_far.r)) {
      return TRACE_FROM_LIGHT;
    }
    reflect_near = reflect_far = vec3(0.0);
  }
#endif
  ph.power *= (1.0 - reflect_near) * caustic_transmittance(near);
  if (far_wall) ph.power *= (1.0 - reflect_far) * caustic_transmittance(object);  // the far wall: means
  float roughness = transmission_roughness(object);
  ph.random = roughness > 0.0;
  if (roughness > 0.0) {  // scattered by each wall (at the far wall's texel here), it lands where it meets a receiver
    uint rng = photon_rng(uv);
    vec3 n1 = unpack_normal(front.x), n2 = unpack_normal(back.x);
    n1 = dot(direction, n1) > 0.0 ? -n1 : n1;
    vec3 d = through_thin(direction, microfacet_normal(n1, direction, roughness, rng), n1);
    if (far_wall) {
      n2 = dot(d, n2) > 0.0 ? -n2 : n2;
      d = through_thin(d, microfacet_normal(n2, d, roughness, rng), n2);
    }
    vec2 landing;
    if (lands_in_image_space(light, far_wall ? eye + direction * back.y : p1, d, landing)) land_on_map(ph, landing);
    return IMAGE_SPACE_DONE;
  }
  // Unbent, it goes on along its own light ray: it lands on the receiver seen at uv.
  if (receiver < 1.0) land_on_map(ph, uv);
  return IMAGE_SPACE_DONE;
}

#ifdef CAUSTICA_HYBRID
// Whether the hybrid trusts an image-space path, and where it then lands (`landing`, on the light's
// image plane).
bool hybrid_trusts(TwoInterfaces path, LightData light, vec2 uv, vec4 front, out vec2 landing) {
  // A trusted path's exit ray is traced exactly: image space sees one refractor layer, and the
  // receiver march lands a photon only to the light map's precision.
  bool hit;
  vec3 ground;
  uint reason = hybrid_exit_ray(path, front, texture(back_tex, uv), unpackHalf2x16(params.hybrid_packed).x, hit, ground);
  if (reason != EXIT_TRUSTED) {
    exact_count(reason == EXIT_REFRACTOR_AHEAD ? RETRACED_REFRACTOR_AHEAD : RETRACED_FIRST + reason - EXIT_TIR);
    return false;
  }
  // One that lands nowhere on the map leaves the refractor where image space is least sure of it
  // (near its outline, bent the most): re-traced, which measured better than trusting it.
  float depth;
  if (!hit || !project_with(light.view_proj, ground, landing, depth) || any(greaterThanEqual(landing, vec2(1.0)))) {
    exact_count(RETRACED_NO_LANDING);
    return false;
  }
  // Another refractor's bounds on the way: the estimated ray may just miss what the true one meets.
  if (crosses_other_refractor(path.exit_point, ground, uint(front.w))) {
    exact_count(RETRACED_FIRST + EXIT_MULTIPLE - EXIT_TIR);
    return false;
  }
  return true;
}

// The Fresnel reflections that image space cannot follow (off the entry, or back inside at the
// exit, where at n = 2.4 a fifth of the light turns) land too: the path keeps its transmitted
// share, and one random choice picks which reflection, if any, to trace exactly with the rest of
// the power, each with its probability times the share `hybrid_reflections` of photons that
// trace one, and its power divided by that share (so the map's expectation stays the same).
// Returns TRACE_SIDE_PATH with `start` and ph.side_power set when it picks one.
uint hybrid_side_path(inout Photon ph, inout ExactStart start, TwoInterfaces path, vec3 p1, vec4 front, vec3 inside_power, uint rng) {
  uint next = IMAGE_SPACE_DONE;
  float share = unpackHalf2x16(params.hybrid_packed).y;
  if (params.fresnel != 0u && share > 0.0) {
    vec3 reflect_in = path.reflectance_in, reflect_out = (1.0 - path.reflectance_in) * (1.0 - path.transmit_out);
    float p_in = choice_probability(reflect_in, photon_band), p_out = choice_probability(reflect_out, photon_band);
    float choice = next_uniform(rng) / share;
    if (choice < p_in) {
      exact_count(EXACT_REFLECTED_OUTSIDE);
      start = ExactStart(p1, path.entry_reflection, -1, 1u, rng);
      ph.side_power = ph.power * choice_weight(reflect_in, p_in) / share;
      next = TRACE_SIDE_PATH;
    } else if (choice < p_in + p_out) {
      start = ExactStart(path.exit_point, path.exit_reflection, int(front.w), 2u, rng);
      ph.side_power = inside_power * choice_weight(reflect_out, p_out) / share;
      next = TRACE_SIDE_PATH;
    }
  }
  return next;
}
#endif

// The image-space part of begin_photon: through the light-view refractor buffers to the receiver.
// A photon from a light inside a solid refractor (LightData::face.y: a bulb in a glass globe): it
// starts in the glass, and its one interface is the nearest back face the light sees (the back
// buffer, drawn from inside), where it leaves into the air for the receivers; refractors beyond
// that are not followed (image space follows one refractor at a time).
uint inside_photon(inout Photon ph, LightData light, vec2 uv, vec3 eye, vec3 direction) {
  vec4 back = texture(back_tex, uv);
  if (back.y <= 0.0) return IMAGE_SPACE_DONE;
  ObjectData object = objects[uint(back.w)];
  ph.hit = true;
  ph.entering = channel_mean(ph.power);
  vec3 n = unpack_normal(back.x);  // outward, along the photon's way out
  float ior = band_ior(object, photon_band);
  vec3 out_direction = refract(direction, -n, ior);
  if (dot(out_direction, out_direction) == 0.0) {
    ph.tir = true;
    return IMAGE_SPACE_DONE;
  }
  ph.power *= exp(-object.absorption_ior.rgb * back.y);
  if (params.fresnel != 0u) {
    ph.power *= 1.0 - reflectance(interface_reflection(object, dot(direction, n), dot(normalize(out_direction), n), ior, 1.0));
  }
  vec2 landing;
  if (lands_in_image_space(light, eye + direction * back.y, normalize(out_direction), landing)) land_on_map(ph, landing);
  return IMAGE_SPACE_DONE;
}

uint image_space_photon(inout Photon ph, LightData light, vec2 uv, vec3 eye, vec3 direction, ViewOrigin origin, inout ExactStart start) {
  if (light.face.y >= 0.0) return inside_photon(ph, light, uv, eye, direction);
  vec4 front = texture(front_tex, uv);
  if (front.y <= 0.0) return IMAGE_SPACE_DONE;
  ObjectData object = objects[uint(front.w)];
  float receiver = texture(receiver_depth, uv).r;
  float receiver_distance = receiver < 1.0 ? view_distance(origin, world_from_depth(light.inv_view_proj, uv, receiver)) : 1e30;
#ifdef CAUSTICA_RAY_QUERY
  // Chosen from the material: image space where it sees the exact path (image_space_is_exact, with
  // no other refractor between it and the receiver), exact paths for the rest; the exact tracer
  // meets the opaque occluders itself.
  if (DISTANCE_MODE == DISTANCE_MATERIAL &&
      material_traces_exactly(uint(front.w), eye + direction * front.y,
                              eye + direction * min(receiver_distance, front.y + REFRACTION_SEARCH_DISTANCE))) {
    return TRACE_FROM_LIGHT;
  }
#endif
  // An opaque surface nearer the light than the refractor takes the photon first: direct light, not
  // a caustic (the light-view refractor buffers are drawn without the opaque geometry).
  if (receiver_distance < front.y * (1.0 - 1e-4)) return IMAGE_SPACE_DONE;
  ph.hit = true;
  ph.entering = channel_mean(ph.power);
  vec3 p1 = eye + direction * front.y;
  if (thin_walled(object)) return thin_wall_photon(ph, light, uv, eye, direction, front, object, receiver, receiver_distance, p1);
  uint rng = photon_rng(uv);
  ph.random = transmission_roughness(object) > 0.0;
  // The interfaces at the entry's texels (the exit takes the same); the numbers drawn, the object's
  // (its means), as the exact tracer draws them.
  ObjectData entered = at_front_texel(object, uv);
  TwoInterfaces path =
      refract_two_interfaces(light.view_proj, origin, p1, buffer_normal(front_tex, uv, front), front.y, front.z, entered, photon_band, uv,
                             transmission_roughness(object), entry_choice_draws(object, band_ior(object, photon_band), params.fresnel != 0u), rng);
  // The hybrid re-traces a photon exactly, from the light, only where the estimate cannot be
  // trusted; one counter per reason (the first that applies).
  vec2 landing;
  bool lands = false;
#ifdef CAUSTICA_HYBRID
  if (!hybrid_trusts(path, light, uv, front, landing)) return TRACE_FROM_LIGHT;
  lands = true;
#else
  // A photon whose path the receiver depth hides lands where the light sees what hides it: the map
  // is the light's image, so that is the texel it belongs to, give or take the hidden stretch.
  lands = !path.tir && lands_in_image_space(light, path.exit_point, path.exit_direction, landing);
#endif
  ph.followed = path.followed;
  if (path.tir) {
    ph.tir = true;
    return IMAGE_SPACE_DONE;
  }
  vec3 inside_power = ph.power * exp(-object.absorption_ior.rgb * path.distance) * caustic_transmittance(entered);
#ifdef CAUSTICA_HYBRID
  uint next = hybrid_side_path(ph, start, path, p1, front, inside_power, rng);
#else
  uint next = IMAGE_SPACE_DONE;
#endif
  ph.power = inside_power;
  if (params.fresnel != 0u) ph.power *= (1.0 - path.reflectance_in) * path.transmit_out;
  if (lands) land_on_map(ph, landing);
  return next;
}

// The photon through the centre of `uv` on the light's image plane, standing for a square of side
// `texel` (in units of the image plane at distance 1): its power is the light's intensity times
// that square's solid angle, texel^2 cos^3 of its angle to the axis, times the spot cone. This is
// its image-space part; `next` says what exact tracing is left to do from `start`, which
// finish_photon (below) does for the whole workgroup at once.
Photon begin_photon(LightData light, vec2 uv, float texel, out uint next, out ExactStart start) {
  Photon ph;
  ph.hit = false;
  ph.tir = false;
  ph.landed = false;
  ph.entering = 0.0;
  ph.texel = ivec2(0);
  ph.landing = vec2(0.0);
  ph.random = false;
  ph.bounced = false;
  ph.followed = false;
  ph.side_landed = false;
  ph.side_texel = ivec2(0);
  ph.side_power = vec3(0.0);
  next = IMAGE_SPACE_DONE;
  // A directional light's photon starts on the plane through its position and travels along the
  // axis, carrying irradiance times its square (`texel` is then in world units); a spot's leaves
  // the light through the image plane at distance 1.
  bool directional = light_is_directional(light);
  vec2 plane = (uv * 2.0 - 1.0) * light.clip.z;
  float cos_axis = directional ? 1.0 : inversesqrt(1.0 + dot(plane, plane));
  vec3 axis = light.direction_cos.xyz;
  vec3 eye = directional ? world_from_depth(light.inv_view_proj, uv, 0.0) - axis * light.clip.x : light.position_type.xyz;
  vec3 direction = directional ? axis : normalize(world_from_depth(light.inv_view_proj, uv, 0.5) - eye);
  ViewOrigin origin = ViewOrigin(light.position_type.xyz, axis, directional);
  if (!directional) origin = perspective_origin(eye);
  float cone = spot_cone(light, direction);
  float emitted = light.radiant.a * texel * texel * cos_axis * cos_axis * cos_axis * cone;
  ph.power = photon_band == BAND_WHITE ? vec3(emitted) : emitted * vec3(equal(uvec3(0u, 1u, 2u), uvec3(photon_band)));
  // A light inside a solid refractor (a bulb in a glass globe): its photons start in the glass.
  start = ExactStart(eye, direction, int(light.face.y), 0u, photon_rng(uv));
  if (emitted <= 0.0) return ph;
#ifdef CAUSTICA_RAY_QUERY
  next = DISTANCE_MODE == DISTANCE_RAY_QUERY ? TRACE_FROM_LIGHT : image_space_photon(ph, light, uv, eye, direction, origin, start);
#else
  image_space_photon(ph, light, uv, eye, direction, origin, start);
#endif
  return ph;
}

#ifdef CAUSTICA_RAY_QUERY
// Exact tracing is tens of times the cost of image space, and it is needed by few photons, spread
// over the grid. Traced where each photon is, every SIMD group that holds one such photon waits for
// it (lavapipe runs 8 invocations in lockstep, a GPU 32 or 64), so the hybrid paid nearly the
// ray-query tracer's price. Instead, finish_photon queues a workgroup's exact paths in shared memory
// and its first invocations trace them side by side, one each; every invocation then takes its own
// result back. At most one path per invocation per call, so one round serves a workgroup of
// EXACT_JOBS invocations.
const uint EXACT_JOBS = 64u;
struct ExactJob {
  vec3 origin;  // in: where the path starts
  int inside;
  vec3 direction;
  uint interfaces;
  vec3 power;  // in: as it starts; out: as it lands
  uint rng;
  vec2 landing;  // out, in caustic-map texels
  float entering;
  uint flags;  // in and out: EXACT_JOB_HIT, EXACT_JOB_RANDOM; out: EXACT_JOB_LANDED, EXACT_JOB_BOUNCED
};
const uint EXACT_JOB_HIT = 1u, EXACT_JOB_RANDOM = 2u, EXACT_JOB_LANDED = 4u, EXACT_JOB_BOUNCED = 8u;
// Two queues, used by alternate calls, so that a call's queue is not refilled before every invocation
// has taken its result from it, and its count is reset while the other queue fills (finish_photon).
shared ExactJob exact_jobs[2][EXACT_JOBS];
shared uint exact_job_count[2];
uint exact_job_parity = 0u;
#endif

// Zeroes the queue's counts, and with them what else the kernel zeroed in shared memory before it,
// for the whole workgroup (a barrier where the kernel traces exact paths; nothing otherwise).
void begin_exact_jobs() {
#ifdef CAUSTICA_RAY_QUERY
  if (gl_LocalInvocationIndex < 2u) exact_job_count[gl_LocalInvocationIndex] = 0u;
  barrier();
#endif
}

// Does the exact work begin_photon left (`next`, from `start`) and merges what it found into ph:
// the photon's whole path traced from the light, or the side path split off it. Every invocation of
// the workgroup must call it together (it holds barriers), each with at most one photon, or
// IMAGE_SPACE_DONE.
void finish_photon(inout Photon ph, uint next, ExactStart start, LightData light) {
#ifdef CAUSTICA_RAY_QUERY
  uint parity = exact_job_parity;
  exact_job_parity ^= 1u;
  uint slot = EXACT_JOBS;
  if (next != IMAGE_SPACE_DONE) {
    slot = atomicAdd(exact_job_count[parity], 1u);
    vec3 power = ph.power;
    uint flags = ph.random ? EXACT_JOB_RANDOM : 0u;
    float entering = ph.entering;
    if (next == TRACE_FROM_LIGHT) {
      entering = 0.0;
    } else {  // the side path, from where it splits off: the photon is counted as entering already
      exact_count(EXACT_TRACED);
      exact_count(RETRACED_REFLECTION);
      power = ph.side_power;
      flags |= EXACT_JOB_HIT;
    }
    exact_jobs[parity][slot] =
        ExactJob(start.origin, start.inside, start.direction, start.interfaces, power, start.rng, vec2(0.0), entering, flags);
  }
  barrier();
  // The other queue's call is over: every invocation has taken its result from it.
  if (gl_LocalInvocationIndex == 0u) exact_job_count[parity ^ 1u] = 0u;
  if (gl_LocalInvocationIndex < exact_job_count[parity]) {
    ExactJob job = exact_jobs[parity][gl_LocalInvocationIndex];
    Photon traced;
    traced.power = job.power;
    traced.entering = job.entering;
    traced.hit = (job.flags & EXACT_JOB_HIT) != 0u;
    traced.random = (job.flags & EXACT_JOB_RANDOM) != 0u;
    traced.bounced = false;
    traced.landed = false;
    traced.landing = vec2(0.0);
    trace_photon_exact(traced, light, ExactStart(job.origin, job.direction, job.inside, job.interfaces, job.rng));
    job.power = traced.power;
    job.entering = traced.entering;
    job.landing = traced.landing;
    job.flags = (traced.hit ? EXACT_JOB_HIT : 0u) | (traced.random ? EXACT_JOB_RANDOM : 0u) | (traced.landed ? EXACT_JOB_LANDED : 0u) |
                (traced.bounced ? EXACT_JOB_BOUNCED : 0u);
    exact_jobs[parity][gl_LocalInvocationIndex] = job;
  }
  barrier();
  if (slot == EXACT_JOBS) return;
  ExactJob done = exact_jobs[parity][slot];
  bool landed = (done.flags & EXACT_JOB_LANDED) != 0u;
  ivec2 texel = clamp(ivec2(done.landing), ivec2(0), imageSize(caustic_map).xy - 1);
  if (next == TRACE_FROM_LIGHT) {
    ph.power = done.power;
    ph.entering = done.entering;
    ph.hit = (done.flags & EXACT_JOB_HIT) != 0u;
    ph.random = (done.flags & EXACT_JOB_RANDOM) != 0u;
    ph.bounced = (done.flags & EXACT_JOB_BOUNCED) != 0u;
    ph.landed = landed;
    ph.landing = done.landing;
    ph.texel = texel;
  } else {
    ph.side_landed = landed;
    ph.side_texel = texel;
    ph.side_power = done.power;
  }
#endif
}

// The caustic map has a layer per colour channel (image atomics are single-channel). A colour
// band's photon has one channel: the others' atomics are skipped.
void splat(ivec2 texel, vec3 power) {
  for (int c = 0; c < 3; ++c) {
    if (power[c] != 0.0) imageAtomicAdd(caustic_map, ivec3(texel, c), power[c]);
  }
}

#endif
