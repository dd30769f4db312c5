#version 460
// An analytic HDR test pattern: smooth stripes and a bright Gaussian "sun" above 1.0, so that a
// blur and a tonemap have something to do and a CPU model can predict every pixel.
layout(push_constant) uniform Params {
  vec2 size;
  vec2 sun;
  float frequency;
  float sun_intensity;
  float sun_radius;
} params;

layout(location = 0) out vec4 color;

void main() {
  const float tau = 6.28318530718;
  vec2 uv = gl_FragCoord.xy / params.size;
  vec3 stripes = vec3(0.5 + 0.5 * sin(tau * params.frequency * uv.x), uv.y, 0.5 + 0.5 * cos(tau * params.frequency * uv.y));
  vec2 d = uv - params.sun;
  float sun = params.sun_intensity * exp(-dot(d, d) / (params.sun_radius * params.sun_radius));
  color = vec4(0.5 * stripes + vec3(sun), 1.0);
}
