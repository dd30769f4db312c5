#version 460
// One level of the caustic-map traversals. A cluster at level L is 2 x 2 photons of the grid of
// side 64 * 2^L.
// Adaptive (Wyman and Nichols 2009): the four photons are traced. All four missing the refractor:
// dropped, unless coverage seeding is on and the coverage pyramid shows a refractor under the
// cluster (then refined, so that refractors smaller than the start grid's spacing are found). At the last level: every photon is output. From converge_level on, four photons landing
// in one caustic-map texel: output as one photon with the cluster's whole power. Otherwise each
// photon becomes a cluster of the next level, appended to the other list.
// HIERARCHICAL (Wyman 2008): nothing is traced above the last level; a cluster whose footprint the
// coverage pyramid shows free of refractors is skipped, any other is refined, and the last level
// traces and outputs its photons.
#extension GL_GOOGLE_include_directive : require
// A photon here may stand for a cluster that stops refining when its photons land together, so
// photon.glsl makes no random choice that moves a landing (see PHOTON_CLUSTERS there).
#define PHOTON_CLUSTERS
#include "caustics/adaptive_common.glsl"
#include "caustics/photon.glsl"
#include "caustics/group_totals.glsl"

layout(local_size_x = 64) in;

const uint PROCESSED = 0u, SPLATTED = 1u, MISS = 2u, TIR = 3u, CONVERGED = 4u, OVERFLOW = 5u, PROCESSED_LEVEL = 6u;
const uint FLUX = 0u, ENTERING = 1u, DROPPED = 2u;

// The random numbers of the shrunk splats' levels (splat_level): drawn from the cluster's place in
// its level's grid and the frame's jitter, not from the order of the cluster lists, which atomics
// fill in a different order from run to run.
uint splat_rng = 0u;

// The level for a footprint `width` finest texels wide: the one whose texels are at least that
// wide, at most the coarsest, never below the finest. ceil(log2()) by frexp, which is exact where
// log2 might round a power of two up a level. Knaus and Zwicker's shrinking (params.kernel_scale
// below 1) then wants a footprint between two levels' texels: the splat takes one of the two at
// random, the coarser with the probability that makes its mean squared width the shrunk one
// (scale^2 of the unshrunk), so that the mean over frames shrinks smoothly. Rounded up instead, a
// power-of-two footprint (a side path's) kept its size until the radius had halved, 26 frames on.
int ceil_log2(float width) {
  int e;
  float f = frexp(width, e);
  return f == 0.5 ? e - 1 : e;
}
uint splat_level(float width) {
  float widest = float(1u << (params.splat_levels - 1u));
  if (width <= 1.0) return 0u;
  int level = ceil_log2(min(width, widest));
  if (params.kernel_scale >= 1.0) return uint(level);
  float shrunk = exp2(float(level)) * params.kernel_scale;
  if (shrunk <= 1.0) return 0u;
  int finer = ceil_log2(shrunk) - 1;  // shrunk lies in (2^finer, 2^(finer + 1)]
  float ratio = shrunk / exp2(float(finer));
  float coarser = (ratio * ratio - 1.0) / 3.0;
  return uint(next_uniform(splat_rng) < coarser ? finer + 1 : finer);
}

// The splat level of a cluster's photons: their footprint on the caustic map is about the spread
// of the cluster's landing points (Chebyshev distance, in finest texels); a photon whose
// neighbours land n texels away goes to the level whose texels are n finest texels wide.
uint footprint_level(Photon ph[4]) {
  int spread = 0;
  for (uint a = 0u; a < 4u; ++a) {
    for (uint b = a + 1u; b < 4u; ++b) {
      if (ph[a].landed && ph[b].landed) {
        ivec2 d = abs(ph[a].texel - ph[b].texel);
        spread = max(spread, max(d.x, d.y));
      }
    }
  }
  return splat_level(float(spread));
}

// Level 0 is the caustic map itself; coarser levels wait in the pyramid for combine.comp.
void splat_at(ivec2 texel, uint level, vec3 power) {
  if (level == 0u) {
    splat(texel, power);
    return;
  }
  uint at = pyramid_index(level, uvec2(texel) >> level);
  for (uint c = 0u; c < 3u; ++c) {
    if (power[c] != 0.0) atomicAdd(pyramid[at + c], power[c]);
  }
}

// A photon's side path (the hybrid's Fresnel reflection, photon.glsl) is one sample for every photon
// of the last level that the photon stands for: splatted over a block as many finest texels wide as
// its grid is coarser than the last level's.
void output_side_path(Photon ph) {
  if (!ph.side_landed) return;
  splat_at(ph.side_texel, splat_level(float(1u << (params.max_level - params.level))), ph.side_power);
  count(SPLATTED);
  add_sum(FLUX, channel_mean(ph.side_power));
}

void output_photon(Photon ph, uint level) {
  output_side_path(ph);
  if (!ph.hit) {
    count(MISS);
    return;
  }
  add_sum(ENTERING, ph.entering);
  if (ph.tir) {
    count(TIR);
    add_sum(DROPPED, channel_mean(ph.power));
  } else if (!ph.landed) {
    count(MISS);
    add_sum(DROPPED, channel_mean(ph.power));
  } else {
    splat_at(ph.texel, level, ph.power);
    count(SPLATTED);
    add_sum(FLUX, channel_mean(ph.power));
  }
}

// A converged cluster's power spread evenly over its footprint on the caustic map: the box around
// the centroid of its landing points, twice their spread wide on each axis (the four photons stand
// for the 2 x 2 cells around them, whose edges lie half a spacing beyond), and at least a texel
// wide, so that a cluster landing in a point shares its power with bilinear weights; shrunk as
// frames accumulate (params.kernel_scale), down to that texel. Each texel
// gets the part of the box it covers; texels outside the map are clamped to its edge, so no flux
// is lost there.
void splat_footprint(vec2 centre, vec2 spread, vec3 power) {
  vec2 width = max(clamp(2.0 * spread, vec2(1.0), vec2(8.0)) * params.kernel_scale, vec2(1.0));
  vec2 low = centre - 0.5 * width, high = centre + 0.5 * width;
  ivec2 first = ivec2(floor(low)), size = imageSize(caustic_map).xy;
  vec3 per_area = power / (width.x * width.y);
  for (int y = first.y; float(y) < high.y; ++y) {
    for (int x = first.x; float(x) < high.x; ++x) {
      vec2 covered = min(high, vec2(x + 1, y + 1)) - max(low, vec2(x, y));
      if (covered.x > 0.0 && covered.y > 0.0) splat(clamp(ivec2(x, y), ivec2(0), size - 1), per_area * covered.x * covered.y);
    }
  }
}

// A converged cluster's power stands for its whole 2 x 2 cells. Where they reach past a refractor's
// silhouette (all four photons on it, a cell's outer part off it), that power would count light
// that misses the refractor, by as much as a fifth of a refractor smaller than a few cells: such a
// cluster refines instead. Tested at the cells' outer corners, just inside.
bool cells_on_refractor(uvec2 cluster, uint side) {
  for (uint k = 0u; k < 4u; ++k) {
    vec2 corner = vec2(cluster * 2u) + vec2(uvec2(k & 1u, k >> 1)) * 1.9 + 0.05;
    if (texture(front_tex, corner / float(side)).y <= 0.0) return false;
  }
  return true;
}

// Appends the four photons of `cluster` as clusters of the next level.
void refine(uvec2 cluster) {
  uint at = atomicAdd(counts[params.level + 1u], 4u);
  if (at + 4u <= list_capacity()) {
    uint base = ((params.level + 1u) % 2u) * list_capacity() + at;
    for (uint k = 0u; k < 4u; ++k) {
      uvec2 child = cluster * 2u + uvec2(k & 1u, k >> 1);
      clusters[base + k] = child.x | (child.y << 16);
    }
  } else {
    count_n(OVERFLOW, 4u);  // cannot happen with the pass's batching; counted, never silent
  }
}


// Traces the four photons of `cluster` (when `tracing`; every invocation of the workgroup calls this
// together, finish_photon's queue of exact paths being the workgroup's).
void trace_cluster(inout Photon ph[4], uvec2 cluster, uint side, float texel, bool tracing, LightData light) {
  for (uint k = 0u; k < 4u; ++k) {
    uint next = IMAGE_SPACE_DONE;
    ExactStart start = ExactStart(vec3(0.0), vec3(0.0), -1, 0u, 0u);
    uvec2 p = cluster * 2u + uvec2(k & 1u, k >> 1);
    if (tracing) ph[k] = begin_photon(light, (vec2(p) + photon_jitter()) / float(side), texel, next, start);
    finish_photon(ph[k], next, start, light);
  }
}

// HIERARCHICAL: the last level's photons, traced and output.
void trace_last_level(inout Photon ph[4], uvec2 cluster, uint side, float texel, bool last, LightData light) {
  trace_cluster(ph, cluster, side, texel, last, light);
  if (last) {
    uint level = footprint_level(ph);
    for (uint k = 0u; k < 4u; ++k) output_photon(ph[k], level);
    count_n(PROCESSED, 4u);
    count_n(PROCESSED_LEVEL, 4u);
  }
}

#ifdef CAUSTICA_RAY_QUERY
shared uint any_second_look;
#endif

// A cluster whose four photons all met a refractor and none landed ends there, dropped (the
// paper's rule, for total internal reflection in image space), unless a photon's exact path
// reflected inside the refractor: where such a path leaves changes from one facet to the next, so
// four lost corners say little of the cells between them, and the cluster refines. Measured at
// 2048^2 against 2e7 reference photons: at n = 2.4 the adaptive hybrid kept 0.937 of the energy
// with the rule for every lost cluster, 0.991 with this exception (docs/stability.md).
// A photon whose image-space search followed total internal reflection inside (search_bounces)
// counts as lost at its first exit, as with no bounce followed: where such light lands is
// scattered, and deciding on it refined the bunny's clusters to 21% more photons for a map no
// better than splatting it coarsely (docs/caustics.md). The traversal decides on first exits only;
// what a followed reflection lands is output where its cluster ends (output_lost_cluster, below).
bool lost_for_good(Photon ph) {
  return ph.hit && (!ph.landed || ph.followed) && !ph.bounced;
}

// The cluster that invocation `index` takes: at level 0 one of the start grid's, counted from the
// batch's first; later, one the level before appended.
uvec2 cluster_at(uint index, bool has_cluster) {
  uvec2 cluster = uvec2(0u);
  if (has_cluster && params.level == 0u) {
    uint start = (params.batch & 0xFFFFu) + index;
    cluster = uvec2(start % START_CLUSTERS_SIDE, start / START_CLUSTERS_SIDE);
  } else if (has_cluster) {
    uint packed = clusters[(params.level % 2u) * list_capacity() + index];
    cluster = uvec2(packed & 0xFFFFu, packed >> 16);
  }
  return cluster;
}

#ifdef HIERARCHICAL
// Skipped where no refractor is under the cluster: no photon of it is traced.
void hierarchical_level(uvec2 cluster, bool has_cluster, uint side, float texel, LightData light) {
  Photon ph[4];
  bool covers = has_cluster && covered(cluster);
  if (covers && params.level < params.max_level) refine(cluster);
  bool last = covers && params.level == params.max_level;
#ifdef PHOTON_BAND_LOOP
  // The traversal does not look at photons, so it is the same for every colour band: with a
  // dispersive refractor the last level traces its photons once per band (a variant of its own, as
  // in regular_photons.comp).
  for (uint band = 0u; band < 3u; ++band) {
    photon_band = band;
    trace_last_level(ph, cluster, side, texel, last, light);
  }
#else
  photon_band = params.band;
  trace_last_level(ph, cluster, side, texel, last, light);
#endif
}
#else
// What the traversal sees of a cluster's four traced photons.
struct ClusterLook {
  bool any_hit;
  bool all_lost;        // lost_for_good, each
  bool all_same_texel;  // all landed from their first exits, in one texel
  bool all_landed;      // from their first exits
  bool any_random;
  vec2 low, high;  // the box around their landing points
  vec2 middle;     // the centroid of their landing points
};

ClusterLook look_at(Photon ph[4]) {
  ClusterLook look;
  look.any_hit = false;
  look.all_same_texel = true;
  look.all_landed = true;
  look.any_random = false;
  look.all_lost = true;
  look.low = vec2(1e30);
  look.high = vec2(-1e30);
  look.middle = vec2(0.0);
  for (uint k = 0u; k < 4u; ++k) {
    look.any_hit = look.any_hit || ph[k].hit;
    bool landed_from_first_exit = ph[k].landed && !ph[k].followed;  // what the traversal decides on (lost_for_good)
    look.all_same_texel = look.all_same_texel && landed_from_first_exit && ph[k].texel == ph[0].texel;
    look.all_lost = look.all_lost && lost_for_good(ph[k]);
    look.all_landed = look.all_landed && landed_from_first_exit;
    look.any_random = look.any_random || ph[k].random;
    look.low = min(look.low, ph[k].landing);
    look.high = max(look.high, ph[k].landing);
    look.middle += 0.25 * ph[k].landing;
  }
  return look;
}

// Converged to nothing: all four met a refractor and none reached a receiver from its first exit
// (total internal reflection or an exit ray that leaves the light's view); their power is dropped as
// one, but for what a followed reflection landed: one sample with no neighbours to size its
// footprint, so splatted at the map's coarsest level. At the side paths' level (as wide as the
// cluster's grid is coarse) the default graph flickered 0.0996 along the stability suite's moving
// light, against the reference's own 0.064; at the coarsest, 0.0765, and the bunny's error at 512^2
// fell from 0.291 to 0.271.
void output_lost_cluster(Photon ph[4]) {
  for (uint k = 0u; k < 4u; ++k) {
    if (ph[k].followed && ph[k].landed) {
      output_photon(ph[k], splat_level(float(1u << (params.splat_levels - 1u))));
      continue;
    }
    count(ph[k].tir ? TIR : MISS);
    add_sum(ENTERING, ph[k].entering);
    add_sum(DROPPED, channel_mean(ph[k].power));
    output_side_path(ph[k]);
  }
  count(CONVERGED);
}

void output_converged_cluster(Photon ph[4], ClusterLook look) {
  vec3 power = ph[0].power + ph[1].power + ph[2].power + ph[3].power;
  splat_footprint(look.middle, look.high - look.low, power);
  for (uint k = 0u; k < 4u; ++k) output_side_path(ph[k]);
  count(CONVERGED);
  count(SPLATTED);
  add_sum(FLUX, channel_mean(power));
  add_sum(ENTERING, ph[0].entering + ph[1].entering + ph[2].entering + ph[3].entering);
}

// What becomes of a traced cluster: output, dropped, or refined at the next level.
void decide_cluster(Photon ph[4], uvec2 cluster, ClusterLook look, bool converged, bool second_look) {
  if (second_look) {
    uint level = footprint_level(ph);
    for (uint k = 0u; k < 4u; ++k) output_photon(ph[k], level);
    count(CONVERGED);
  } else if (!look.any_hit && params.coverage_seeded != 0u && params.level < params.max_level && covered(cluster)) {
    // All four missed, but the coverage pyramid shows a refractor between them (one smaller than
    // the photon spacing): look closer instead of losing it.
    refine(cluster);
  } else if (!look.any_hit) {
    count_n(MISS, 4u);
  } else if (params.level == params.max_level) {
    uint level = footprint_level(ph);
    for (uint k = 0u; k < 4u; ++k) output_photon(ph[k], level);
  } else if (params.level >= params.converge_level && look.all_lost) {
    output_lost_cluster(ph);
  } else if (params.level >= params.converge_level && converged) {
    output_converged_cluster(ph, look);
  } else {
    refine(cluster);
  }
}

void adaptive_level(uvec2 cluster, bool has_cluster, uint side, float texel, LightData light) {
  Photon ph[4];
  photon_band = params.band;  // the traversal follows one band's photons
  ClusterLook look;
  bool converged = false, second_look = false;
  // A cluster decided before the last level (converged, or lost) by photons whose paths drew
  // random numbers (Fresnel choices, rough facets) would be biased by those very draws: all four
  // happening to land together splats its whole power, all four happening to be lost drops it
  // (at n = 2.4 the hybrid kept 0.81 of the reference's energy so). Such a cluster's photons are
  // traced once more with their second set of numbers (photon_stream 1), and those, each splatted
  // where it lands, are its estimate, independent of the decision. A loop, not a second call:
  // each call of trace_cluster inlines the exact tracer, which lavapipe compiles slowly.
  bool tracing = has_cluster;
  for (uint stream = 0u; stream < 2u; ++stream) {
    photon_stream = stream;
    trace_cluster(ph, cluster, side, texel, tracing, light);
    if (tracing) {
      second_look = stream == 1u;
      look = look_at(ph);
      count_n(PROCESSED, 4u);
      count_n(PROCESSED_LEVEL, 4u);
      // The paper's test: all four in one texel. Within a texel: their landing points closer than
      // converge_spread texels on both axes, wherever the texel edges fall; a cluster that
      // straddles an edge then converges too, instead of refining to the last level.
      if (stream == 0u) {
        converged = params.converge_spread > 0.0 ? look.all_landed && all(lessThan(look.high - look.low, vec2(params.converge_spread)))
                                                 : look.all_same_texel;
        converged = converged && cells_on_refractor(cluster, side);
        bool early = look.any_hit && params.level < params.max_level && params.level >= params.converge_level && (look.all_lost || converged);
        tracing = early && look.any_random;
#ifdef CAUSTICA_RAY_QUERY
        if (tracing) atomicOr(any_second_look, 1u);
#endif
      }
    }
    if (stream == 1u) break;
#ifdef CAUSTICA_RAY_QUERY
    barrier();  // finish_photon's barriers: the workgroup takes the second look together, or none does
    if (any_second_look == 0u) break;
#else
    if (!tracing) break;  // image space alone: each invocation its own
#endif
  }
  if (has_cluster) decide_cluster(ph, cluster, look, converged, second_look);
}
#endif

void main() {
#ifdef CAUSTICA_RAY_QUERY
  if (gl_LocalInvocationIndex == 0u) any_second_look = 0u;
#endif
  begin_exact_jobs();
  begin_group_totals();
  uint index = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * GROUP + gl_LocalInvocationID.x;
  uint clusters_here = params.level == 0u ? params.batch >> 16 : min(counts[params.level], list_capacity());
  bool has_cluster = index < clusters_here;
  uvec2 cluster = cluster_at(index, has_cluster);
  splat_rng = pcg_hash((cluster.x | cluster.y << 16) ^ pcg_hash(params.jitter ^ pcg_hash(params.level | params.band << 8)));
  LightData light = frame.caustic_lights[params.light];
  uint side = 64u << params.level;
  float texel = 2.0 * light.clip.z / float(side);
#ifdef HIERARCHICAL
  hierarchical_level(cluster, has_cluster, side, texel, light);
#else
  adaptive_level(cluster, has_cluster, side, texel, light);
#endif
  end_group_totals(7u, 8u, 3u);
}
