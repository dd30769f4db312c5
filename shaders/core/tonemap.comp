#version 460
// Exponential tonemap to 8-bit sRGB, counting pixels that were brighter than white.
#extension GL_GOOGLE_include_directive : require
#include "common/color.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0) uniform sampler2D source;
layout(binding = 1, rgba8) uniform writeonly image2D target;
layout(binding = 2) buffer Counters { uint counters[]; };
layout(push_constant) uniform Params {
  ivec2 size;
  float exposure;
  uint bright_counter;
} params;

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, params.size))) return;
  vec3 hdr = texelFetch(source, p, 0).rgb * params.exposure;
  if (luminance(hdr) > 1.0) atomicAdd(counters[params.bright_counter], 1u);
  imageStore(target, p, vec4(srgb_encode(vec3(1.0) - exp(-hdr)), 1.0));
}
