#version 460
// The refractors' back surfaces as the light sees them: their distance from the light, white at
// `near` and dark at `far`, black where the light meets no refractor (refractor_buffers clears to zero).
layout(binding = 0) uniform sampler2D back;
layout(location = 0) out vec4 view;
layout(push_constant) uniform Params {
  float near;
  float far;
} params;

void main() {
  const float from_light = texelFetch(back, ivec2(gl_FragCoord.xy), 0).y;
  const float shade = from_light > 0.0 ? 1.0 - 0.9 * clamp((from_light - params.near) / (params.far - params.near), 0.0, 1.0) : 0.0;
  view = vec4(vec3(shade), 1.0);
}
