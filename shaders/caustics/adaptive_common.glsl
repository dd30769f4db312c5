#ifndef CAUSTICA_ADAPTIVE_COMMON_GLSL
#define CAUSTICA_ADAPTIVE_COMMON_GLSL
// Bindings and push constants shared by the adaptive traversal's two kernels, which use one
// pipeline layout so that pushed descriptors stay valid between them.
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
// Two cluster lists of list_capacity() entries each; level L reads list L % 2 and appends to the other.
layout(set = 0, binding = 9, std430) buffer ListBlock { uint clusters[]; };
// counts[L]: clusters at level L; args[L]: the indirect dispatch that processes them.
layout(set = 0, binding = 10, std430) buffer ControlBlock {
  uint counts[16];
  uint args[16][3];
};
// Hierarchical, and adaptive with coverage_seeding: a max pyramid of the refractor coverage of the
// light-view front surfaces, finest level (light_size^2) first, each next level half the side.
layout(set = 0, binding = 11, std430) buffer CoverageBlock { uint coverage[]; };
// The multi-resolution caustic map: splat_levels levels of flux per texel and colour channel (three
// consecutive floats), the caustic map's size first, each next level half the side; combine.comp
// sums them into the caustic map.
layout(set = 0, binding = 12, std430) buffer PyramidBlock { float pyramid[]; };

const uint START_CLUSTERS_SIDE = 32u;  // a 64 x 64 photon grid: 32 x 32 clusters of 2 x 2 photons
const uint GROUP = 64u;

layout(push_constant) uniform Params {
  uint distance_mode;
  uint search;  // refraction.glsl: search_steps() and search_tir_bounces()
  float search_distance;
  uint light;
  uint fresnel;
  uint level;
  uint max_level;       // the level whose photon grid is the effective grid
  uint converge_level;  // first level with the max-error test (beyond max_level: never)
  uint batch;  // this batch's start clusters, row-major over 32 x 32: the first (low 16 bits) and the count (high 16)
  uint light_size_log2;  // log2 of the side of the coverage pyramid's finest level
  uint splat_levels;
  uint coverage_seeded;  // adaptive: the coverage pyramid exists and keeps clusters over small refractors
  float converge_spread;  // convergence test: 0 all four in one texel (the paper), else landing points closer than this (texels)
  // Counter slots: processed, splatted, dropped_miss, dropped_tir, converged, overflow,
  // processed at this level, peak bytes (counts); flux, flux_entering, flux_dropped (sums).
  uint counter_slot[11];
  // Exact paths (caustics/photon.glsl; passes/refraction.h ExactPathPush).
  uint exact_max_interfaces;
  uint exact_seed;
  uint exact_counters;
  float exact_epsilon;
  uint hybrid_packed;  // hybrid_tolerance and hybrid_reflections as two halves (packHalf2x16)
  uint band;  // caustics/photon.glsl: BAND_WHITE or the colour band traced (unused with PHOTON_BAND_LOOP)
  uint jitter;  // where in its cell each photon starts, 1/65536ths of the cell: x in the low 16 bits, y in the high
  float kernel_scale;  // Knaus and Zwicker's r_i / r_0: this frame's coarse splats, shrunk (passes/adaptive_caustic_map.cpp)
} params;

// The two lists fill their buffer (the push constants have no room left for their size).
uint list_capacity() { return uint(clusters.length()) / 2u; }

// Where in its cell of any level's grid each photon starts: (0.5, 0.5) the centre.
vec2 photon_jitter() { return vec2(params.jitter & 0xFFFFu, params.jitter >> 16) / 65536.0; }

// Whether any light-view texel under a cluster's footprint at params.level shows a refractor: one
// texel of the pyramid level whose texels are the footprint's size, or the finest level's texel
// that holds it.
bool covered(uvec2 cluster) {
  uint clusters_log2 = 5u + params.level;  // 32 * 2^level clusters per side
  uint k = params.light_size_log2 > clusters_log2 ? params.light_size_log2 - clusters_log2 : 0u;
  uint offset = 0u;
  for (uint l = 0u; l < k; ++l) offset += 1u << (2u * (params.light_size_log2 - l));
  uint level_side = 1u << (params.light_size_log2 - k);
  uvec2 texel = clusters_log2 >= params.light_size_log2 ? cluster >> (clusters_log2 - params.light_size_log2) : cluster;
  return coverage[offset + texel.y * level_side + texel.x] != 0u;
}

uvec2 pyramid_size(uint level) { return max(uvec2(imageSize(caustic_map).xy) >> level, uvec2(1u)); }

// The index of texel t's first channel at `level`.
uint pyramid_index(uint level, uvec2 t) {
  uint offset = 0u;
  for (uint l = 0u; l < level; ++l) offset += pyramid_size(l).x * pyramid_size(l).y;
  return 3u * (offset + t.y * pyramid_size(level).x + t.x);
}

#endif
