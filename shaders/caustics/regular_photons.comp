#version 460
// Regular caustic map: one photon per texel of an N x N grid over the light's image plane, each
// traced by begin_photon() and finish_photon() (caustics/photon.glsl) and splatted into the caustic-map texel it lands in.
// PHOTON_BAND_LOOP (a scene with a dispersive refractor, in image space): each invocation traces
// its photon once per colour band, in one dispatch. A photon that meets no refractor in the first
// band meets none in the others (where it enters does not depend on the band), so the light's view
// outside the refractors and each workgroup's bookkeeping are paid once, not three times. A
// variant of its own, because the loop's mere presence slowed white photons by about 6% (and, around
// the exact tracer, by an eighth), measured on lavapipe; with exact paths the pass dispatches once
// per band.
#extension GL_GOOGLE_include_directive : require
#include "scene/scene.glsl"
SCENE_FRAME
SCENE_OBJECTS
layout(set = 0, binding = 3) uniform sampler2D front_tex;
layout(set = 0, binding = 4) uniform sampler2D back_tex;
layout(set = 0, binding = 5) uniform sampler2D receiver_depth;
layout(set = 0, binding = 6, r32f) uniform image2DArray caustic_map;  // a layer per colour channel
layout(set = 0, binding = 7, std430) buffer CounterBlock { uint counters[]; };
layout(set = 0, binding = 8, std430) buffer SumBlock { float sums[]; };  // the same buffer, float slots

layout(push_constant) uniform Params {
  uint distance_mode;
  uint search;  // refraction.glsl: search_steps() and search_tir_bounces()
  float search_distance;
  uint light;
  uint grid;
  uint fresnel;
  // Counter slots: processed, splatted, dropped_miss, dropped_tir, processed.level0 (counts),
  // then flux, flux_entering, flux_dropped (sums).
  uint counter_slot[8];
  // Exact paths (caustics/photon.glsl; passes/refraction.h ExactPathPush).
  uint exact_max_interfaces;
  uint exact_seed;
  uint exact_counters;
  float exact_epsilon;
  uint hybrid_packed;  // hybrid_tolerance and hybrid_reflections as two halves (packHalf2x16)
  uint band;  // caustics/photon.glsl: BAND_WHITE or the colour band traced (unused with PHOTON_BAND_LOOP)
  vec2 jitter;  // where in its grid cell each photon starts: (0.5, 0.5) the centre
  // This frame's slice of the grid: the cells slice_offset + slice_side * gl_GlobalInvocationID.xy,
  // each photon carrying the power of slice_side^2 (passes/caustic_map.cpp).
  uvec2 slice_offset;
  uint slice_side;
} params;

#include "caustics/photon.glsl"
#include "caustics/group_totals.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

// Traces the grid's photon `id` in photon_band when `tracing`, else counts it as missing again (it
// missed in the band before), and splats it. Every invocation calls it together (finish_photon).
// True when the photon met a refractor.
bool trace_and_splat(uvec2 id, bool in_grid, bool tracing, LightData light) {
  uint next = IMAGE_SPACE_DONE;
  ExactStart start;
  Photon ph;
  if (tracing) ph = begin_photon(light, (vec2(id) + params.jitter) / float(params.grid), 2.0 * light.clip.z / float(params.grid), next, start);
  finish_photon(ph, next, start, light);
  if (!in_grid) return false;
  count(0);
  count(4);
  if (!tracing || !ph.hit) {
    count(2);  // misses every refractor: direct light, not a caustic
    return false;
  }
  const float slice_weight = float(params.slice_side * params.slice_side);
  ph.power *= slice_weight;
  ph.entering *= slice_weight;
  ph.side_power *= slice_weight;
  add_sum(1, ph.entering);
  if (ph.tir) {
    count(3);
    add_sum(2, channel_mean(ph.power));
  } else if (!ph.landed) {
    count(2);
    add_sum(2, channel_mean(ph.power));
  } else {
    splat(ph.texel, ph.power);
    count(1);
    add_sum(0, channel_mean(ph.power));
  }
  if (ph.side_landed) {  // the hybrid's Fresnel reflection, split off the photon's path (photon.glsl)
    splat(ph.side_texel, ph.side_power);
    count(1);
    add_sum(0, channel_mean(ph.side_power));
  }
  return true;
}

void main() {
  begin_exact_jobs();
  begin_group_totals();
  uvec2 id = gl_GlobalInvocationID.xy * params.slice_side + params.slice_offset;
  bool in_grid = all(lessThan(id, uvec2(params.grid)));
  LightData light = frame.caustic_lights[params.light];
#ifdef PHOTON_BAND_LOOP
  bool met_refractor = true;
  for (uint band = 0u; band < 3u; ++band) {
    photon_band = band;
    met_refractor = trace_and_splat(id, in_grid, in_grid && met_refractor, light);
  }
#else
  photon_band = params.band;
  trace_and_splat(id, in_grid, in_grid, light);
#endif
  end_group_totals(5u, 5u, 3u);
}
