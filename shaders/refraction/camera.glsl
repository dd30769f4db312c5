#ifndef CAUSTICA_REFRACTION_CAMERA_GLSL
#define CAUSTICA_REFRACTION_CAMERA_GLSL
// The camera passes' part of refraction/refraction.glsl, which includes it unless
// REFRACTION_NO_CAMERA is defined: what a pixel that sees a refractor shows, through image-space
// paths or (with CAUSTICA_RAY_QUERY) exact ones. Needs what refraction.glsl says a camera pass
// declares: background_tex, depth_tex and a `counters` buffer with params.tir_counter.

#ifdef CAUSTICA_RAY_QUERY
#include "refraction/exact_path.glsl"
#endif

// scene/lighting.frag's model at p (ambient sky and every light); with `shadowed`, and ray
// queries, an exact shadow ray for every light, as the ray-traced reference has.
vec3 lambert(vec3 p, vec3 n, vec3 albedo, bool shadowed) {
  vec3 irradiance = vec3(0.0);
  for (uint i = 0u; i < frame.light_count; ++i) {
    LightData light = frame.lights[i];
    float d2;
    vec3 l = toward_light(light, p, d2);
    float cone = spot_cone(light, -l);
#ifdef CAUSTICA_RAY_QUERY
    float reach = light_is_directional(light) ? 1e30 : sqrt(d2) - params.exact_epsilon;
    if (shadowed && cone > 0.0 && occluded(p + n * params.exact_epsilon, l, reach)) cone = 0.0;
#endif
    irradiance += light.radiant.rgb * max(dot(n, l), 0.0) / d2 * cone;
  }
  return albedo * (frame.sky_ambient.a * frame.sky_ambient.rgb + irradiance * (1.0 / 3.14159265358979));
}

// What a refractor's surface at p (normal n towards the viewer) sends to the viewer, given the
// radiance `through` that reaches it from behind the surface (exit Fresnel and absorption applied):
// the entry's Fresnel reflection of the sky; of the rest, the share `transmission` passes tinted,
// the remainder is reflected diffusely with the tint as albedo (lit without shadows in image space).
vec3 refractor_surface(ObjectData object, vec3 reflectance_in, vec3 p, vec3 n, vec3 through) {
  float transmission = object.tint_transmission.a;
  vec3 tint = object.tint_transmission.rgb;
  vec3 diffuse = transmission < 1.0 ? (1.0 - transmission) * lambert(p, n, tint, false) : vec3(0.0);
  return reflectance_in * frame.sky_ambient.rgb + (1.0 - reflectance_in) * (transmission * tint * through + diffuse);
}

// The background seen along an exit ray from the camera: the lit image where the ray meets the
// background's depth, the sky where it leaves the screen.
vec3 background_along(vec3 origin, vec3 direction) {
  vec2 uv;
  return march_depth(depth_tex, frame.view_proj, origin, direction, uv) == MARCH_HIT ? texture(background_tex, uv).rgb : frame.sky_ambient.rgb;
}

// Radiance through a refractor along `path` from its front surface point p1 (normal n1): the rest
// of the entry's light is absorbed inside and weighted by the exit's transmittance before it sees
// `behind`.
vec3 through_refractor(TwoInterfaces path, ObjectData object, vec3 p1, vec3 n1, vec3 behind) {
  vec3 absorbed = exp(-object.absorption_ior.rgb * path.distance);
  return refractor_surface(object, path.reflectance_in, p1, n1, path.transmit_out * absorbed * behind);
}

// A rough refractor's pixel averages this many paths, each through its own microfacets (the
// pixel's random numbers: pixel_rng); a smooth one's takes one.
const uint CAMERA_ROUGH_SAMPLES = 8u;
uint camera_samples(ObjectData object) { return transmission_roughness(object) > 0.0 ? CAMERA_ROUGH_SAMPLES : 1u; }
uint pixel_rng(vec2 pixel_uv) { return pcg_hash(floatBitsToUint(pixel_uv.x) ^ pcg_hash(floatBitsToUint(pixel_uv.y))); }

// Radiance seen through a thin-walled object whose near wall is at p1 (refractor-buffer texel
// `front`): the pixel's own background, unbent, through its far wall too when it has one; a rough
// wall scatters the ray, which then sees the background where it meets it.
vec3 through_thin_wall(ObjectData object, vec3 p1, vec3 n1, vec4 front, vec2 pixel_uv) {
  vec3 eye = frame.camera_position.xyz;
  vec3 v = normalize(p1 - eye);
  float ior = object.absorption_ior.a;
  float roughness = transmission_roughness(object);
  vec4 back = texture(back_tex, pixel_uv);
  bool far_wall = thin_far_wall(front, back);
  vec3 p2 = eye + v * back.y, n2 = unpack_normal(back.x);
  if (dot(v, n2) > 0.0) n2 = -n2;
  if (dot(v, n1) > 0.0) n1 = -n1;
  uint rng = pixel_rng(pixel_uv), samples = camera_samples(object);
  vec3 radiance = vec3(0.0);
  for (uint s = 0u; s < samples; ++s) {
    vec3 m1 = microfacet_normal(n1, v, roughness, rng);
    vec3 d = through_thin(v, m1, n1);
    vec3 reflect_far = vec3(0.0);
    if (far_wall) {
      vec3 m2 = microfacet_normal(n2, d, roughness, rng);
      reflect_far = reflectance(interface_reflection(object, -dot(d, m2), -dot(d, n2), 1.0, ior));
      d = through_thin(d, m2, n2);
    }
    vec3 through = roughness > 0.0 ? background_along(far_wall ? p2 : p1, d) : texture(background_tex, pixel_uv).rgb;
    if (far_wall) through = refractor_surface(objects[uint(front.w)], reflect_far, p2, n2, through);  // the far wall: means
    radiance +=
        refractor_surface(object, reflectance(interface_reflection(object, -dot(v, m1), coat_cos_outside(object, v, n1), 1.0, ior)), p1, n1, through);
  }
  return radiance / float(samples);
}

// Radiance seen through a refractor whose front surface is at p1 with outward normal n1 (`object`:
// objects[object_index] with its tint and transmission at p1); a dispersive one is refracted once
// per colour band, each band giving its own channel.
vec3 refracted_radiance(vec3 p1, vec3 n1, float front_distance, float dn, uint object_index, ObjectData object, vec2 pixel_uv) {
  if (thin_walled(object)) return through_thin_wall(object, p1, n1, vec4(0.0, front_distance, 0.0, float(object_index)), pixel_uv);
  vec3 facing = dot(normalize(p1 - frame.camera_position.xyz), n1) > 0.0 ? -n1 : n1;
  vec3 radiance = vec3(0.0);
  uint first = disperses(object) ? 0u : BAND_WHITE, last = disperses(object) ? 2u : BAND_WHITE;
  uint rng = pixel_rng(pixel_uv), samples = camera_samples(object);
  for (uint s = 0u; s < samples; ++s) {
    for (uint band = first; band <= last; ++band) {
      TwoInterfaces path = refract_two_interfaces(frame.view_proj, perspective_origin(frame.camera_position.xyz), p1, n1, front_distance, dn,
                                                  object, band, pixel_uv, transmission_roughness(object), 0u, rng);
      // Total internal reflection: the ray reflects and, in this two-interface model, leaves along
      // the reflected direction with all its energy (no black pixels, no NaN).
      if (path.tir) atomicAdd(counters[params.tir_counter], 1u);
      vec3 seen = through_refractor(path, object, p1, facing, background_along(path.exit_point, path.exit_direction));
      if (band == BAND_WHITE) radiance += seen;
      else radiance[band] += seen[band];
    }
  }
  return radiance / float(samples);
}

#ifdef CAUSTICA_RAY_QUERY
// Exact camera paths (distance ray_query, and hybrid where the image-space exit is not trusted).
// Needs params.exact_max_interfaces, exact_epsilon and exact_counters: consecutive counter slots
// for the pixels traced exactly, the hybrid's reasons (EXIT_TIR .. EXIT_MULTIPLE, then
// CAMERA_OFF_SCREEN, CAMERA_REFRACTOR_AHEAD) and the rays trapped inside after exact_max_interfaces
// interfaces.
const uint CAMERA_EXACT = 0u, CAMERA_OFF_SCREEN = 5u, CAMERA_REFRACTOR_AHEAD = 6u, CAMERA_TRAPPED = 7u;
void camera_count(uint k) { atomicAdd(counters[params.exact_counters + k], 1u); }

// Whether the camera sees the very point p (at `uv`): on screen and not hidden behind opaque geometry.
bool seen_on_screen(vec3 p, out vec2 uv) {
  float depth;
  if (!project_to_screen(p, uv, depth)) return false;
  vec3 seen = world_from_depth(frame.inv_view_proj, uv, texture(depth_tex, uv).r);
  return distance(seen, p) <= 0.01 * distance(p, frame.camera_position.xyz) + 4.0 * params.exact_epsilon;
}

// Direct light at an opaque point an exact path reached: the lit background where the camera sees
// that very point (it carries the frame's shadow map and caustics); elsewhere scene/lighting.frag's
// model with an exact shadow ray for the first spot light, as the ray-traced reference does, and no
// caustic.
vec3 shade_exit_hit(vec3 p, vec3 n, vec3 albedo) {
  vec2 uv;
  return seen_on_screen(p, uv) ? texture(background_tex, uv).rgb : lambert(p, n, albedo, true);
}

// Radiance along a camera ray traced through every interface (refraction/exact_path.glsl, Fresnel
// weighted), as the ray-traced reference does: at a refractor's entry the Fresnel reflection sees
// the sky and the rest refracts in; inside, absorption and total internal reflection; at the exit
// the Fresnel transmittance. A ray still inside after exact_max_interfaces interfaces (or lost in an
// open mesh) brings nothing more. In colour band `band` (refracting with its index); a white ray that
// meets a dispersive refractor stops and sets `dispersed` (trace_camera_exact below then traces each
// band). A rough refractor's surfaces scatter the ray about microfacets drawn from `rng`, and set
// `rough`.
vec3 trace_camera_band(vec3 origin, vec3 direction, uint band, inout uint rng, inout bool dispersed, inout bool rough) {
  ExactPath path = ExactPath(origin, direction, -1, 0u, rng, vec3(1.0));
  vec3 radiance = vec3(0.0);
  for (;;) {
    vec3 before = path.throughput;
    PathEvent e = exact_path_step(path, band, true, false);
    rng = path.rng;
    if (e.kind == PATH_ESCAPED) return path.inside < 0 ? radiance + path.throughput * frame.sky_ambient.rgb : radiance;
    if (e.kind == PATH_TRAPPED) {
      camera_count(CAMERA_TRAPPED);
      return radiance;
    }
    if (e.kind == PATH_DISPERSED) {
      dispersed = true;
      return vec3(0.0);
    }
    // What the path sees diffusely here, shaded once below: the opaque surface that ends it, or a
    // refractor's diffusely reflected share at its entry (of what the Fresnel reflection, which sees
    // the sky, left, the share `transmission` passes tinted). One call site of shade_exit_hit, whose
    // exact shadow ray is a ray query: lavapipe inlines every call, and each copy of a ray query
    // lengthens its compile by seconds.
    vec3 shade_weight = vec3(0.0), shade_albedo = vec3(0.0);
    bool ends = e.kind == PATH_OPAQUE;
    if (ends) {
      shade_weight = path.throughput;
      shade_albedo = objects[e.object].albedo_refractor.rgb;
    } else {
      rough = rough || e.roughness > 0.0;
      if (e.entering && !e.reflected) {  // (an entry reflects only totally, into a refractor of index below 1: followed)
        radiance += before * e.reflectance * frame.sky_ambient.rgb;
        shade_weight = before * (1.0 - e.reflectance) * (1.0 - e.tint_transmission.a);
        shade_albedo = e.tint_transmission.rgb;
      }
    }
    if (any(greaterThan(shade_weight, vec3(0.0)))) radiance += shade_weight * shade_exit_hit(e.position, e.normal, shade_albedo);
    if (ends) return radiance;
  }
}

// The pixel at `pixel_uv` seen along a camera ray: one path, or, where it met a rough refractor,
// the mean of CAMERA_ROUGH_SAMPLES.
vec3 trace_camera_exact(vec3 origin, vec3 direction, vec2 pixel_uv) {
  uint rng = pixel_rng(pixel_uv);
  bool rough = false;
  vec3 sum = vec3(0.0);
  for (uint s = 0u; s < CAMERA_ROUGH_SAMPLES; ++s) {
    // The white ray, then, where it met a dispersive refractor, each band's: one call site of
    // trace_camera_band, for the reason given at shade_exit_hit's.
    bool dispersed = false;
    vec3 radiance = vec3(0.0);
    for (uint band = BAND_WHITE;;) {
      vec3 seen = trace_camera_band(origin, direction, band, rng, dispersed, rough);
      if (band == BAND_WHITE) {
        if (!dispersed) {
          radiance = seen;
          break;
        }
        band = 0u;
      } else {
        radiance[band] = seen[band];
        if (++band == 3u) break;
      }
    }
    sum += radiance;
    if (!rough) return sum;
  }
  return sum / float(CAMERA_ROUGH_SAMPLES);
}
#endif

#endif
