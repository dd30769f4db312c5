#version 460
// One frame of a temporal_mean pass (passes/temporal_mean.cpp): the last frame's mean moved toward
// this frame's image by the frame's weight (1 / frames in the mean: the whole image on the first
// frame after a reset, 0 once the mean holds).
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0) uniform sampler2D current;
layout(binding = 1) uniform sampler2D previous;
layout(binding = 2, rgba32f) uniform writeonly image2D average;

layout(push_constant) uniform Params {
  uvec2 size;
  float weight;
} params;

void main() {
  ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(uvec2(texel), params.size))) return;
  vec4 last = texelFetch(previous, texel, 0);
  imageStore(average, texel, last + (texelFetch(current, texel, 0) - last) * params.weight);
}
