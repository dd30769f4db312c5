#version 460
// The regular caustic map's photons (the built-in caustic_map, shaders/caustics/regular_photons.comp)
// as a user pass: one photon per texel of a grid x grid grid over the light's image plane, started
// at its cell's centre, traced through the light-view refractor buffers by the shader library's
// begin_photon (caustics/photon.glsl) and splatted into the caustic map, which the graph's
// caustic_clear pass has zeroed. Its counters are the built-in's, in the graph's order: the counts
// processed, splatted, dropped_miss, dropped_tir, processed.level0, then the sums flux,
// flux_entering, flux_dropped (added once per workgroup by caustics/group_totals.glsl).
#extension GL_GOOGLE_include_directive : require
#include "scene/scene.glsl"
SCENE_FRAME
SCENE_OBJECTS
// The ports, at the bindings the library's helpers expect of the built-in pass.
layout(set = 0, binding = 3) uniform sampler2D front_tex;
layout(set = 0, binding = 4) uniform sampler2D back_tex;
layout(set = 0, binding = 5) uniform sampler2D receiver_depth;
layout(set = 0, binding = 6, r32f) uniform image2DArray caustic_map;  // a layer per colour channel
// The pass's counters: counts and sums in one buffer, slot k the graph's k-th counter.
layout(set = 0, binding = 7, std430) buffer CounterBlock { uint counters[]; };
layout(set = 0, binding = 8, std430) buffer SumBlock { float sums[]; };

layout(push_constant) uniform Params {
  uint distance;  // the index of its choice: dv, dv_dn
  uint search_steps;
  float search_distance;
  uint light;
  uint grid;
  uint fresnel;
  uint exact_seed;
  uint dispersive;
} params;

// What the library reads of a built-in pass's push constants, from this pass's parameters: the
// choices dv and dv_dn are refraction.glsl's DISTANCE_DV and DISTANCE_DV_DN; the march onto the
// receivers takes the search's steps and reach (no total internal reflection is followed in these
// modes, so the packed word's bounces are 0).
#define CAUSTICA_DISTANCE_MODE params.distance
#define REFRACTION_SEARCH params.search_steps
#define REFRACTION_SEARCH_DISTANCE params.search_distance
#define REFRACTOR_TINT 1  // the front_tint_tex port: the refractors' per-texel tint
#define GROUP_COUNTER_SLOT(k) (k)
#include "caustics/photon.glsl"
#include "caustics/group_totals.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

// Traces photon `id` in photon_band when `tracing`, else counts it as missing again (it missed in
// the band before), and splats it. True when the photon met a refractor.
bool trace_and_splat(uvec2 id, bool in_grid, bool tracing, LightData light) {
  uint next;
  ExactStart start;
  Photon ph;
  if (tracing) ph = begin_photon(light, (vec2(id) + 0.5) / float(params.grid), 2.0 * light.clip.z / float(params.grid), next, start);
  if (!in_grid) return false;
  count(0);
  count(4);
  if (!tracing || !ph.hit) {
    count(2);  // misses every refractor: direct light, not a caustic
    return false;
  }
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
  return true;
}

void main() {
  begin_group_totals();
  uvec2 id = gl_GlobalInvocationID.xy;
  bool in_grid = all(lessThan(id, uvec2(params.grid)));
  LightData light = frame.caustic_lights[params.light];
  if (params.dispersive != 0u) {
    // Each photon once per colour band; one that meets no refractor in the first band meets none
    // in the others.
    bool met_refractor = true;
    for (uint band = 0u; band < 3u; ++band) {
      photon_band = band;
      met_refractor = trace_and_splat(id, in_grid, in_grid && met_refractor, light);
    }
  } else {
    photon_band = BAND_WHITE;
    trace_and_splat(id, in_grid, in_grid, light);
  }
  end_group_totals(5u, 5u, 3u);
}
