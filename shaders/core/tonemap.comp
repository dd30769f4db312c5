#version 460
// Exponential tonemap to 8-bit sRGB, counting pixels that were brighter than white. Dithered by
// half a level either way before the 8-bit store rounds, so that slow gradients (light falling off
// across a floor, absorption through thick glass) show no contour bands: the rounding error no
// longer repeats across a band but averages out over a few pixels.
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
  // Interleaved gradient noise (Jimenez 2014): uniform in [0, 1), no visible pattern, no texture.
  float noise = fract(52.9829189 * fract(dot(vec2(p), vec2(0.06711056, 0.00583715))));
  vec3 encoded = srgb_encode(vec3(1.0) - exp(-hdr)) + (noise - 0.5) / 255.0;
  imageStore(target, p, vec4(clamp(encoded, 0.0, 1.0), 1.0));
}
