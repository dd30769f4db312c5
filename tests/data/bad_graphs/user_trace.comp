#version 460
#extension GL_EXT_ray_query : require
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 3, rgba32f) uniform writeonly image2D hits;
layout(binding = 14) uniform accelerationStructureEXT tlas;
layout(push_constant) uniform Params {
  float height;
} params;
void main() {
  rayQueryEXT query;
  rayQueryInitializeEXT(query, tlas, gl_RayFlagsOpaqueEXT, 0xFFu, vec3(0.0, params.height, 0.0), 0.0, vec3(0.0, -1.0, 0.0), 1e30);
  while (rayQueryProceedEXT(query)) {}
  imageStore(hits, ivec2(gl_GlobalInvocationID.xy), vec4(rayQueryGetIntersectionTEXT(query, true)));
}
