#version 460
// Zeroes an r32f storage image (the caustic map before photons are splatted into it).
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, r32f) uniform writeonly image2D target;
void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (all(lessThan(p, imageSize(target)))) imageStore(target, p, vec4(0.0));
}
