#version 460
// Regular caustic map: one photon per texel of an N x N grid over the light's image plane, each
// traced by begin_photon() and finish_photon() (caustics/photon.glsl) and splatted into the caustic-map texel it lands in.
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
  uint search_steps;
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
  uint band;  // caustics/photon.glsl: BAND_WHITE, or the colour band traced
} params;

#include "caustics/photon.glsl"
#include "caustics/group_totals.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

void main() {
  begin_exact_jobs();  // before begin_group_totals' barrier
  begin_group_totals();
  uvec2 id = gl_GlobalInvocationID.xy;
  bool in_grid = all(lessThan(id, uvec2(params.grid)));
  LightData light = frame.lights[params.light];
  uint next = IMAGE_SPACE_DONE;
  ExactStart start;
  Photon ph;
  if (in_grid) ph = begin_photon(light, (vec2(id) + 0.5) / float(params.grid), 2.0 * light.clip.z / float(params.grid), next, start);
  finish_photon(ph, next, start, light);
  if (in_grid) {
    count(0);
    count(4);
    if (!ph.hit) {
      count(2);  // misses every refractor: direct light, not a caustic
    } else {
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
    }
  }
  end_group_totals(5u, 5u, 3u);
}
