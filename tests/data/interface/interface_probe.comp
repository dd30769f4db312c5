#version 460
// The device's interface model (refraction/interface.glsl) at chosen materials, angles and indices:
// texel i of `values` holds case i's reflectance per channel (rgb) and the coat's share (a), which
// tests/interface_test.cpp compares with values worked by hand from the extensions' formulas.
#extension GL_GOOGLE_include_directive : require
#include "common/scene_types.h"
#include "refraction/interface.glsl"

layout(set = 0, binding = 0, rgba32f) uniform writeonly image2D values;

layout(local_size_x = 8, local_size_y = 1) in;

// A plain glass of index 1.5: specular 1 and white, no coat, no film.
ObjectData glass() {
  ObjectData o;
  o.absorption_ior = vec4(0.0, 0.0, 0.0, 1.5);
  o.specular = vec4(1.0);
  o.layers = vec4(0.0, 0.0, 0.0, 1.3);
  o.film = vec4(0.0);
  return o;
}

void main() {
  int i = int(gl_GlobalInvocationID.x);
  if (i >= imageSize(values).x) return;
  ObjectData o = glass();
  float cos_i = 1.0, cos_outside = 1.0, eta_i = 1.0, eta_t = 1.5;
  if (i == 1) {  // KHR_materials_specular: colour (2, 1, 0.5), weight 0.8, at normal incidence
    o.specular = vec4(2.0, 1.0, 0.5, 0.8);
  } else if (i == 2) {  // the same at 45 degrees
    o.specular = vec4(2.0, 1.0, 0.5, 0.8);
    cos_i = cos_outside = sqrt(0.5);
  } else if (i == 3) {  // KHR_materials_clearcoat: a full coat at normal incidence
    o.layers.x = 1.0;
  } else if (i == 4) {  // a full coat, light at 60 degrees to the normal outside
    o.layers.x = 1.0;
    cos_i = cos_outside = 0.5;
  } else if (i == 5 || i == 6) {  // KHR_materials_iridescence: a film of 1.3, a quarter (a half) wave at 587.56 nm
    o.layers.zw = vec2(1.0, 1.3);
    o.film.x = 587.56 / ((i == 5 ? 4.0 : 2.0) * 1.3);
  } else if (i == 7) {  // the quarter-wave film seen from inside the glass
    o.layers.zw = vec2(1.0, 1.3);
    o.film.x = 587.56 / (4.0 * 1.3);
    eta_i = 1.5;
    eta_t = 1.0;
  }
  InterfaceReflection r = interface_reflection(o, cos_i, cos_outside, eta_i, eta_t);
  imageStore(values, ivec2(i, 0), vec4(reflectance(r), r.coat));
}
