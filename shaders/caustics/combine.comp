#version 460
// The multi-resolution caustic map summed into the caustic map: each finest texel gets its own flux
// plus every coarser level's, bilinearly interpolated at its centre and divided by the number of
// finest texels a coarse texel covers (4^level), which keeps the total flux.
#extension GL_GOOGLE_include_directive : require
#include "caustics/adaptive_common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

float pyramid_texel(uint level, ivec2 t) {
  ivec2 size = ivec2(pyramid_size(level));
  t = clamp(t, ivec2(0), size - 1);
  return pyramid[pyramid_offset(level) + uint(t.y * size.x + t.x)];
}

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, imageSize(caustic_map)))) return;
  float flux = pyramid_texel(0u, p);
  for (uint level = 1u; level < params.splat_levels; ++level) {
    vec2 c = (vec2(p) + 0.5) / float(1u << level) - 0.5;
    ivec2 i = ivec2(floor(c));
    vec2 f = c - vec2(i);
    float v = mix(mix(pyramid_texel(level, i), pyramid_texel(level, i + ivec2(1, 0)), f.x),
                  mix(pyramid_texel(level, i + ivec2(0, 1)), pyramid_texel(level, i + ivec2(1, 1)), f.x), f.y);
    flux += v / float(1u << (2u * level));
  }
  imageStore(caustic_map, p, vec4(flux));
}
