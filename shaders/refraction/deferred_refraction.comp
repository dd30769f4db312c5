#version 460
// Deferred refraction over the refractor buffers; each pixel is shaded once, for the nearest
// refractor surface only (its tint and transmission per pixel with REFRACTOR_TINT). Dispatched over
// `rect` (the refractors' screen rectangle) alone, after the pass has copied the background over the
// whole target (common/copy.comp): pixels that cannot show a refractor cost a copy, not this kernel.
// A compute shader because llvmpipe (lavapipe) compiles a fragment shader twice, for whole tiles and
// for tiles on a triangle's edge (10.5 s of the ray-query variant's cold compile); it runs slower
// there than the fragment version did (docs/testing.md). OUT_FORMAT is the target's storage format
// qualifier, set by the pass.
// Compiled with CAUSTICA_RAY_QUERY when the pass's `distance` is ray_query (every pixel traced
// exactly), material, or hybrid (the image-space search, traced exactly where it cannot be
// trusted; CAUSTICA_HYBRID too).
#extension GL_GOOGLE_include_directive : require
#ifndef OUT_FORMAT
#define OUT_FORMAT rgba16f
#endif
#include "scene/scene.glsl"
SCENE_FRAME
SCENE_OBJECTS
layout(set = 0, binding = 3) uniform sampler2D background_tex;
layout(set = 0, binding = 4) uniform sampler2D depth_tex;
layout(set = 0, binding = 5) uniform sampler2D front_tex;
layout(set = 0, binding = 6) uniform sampler2D back_tex;
layout(set = 0, binding = 7, std430) buffer CounterBlock { uint counters[]; };
layout(set = 0, binding = 8, OUT_FORMAT) uniform writeonly image2D out_color;
layout(local_size_x = 8, local_size_y = 8) in;

// passes/refraction.cpp, DeferredRefractionPush: RefractionPush, then the rectangle.
layout(push_constant) uniform Params {
  uint distance_mode;
  uint search;  // refraction.glsl: search_steps() and search_tir_bounces()
  float search_distance;
  uint tir_counter;
  uint exact_max_interfaces;
  float exact_epsilon;
  float hybrid_tolerance;
  uint exact_counters;
  ivec4 rect;  // x0, y0, x1, y1: the dispatch covers [x0, x1) x [y0, y1) from (x0, y0)
} params;

#define REFRACTION_FRONT_TEX
#include "refraction/refraction.glsl"
#ifdef CAUSTICA_HYBRID
#include "refraction/hybrid.glsl"
#endif

#ifdef CAUSTICA_HYBRID
// The hybrid's image-space answer, or the reason it is not trusted: untrusted_exit's, or, for the
// exit ray (traced exactly), CAMERA_REFRACTOR_AHEAD when it meets a refractor (its own again, or
// another), which one image-space layer cannot follow; CAMERA_OFF_SCREEN when the camera does not
// see what it meets (or it meets nothing): such rays leave near the outline, where the estimate is
// least sure, and re-tracing them measured better than shading what they meet; and EXIT_MULTIPLE
// when it passes another refractor's bounds (measured better than trusting the estimated ray's near
// misses). A trusted exit ray sees the lit image where the camera sees its hit. An untrusted pixel is traced whole: tracing
// only its exit ray from the estimated exit point, which need not lie on the surface, was measured
// to be far worse (docs/exact_paths.md).
uint hybrid_radiance(vec3 p1, vec4 front, vec2 uv, out vec3 radiance) {
  ObjectData object = at_front_texel(objects[uint(front.w)], uv);
  vec3 eye = frame.camera_position.xyz;
  vec3 n1 = unpack_normal(front.x);
  if (thin_walled(object)) {  // image space sees a thin wall's path exactly
    radiance = through_thin_wall(object, p1, n1, front, uv);
    return EXIT_TRUSTED;
  }
  // A dispersive refractor: each colour band's path, each trusted, gives its own channel; a rough
  // one: the mean of its samples' paths, each trusted.
  uint first = disperses(object) ? 0u : BAND_WHITE, last = disperses(object) ? 2u : BAND_WHITE;
  uint rng = pixel_rng(uv), samples = camera_samples(object);
  radiance = vec3(0.0);
  for (uint s = 0u; s < samples; ++s) {
    for (uint band = first; band <= last; ++band) {
      TwoInterfaces path = refract_two_interfaces(frame.view_proj, perspective_origin(eye), p1, n1, front.y, front.z, object, band, uv,
                                                  transmission_roughness(object), 0u, rng);
      bool hit;
      vec3 behind;
      uint reason = hybrid_exit_ray(path, front, texture(back_tex, uv), params.hybrid_tolerance, hit, behind);
      if (reason != EXIT_TRUSTED) return reason == EXIT_REFRACTOR_AHEAD ? CAMERA_REFRACTOR_AHEAD : reason;
      vec2 behind_uv;
      if (!hit || !seen_on_screen(behind, behind_uv)) return CAMERA_OFF_SCREEN;
      // Another refractor's bounds on the way: the estimated ray may just miss what the true one meets.
      if (crosses_other_refractor(path.exit_point, behind, uint(front.w))) return EXIT_MULTIPLE;
      vec3 seen = through_refractor(path, object, p1, dot(p1 - eye, n1) > 0.0 ? -n1 : n1, texture(background_tex, behind_uv).rgb);
      if (band == BAND_WHITE) radiance += seen;
      else radiance[band] += seen[band];
    }
  }
  radiance /= float(samples);
  return EXIT_TRUSTED;
}
#endif

vec3 shade(ivec2 pixel, vec2 uv, vec3 background) {
  vec4 front = texelFetch(front_tex, pixel, 0);
  if (front.y <= 0.0) return background;
  vec3 eye = frame.camera_position.xyz;
  vec3 ray = normalize(world_from_depth(frame.inv_view_proj, uv, 0.5) - eye);
  vec3 p1 = eye + ray * front.y;
  float opaque_depth = texture(depth_tex, uv).r;
  vec2 ignored_uv;
  float front_depth;
  project_to_screen(p1, ignored_uv, front_depth);
  if (opaque_depth < front_depth) return background;  // an opaque surface in front of the refractor
#ifdef CAUSTICA_RAY_QUERY
  bool exact_material =
      DISTANCE_MODE == DISTANCE_MATERIAL &&
      material_traces_exactly(uint(front.w), p1, opaque_depth < 1.0 ? world_from_depth(frame.inv_view_proj, uv, opaque_depth) : p1 + ray * params.search_distance);
  if (DISTANCE_MODE == DISTANCE_RAY_QUERY || DISTANCE_MODE == DISTANCE_HYBRID || exact_material) {
    vec3 radiance;
    uint reason = EXIT_TRUSTED;
#ifdef CAUSTICA_HYBRID
    reason = hybrid_radiance(p1, front, uv, radiance);
    if (reason != EXIT_TRUSTED)
#endif
    {
      camera_count(CAMERA_EXACT);
      if (reason != EXIT_TRUSTED) camera_count(reason);
      radiance = trace_camera_exact(eye, ray, uv);
    }
    return radiance;
  }
#endif
  return refracted_radiance(p1, unpack_normal(front.x), front.y, front.z, uint(front.w), at_front_texel(objects[uint(front.w)], uv), uv);
}

void main() {
  ivec2 pixel = params.rect.xy + ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, params.rect.zw))) return;
  vec2 uv = (vec2(pixel) + 0.5) * frame.sizes.zw;
  imageStore(out_color, pixel, vec4(shade(pixel, uv, texture(background_tex, uv).rgb), 1.0));
}
