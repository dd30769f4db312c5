#version 460
// A shader that never ends while `keep_going` is set: each turn writes the image, so no compiler
// may drop the loop as one without effects.
layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;
layout(binding = 0, rgba8) uniform writeonly image2D target;
layout(push_constant) uniform Params {
  int keep_going;
} params;

void main() {
  const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, imageSize(target)))) return;
  float value = 0.0;
  do {
    value = fract(value + 0.001);
    imageStore(target, p, vec4(value));
  } while (params.keep_going != 0);
}
