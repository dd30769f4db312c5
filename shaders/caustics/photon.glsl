#ifndef CAUSTICA_PHOTON_GLSL
#define CAUSTICA_PHOTON_GLSL
// One photon from a spot light through the light-view refractor buffers to the receivers, shared by
// every caustic method. Needs, declared before inclusion: SCENE_FRAME, SCENE_OBJECTS, front_tex,
// back_tex, receiver_depth, caustic_map, and `params` with distance_mode, search_steps,
// search_distance, light and fresnel (see refraction.glsl).
#extension GL_EXT_shader_atomic_float : require
#define REFRACTION_NO_CAMERA
#include "refraction/refraction.glsl"

struct Photon {
  float power;     // after Fresnel and absorption; the power it left the light with when it missed
  float entering;  // its power before the refractor, when it met one (else 0)
  bool hit;        // met a refractor
  bool tir;        // dropped: total internal reflection at the back surface
  bool landed;     // reached a receiver at `texel` of the caustic map
  ivec2 texel;
  vec2 landing;    // where it landed, in caustic-map texels (texel = floor(landing), clamped)
};

// The photon through the centre of `uv` on the light's image plane, standing for a square of side
// `texel` (in units of the image plane at distance 1): its power is the light's intensity times
// that square's solid angle, texel^2 cos^3 of its angle to the axis, times the spot cone.
Photon trace_photon(LightData light, vec2 uv, float texel) {
  Photon ph;
  ph.hit = false;
  ph.tir = false;
  ph.landed = false;
  ph.entering = 0.0;
  ph.texel = ivec2(0);
  ph.landing = vec2(0.0);
  vec2 plane = (uv * 2.0 - 1.0) * light.clip.z;
  float cos_axis = inversesqrt(1.0 + dot(plane, plane));
  vec3 eye = light.position_type.xyz;
  vec3 direction = normalize(world_from_depth(light.inv_view_proj, uv, 0.5) - eye);
  // The spot's cone, with the soft edge of scene/lighting.frag.
  float cone = smoothstep(light.direction_cos.w, mix(light.direction_cos.w, 1.0, 0.02), dot(direction, light.direction_cos.xyz));
  ph.power = light.radiant.a * texel * texel * cos_axis * cos_axis * cos_axis * cone;
  vec4 front = texture(front_tex, uv);
  if (front.y <= 0.0 || ph.power <= 0.0) return ph;
  ph.hit = true;
  ph.entering = ph.power;
  ObjectData object = objects[uint(front.w)];
  vec3 p1 = eye + direction * front.y;
  TwoInterfaces path = refract_two_interfaces(light.view_proj, eye, p1, unpack_normal(front.x), front.y, front.z, object.absorption_ior.a, uv);
  if (path.tir) {
    ph.tir = true;
    return ph;
  }
  if (params.fresnel != 0u) ph.power *= (1.0 - path.reflectance_in) * path.transmit_out;
  // The caustic map holds one channel: the mean of the three absorption coefficients.
  ph.power *= exp(-dot(object.absorption_ior.rgb, vec3(1.0 / 3.0)) * path.distance);
  vec2 landing;
  if (!march_depth(receiver_depth, light.view_proj, path.exit_point, path.exit_direction, landing)) return ph;
  ivec2 size = imageSize(caustic_map);
  ph.landing = landing * vec2(size);
  ph.texel = clamp(ivec2(ph.landing), ivec2(0), size - 1);
  ph.landed = true;
  return ph;
}

void splat(ivec2 texel, float power) { imageAtomicAdd(caustic_map, texel, power); }

#endif
