#version 460
// One axis of a separable box filter, clamped at the edges. OUT_FORMAT is the target's storage
// format qualifier, set by the pass from the bound resource.
#ifndef OUT_FORMAT
#define OUT_FORMAT rgba16f
#endif
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0) uniform sampler2D source;
layout(binding = 1, OUT_FORMAT) uniform writeonly image2D target;
layout(push_constant) uniform Params {
  ivec2 size;
  ivec2 axis;
  int radius;
} params;

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, params.size))) return;
  vec4 sum = vec4(0.0);
  for (int k = -params.radius; k <= params.radius; ++k) {
    sum += texelFetch(source, clamp(p + k * params.axis, ivec2(0), params.size - 1), 0);
  }
  imageStore(target, p, sum / float(2 * params.radius + 1));
}
