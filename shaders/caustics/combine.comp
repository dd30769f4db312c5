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
  uint at = pyramid_index(level, uvec2(t));
  vec3 flux = vec3(pyramid[at], pyramid[at + 1u], pyramid[at + 2u]);
  if (flux == vec3(0.0)) return;
  int side = 1 << level;  // finest texels per texel of this level
  ivec2 first = t * side - side / 2;
  ivec2 map_size = imageSize(caustic_map).xy;
  float norm = 1.0 / float(side);
  for (int y = 0; y < 2 * side; ++y) {
    float wy = (1.0 - abs(float(y) + 0.5 - float(side)) * norm) * norm;
    for (int x = 0; x < 2 * side; ++x) {
      float wx = (1.0 - abs(float(x) + 0.5 - float(side)) * norm) * norm;
      ivec2 texel = clamp(first + ivec2(x, y), ivec2(0), map_size - 1);
      for (int c = 0; c < 3; ++c) {
        if (flux[c] != 0.0) imageAtomicAdd(caustic_map, ivec3(texel, c), flux[c] * wx * wy);
      }
    }
  }
}
