#version 460
// An image copied into a storage image of the same extent (deferred refraction: the background
// under the refractors' rectangle, and in refraction_layers the background that an even count of
// layers starts from). OUT_FORMAT is the target's storage format qualifier, set by the pass.
#ifndef OUT_FORMAT
#define OUT_FORMAT rgba16f
#endif
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0) uniform sampler2D source;
layout(binding = 1, OUT_FORMAT) uniform writeonly image2D target;
layout(push_constant) uniform Params { ivec2 size; } params;

void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, params.size))) return;
  imageStore(target, p, texelFetch(source, p, 0));
}
