#version 460
// The regular caustic map's photons traced exactly (the built-in caustic_map with distance
// ray_query, caustics_raytraced.json) as a user pass: one photon per texel of a grid x grid grid over
// the light's image plane, started at its cell's centre and traced through the scene (ray queries
// or the compute tracer, as the plan has it) by the shader library's exact tracer (caustics/photon.glsl with
// CAUSTICA_RAY_QUERY: every interface, Fresnel choices, total internal reflection, absorption, MASK
// materials' coverage from the scene's textures), then splatted into the caustic map, which the
// graph's caustic_clear pass has zeroed. Its counters are the built-in's, in the graph's order: the
// eight of example (a) (caustic_map_user.comp), then the sixteen exact-path ones from slot 8.
#extension GL_GOOGLE_include_directive : require
#include "scene/scene.glsl"
SCENE_FRAME
SCENE_OBJECTS
// The library's image-space part reads these; an exact photon does not, but the shader declares them.
layout(set = 0, binding = 3) uniform sampler2D front_tex;
layout(set = 0, binding = 4) uniform sampler2D back_tex;
layout(set = 0, binding = 5) uniform sampler2D receiver_depth;
layout(set = 0, binding = 6, r32f) uniform image2DArray caustic_map;  // a layer per colour channel
layout(set = 0, binding = 7, std430) buffer CounterBlock { uint counters[]; };
layout(set = 0, binding = 8, std430) buffer SumBlock { float sums[]; };

layout(push_constant) uniform Params {
  uint light;
  uint grid;
  uint fresnel;
  uint exact_seed;
  uint exact_max_interfaces;
  float exact_epsilon;
  uint dispersive;
} params;

// Every photon exact from the light (the scene's structure and textures, bindings 14 and 15 and set
// 1, come with scene/trace.glsl, which photon.glsl includes, for either tracer); the image-space
// search is never run, so its steps and reach are nothing.
#define CAUSTICA_RAY_QUERY 1
#define CAUSTICA_DISTANCE_MODE DISTANCE_RAY_QUERY
#define REFRACTION_SEARCH 0u
#define REFRACTION_SEARCH_DISTANCE 0.0
#define GROUP_COUNTER_SLOT(k) (k)
#define EXACT_COUNTER_SLOT(k) (8u + (k))
#include "caustics/photon.glsl"
#include "caustics/group_totals.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

// Traces photon `id` in photon_band and splats it. Every invocation calls it together
// (finish_photon holds the workgroup's barriers).
void trace_and_splat(uvec2 id, bool in_grid, LightData light) {
  uint next = IMAGE_SPACE_DONE;
  ExactStart start;
  Photon ph;
  if (in_grid) ph = begin_photon(light, (vec2(id) + 0.5) / float(params.grid), 2.0 * light.clip.z / float(params.grid), next, start);
  finish_photon(ph, next, start, light);
  if (!in_grid) return;
  count(0);
  count(4);
  if (!ph.hit) {
    count(2);  // misses every refractor: direct light, not a caustic
    return;
  }
  add_sum(1, ph.entering);
  if (!ph.landed) {
    count(2);
    add_sum(2, channel_mean(ph.power));
  } else {
    splat(ph.texel, ph.power);
    count(1);
    add_sum(0, channel_mean(ph.power));
  }
}

void main() {
  begin_exact_jobs();
  begin_group_totals();
  uvec2 id = gl_GlobalInvocationID.xy;
  bool in_grid = all(lessThan(id, uvec2(params.grid)));
  LightData light = frame.caustic_lights[params.light];
  // With a dispersive refractor each photon once per colour band, as the built-in's three
  // dispatches trace it. One call site in a loop the compiler cannot unroll: each inlined copy of
  // the exact tracer lengthens lavapipe's compile by seconds.
  uint bands = params.dispersive != 0u ? 3u : 1u;
  for (uint band = 0u; band < bands; ++band) {
    photon_band = params.dispersive != 0u ? band : BAND_WHITE;
    trace_and_splat(id, in_grid, light);
  }
  end_group_totals(5u, 5u, 3u);
}
