#version 460
// The coverage pyramid of the hierarchical caustic map and of coverage seeding: level 0 marks the
// blocks of light-view texels that show a refractor; each next level is the max of 2 x 2 texels of
// the one before.
#extension GL_GOOGLE_include_directive : require
#include "caustics/adaptive_common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

void main() {
  uvec2 p = gl_GlobalInvocationID.xy;
  uint level = params.level;  // the pyramid level being written
  uint side = 1u << (params.light_size_log2 - level);
  if (any(greaterThanEqual(p, uvec2(side)))) return;
  uint offset = 0u;
  for (uint l = 0u; l < level; ++l) offset += 1u << (2u * (params.light_size_log2 - l));
  if (level == 0u) {
    // The finest level is coarser than the light view by kCoverageBlock (see the pass): each of its
    // texels is the max over a block of light-view texels, read here in one thread.
    int block = textureSize(front_tex, 0).x >> params.light_size_log2;
    uint any_refractor = 0u;
    for (int y = 0; y < block; ++y) {
      for (int x = 0; x < block; ++x) any_refractor |= texelFetch(front_tex, ivec2(p) * block + ivec2(x, y), 0).y > 0.0 ? 1u : 0u;
    }
    coverage[p.y * side + p.x] = any_refractor;
    return;
  }
  uint below = offset - (1u << (2u * (params.light_size_log2 - level + 1u)));
  uint below_side = side * 2u;
  uvec2 q = p * 2u;
  uint any_covered = coverage[below + q.y * below_side + q.x] | coverage[below + q.y * below_side + q.x + 1u] |
                     coverage[below + (q.y + 1u) * below_side + q.x] | coverage[below + (q.y + 1u) * below_side + q.x + 1u];
  coverage[offset + p.y * side + p.x] = any_covered;
}
