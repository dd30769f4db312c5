#version 460
// The multi-resolution caustic map's levels as splatted, side by side in one image for inspection:
// level 0 at the left, each next level half as large to the right of the one before. A texel of
// level L covers 4^L texels of level 0, so its flux is divided by 4^L: one exposure shows every
// level on the same scale. Texels outside every level are zero.
#extension GL_GOOGLE_include_directive : require
#include "caustics/adaptive_common.glsl"

layout(set = 0, binding = 13, r32f) uniform writeonly image2DArray caustic_levels;  // a layer per colour channel

layout(local_size_x = 8, local_size_y = 8) in;

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, imageSize(caustic_levels).xy))) return;
  vec3 flux = vec3(0.0);
  uint left = 0u;
  for (uint level = 0u; level < params.splat_levels; ++level) {
    uvec2 size = pyramid_size(level);
    if (uint(p.x) < left + size.x) {
      uvec2 t = uvec2(uint(p.x) - left, uint(p.y));
      // Level 0 is the caustic map itself, which holds only level 0 until combine.comp runs.
      if (t.y < size.y) {
        for (int c = 0; c < 3; ++c) {
          flux[c] = level == 0u ? imageLoad(caustic_map, ivec3(t, c)).r : pyramid[pyramid_index(level, t) + uint(c)] / float(1u << (2u * level));
        }
      }
      break;
    }
    left += size.x;
  }
  for (int c = 0; c < 3; ++c) imageStore(caustic_levels, ivec3(p, c), vec4(flux[c]));
}
