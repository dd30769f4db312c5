#version 460
// Zeroes every layer of an r32f storage image array (the caustic map before photons are splatted into it).
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, r32f) uniform writeonly image2DArray target;
void main() {
  ivec3 size = imageSize(target);
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, size.xy))) return;
  for (int layer = 0; layer < size.z; ++layer) imageStore(target, ivec3(p, layer), vec4(0.0));
}
