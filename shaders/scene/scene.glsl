#ifndef CAUSTICA_SCENE_GLSL
#define CAUSTICA_SCENE_GLSL
#extension GL_GOOGLE_include_directive : require
#include "common/scene_types.h"

// Bindings every scene pass shares; a shader declares the ones it uses with these macros.
#define SCENE_FRAME                                         \
  layout(set = 0, binding = 0, std140) uniform FrameBlock { \
    FrameData frame;                                        \
  };
#define SCENE_VERTICES                                               \
  layout(set = 0, binding = 1, std430) readonly buffer VertexBlock { \
    Vertex vertices[];                                               \
  };
#define SCENE_OBJECTS                                                \
  layout(set = 0, binding = 2, std430) readonly buffer ObjectBlock { \
    ObjectData objects[];                                            \
  };

// A refractor's tint and transmission vary over its surface where it has a base colour or a
// transmission texture (scene/textures.glsl, tint_transmission_from).
bool transmittance_varies(ObjectData object) {
  return object.base_color.row_u.w >= 0.0 || object.transmission_map.row_u.w >= 0.0;
}

// A solid refractor whose mesh bounds a convex body (engine/scene/convexity.cpp): a ray that leaves
// it cannot meet it again.
bool convex_solid(ObjectData object) {
  return object.albedo_refractor.a > 1.5;
}

// Octahedral unit-vector encoding stored in one float's bits (a refractor buffer's first channel).
// The bits always form a normal, finite float (exponent field 1 to 254): a colour attachment and
// a sampled fetch need not keep a NaN's payload or a denormal (Vulkan lets implementations quiet
// NaNs and flush denormals), and two snorm16 values' bits are one or the other wherever the second
// value lies within 1/256 of 0 or of -1 (a sphere in the light's view: about 550 of its 2e5
// texels). x takes the low 16 bits (unorm); y the high 16, as an index into the 65024 patterns
// whose exponent field is neither 0 nor 255: [128, 32639] (positive floats) and [32896, 65407]
// (negative ones).
const uint NORMAL_Y_POSITIVE = 128u, NORMAL_Y_NEGATIVE = 32896u, NORMAL_Y_RUN = 32512u, NORMAL_Y_LEVELS = 2u * NORMAL_Y_RUN - 1u;
vec2 oct_wrap(vec2 v) {
  return (1.0 - abs(v.yx)) * vec2(v.x >= 0.0 ? 1.0 : -1.0, v.y >= 0.0 ? 1.0 : -1.0);
}
float pack_normal(vec3 n) {
  n /= abs(n.x) + abs(n.y) + abs(n.z);
  vec2 e = clamp(0.5 * (n.z >= 0.0 ? n.xy : oct_wrap(n.xy)) + 0.5, 0.0, 1.0);
  uint x = uint(round(e.x * 65535.0)), y = uint(round(e.y * float(NORMAL_Y_LEVELS)));
  uint high = y < NORMAL_Y_RUN ? NORMAL_Y_POSITIVE + y : NORMAL_Y_NEGATIVE + (y - NORMAL_Y_RUN);
  return uintBitsToFloat(x | (high << 16));
}
vec3 unpack_normal(float packed) {
  uint bits = floatBitsToUint(packed), high = bits >> 16;
  uint y = high < NORMAL_Y_NEGATIVE ? high - NORMAL_Y_POSITIVE : high - NORMAL_Y_NEGATIVE + NORMAL_Y_RUN;
  vec2 e = vec2(float(bits & 0xFFFFu) / 65535.0, float(y) / float(NORMAL_Y_LEVELS)) * 2.0 - 1.0;
  vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));
  if (n.z < 0.0) n.xy = oct_wrap(n.xy);
  return normalize(n);
}

// World position of a pixel from its depth-buffer value.
vec3 world_from_depth(mat4 inv_view_proj, vec2 uv, float depth) {
  vec4 p = inv_view_proj * vec4(uv * 2.0 - 1.0, depth, 1.0);
  return p.xyz / p.w;
}

// Lights: position_type.w 0 spot, 1 point, 2 directional (common/scene_types.h).
bool light_is_directional(LightData light) {
  return light.position_type.w == 2.0;
}
bool light_is_point(LightData light) {
  return light.position_type.w == 1.0;
}
// The cube face (LightData::faces) that holds direction d from a point light: its major axis.
uint cube_face(vec3 d) {
  vec3 a = abs(d);
  if (a.x >= a.y && a.x >= a.z) return d.x > 0.0 ? 0u : 1u;
  if (a.y >= a.z) return d.y > 0.0 ? 2u : 3u;
  return d.z > 0.0 ? 4u : 5u;
}
// The unit direction from p towards the light, and the squared distance its light falls off with
// (1 for a directional light, which is infinitely far along -axis).
vec3 toward_light(LightData light, vec3 p, out float d2) {
  if (light_is_directional(light)) {
    d2 = 1.0;
    return -light.direction_cos.xyz;
  }
  vec3 to_light = light.position_type.xyz - p;
  d2 = max(dot(to_light, to_light), 1e-8);
  return to_light * inversesqrt(d2);
}

// A spot light's cone seen along `direction` (unit, from the light), its edge softened over a small
// band so that it does not alias; 1 for a point or directional light, but for a point light's
// caustic cube face (LightData::face) 0 outside the face's own directions, so that the faces'
// photons partition the sphere.
float spot_cone(LightData light, vec3 direction) {
  if (light.face.x >= 0.0) return cube_face(direction) == uint(light.face.x) ? 1.0 : 0.0;
  if (light.position_type.w != 0.0) return 1.0;
  return smoothstep(light.direction_cos.w, mix(light.direction_cos.w, 1.0, 0.02), dot(direction, light.direction_cos.xyz));
}

// 1 / direction for a ray's slab tests, every component finite: a zero one becomes a tiny one of
// its sign, so that a box's slab gives a huge distance, never NaN.
vec3 slab_inverse(vec3 direction) {
  vec3 away_from_zero = mix(vec3(1e-30), vec3(-1e-30), lessThan(direction, vec3(0.0)));
  return 1.0 / mix(direction, away_from_zero, lessThan(abs(direction), vec3(1e-30)));
}

#endif
