#ifndef CAUSTICA_COLOR_GLSL
#define CAUSTICA_COLOR_GLSL
// Shared colour helpers. tests/core_render_test.cpp models these on the CPU; keep them in step.

float srgb_encode(float linear) {
  linear = clamp(linear, 0.0, 1.0);
  return linear <= 0.0031308 ? 12.92 * linear : 1.055 * pow(linear, 1.0 / 2.4) - 0.055;
}

vec3 srgb_encode(vec3 linear) { return vec3(srgb_encode(linear.r), srgb_encode(linear.g), srgb_encode(linear.b)); }

float luminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }

#endif
