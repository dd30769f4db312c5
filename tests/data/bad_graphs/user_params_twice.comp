#version 460
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, rgba32f) uniform writeonly image2D hits;
layout(push_constant) uniform Push {
  float height;
} push;
layout(binding = 1) uniform Params {
  float height;
} params;
void main() { imageStore(hits, ivec2(gl_GlobalInvocationID.xy), vec4(push.height + params.height)); }
