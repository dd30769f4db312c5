#version 460
// The hierarchical caustic map's coverage pyramid: level 0 marks the light-view texels that show a
// refractor; each next level is the max of 2 x 2 texels of the one before.
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
    coverage[p.y * side + p.x] = texelFetch(front_tex, ivec2(p), 0).y > 0.0 ? 1u : 0u;
    return;
  }
  uint below = offset - (1u << (2u * (params.light_size_log2 - level + 1u)));
  uint below_side = side * 2u;
  uvec2 q = p * 2u;
  uint any_covered = coverage[below + q.y * below_side + q.x] | coverage[below + q.y * below_side + q.x + 1u] |
                     coverage[below + (q.y + 1u) * below_side + q.x] | coverage[below + (q.y + 1u) * below_side + q.x + 1u];
  coverage[offset + p.y * side + p.x] = any_covered;
}
