#version 460
// One step of summing the multi-resolution caustic map, coarsest level first: every texel of level
// params.level - 1 adds level params.level bilinearly interpolated at its centre, divided by 4 (a
// texel covers four of the finer level's), which keeps the total flux. The step into level 0
// writes the caustic map.
#extension GL_GOOGLE_include_directive : require
#include "caustics/adaptive_common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

void main() {
  uint coarse = params.level, fine = coarse - 1u;
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  ivec2 fine_size = ivec2(pyramid_size(fine)), size = ivec2(pyramid_size(coarse));
  if (any(greaterThanEqual(p, fine_size))) return;
  uint fine_offset = pyramid_offset(fine), offset = pyramid_offset(coarse);
  float flux = pyramid[fine_offset + uint(p.y * fine_size.x + p.x)];
  if (coarse < params.splat_levels) {
    vec2 c = (vec2(p) + 0.5) * 0.5 - 0.5;
    ivec2 i = ivec2(floor(c));
    vec2 f = c - vec2(i);
    ivec2 a = clamp(i, ivec2(0), size - 1), b = clamp(i + 1, ivec2(0), size - 1);
    float v00 = pyramid[offset + uint(a.y * size.x + a.x)], v10 = pyramid[offset + uint(a.y * size.x + b.x)];
    float v01 = pyramid[offset + uint(b.y * size.x + a.x)], v11 = pyramid[offset + uint(b.y * size.x + b.x)];
    flux += 0.25 * mix(mix(v00, v10, f.x), mix(v01, v11, f.x), f.y);
  }
  if (fine == 0u) imageStore(caustic_map, p, vec4(flux));
  else pyramid[fine_offset + uint(p.y * fine_size.x + p.x)] = flux;
}
