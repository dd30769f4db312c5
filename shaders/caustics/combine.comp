#version 460
// Adds one coarse level (params.level >= 1) of the multi-resolution caustic map into the caustic
// map, which already holds level 0: each non-zero texel spreads its flux over the finest texels
// under a tent twice its width (bilinear weights, 2^(L+1) texels a side, summing to one; at the
// map's edge the weight of texels outside goes to the edge texel), so the total flux is kept.
// Only texels that photons reached do any work, which is what keeps this cheap: the coarse
// levels are mostly empty.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_atomic_float : require
#include "caustics/adaptive_common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

void main() {
  uint level = params.level;
  ivec2 t = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = ivec2(pyramid_size(level));
  if (any(greaterThanEqual(t, size))) return;
  float flux = pyramid[pyramid_offset(level) + uint(t.y * size.x + t.x)];
  if (flux == 0.0) return;
  int side = 1 << level;  // finest texels per texel of this level
  ivec2 first = t * side - side / 2;
  ivec2 map_size = imageSize(caustic_map);
  float norm = 1.0 / float(side);
  for (int y = 0; y < 2 * side; ++y) {
    float wy = (1.0 - abs(float(y) + 0.5 - float(side)) * norm) * norm;
    for (int x = 0; x < 2 * side; ++x) {
      float wx = (1.0 - abs(float(x) + 0.5 - float(side)) * norm) * norm;
      imageAtomicAdd(caustic_map, clamp(first + ivec2(x, y), ivec2(0), map_size - 1), flux * wx * wy);
    }
  }
}
