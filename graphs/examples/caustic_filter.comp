#version 460
// A kernel-density filter of a caustic map: each texel becomes the Epanechnikov-weighted mean of
// the flux within `radius` texels, so that the grid's photons, splatted to single texels, spread
// into a smooth density. The weights sum to one, so the map's total flux is kept (away from its
// edges). One invocation per texel and colour layer.
layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;
layout(binding = 0) uniform sampler2DArray caustics;
layout(binding = 1, r32f) uniform writeonly image2DArray filtered;
layout(push_constant) uniform Params {
  int radius;
} params;

void main() {
  const ivec3 size = imageSize(filtered);
  const ivec3 p = ivec3(gl_GlobalInvocationID);
  if (any(greaterThanEqual(p, size))) return;
  float sum = 0.0, weights = 0.0;
  const float r2 = float((params.radius + 1) * (params.radius + 1));
  for (int y = -params.radius; y <= params.radius; ++y) {
    for (int x = -params.radius; x <= params.radius; ++x) {
      const ivec2 q = p.xy + ivec2(x, y);
      const float w = max(0.0, 1.0 - float(x * x + y * y) / r2);
      if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size.xy))) continue;
      sum += w * texelFetch(caustics, ivec3(q, p.z), 0).r;
      weights += w;
    }
  }
  imageStore(filtered, p, vec4(sum / weights));
}
