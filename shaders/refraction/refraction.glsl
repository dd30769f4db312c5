#ifndef CAUSTICA_REFRACTION_GLSL
#define CAUSTICA_REFRACTION_GLSL
// Image-space refraction through two interfaces (Wyman 2005), shared by the forward and the
// deferred pass so that they differ only in where the front surface comes from.
//
// Needs, declared by the including shader: `frame` (SCENE_FRAME), `objects` (SCENE_OBJECTS),
// background_tex (the image behind the refractor), depth_tex (its depth), back_tex (the
// refractor's back surfaces, as written by refractor.frag), and `params` with distance_mode,
// search_steps, search_distance. And a counter buffer with tir_counter.
#include "scene/scene.glsl"

const uint DISTANCE_DV = 0u;     // d_V: front-to-back distance along the view ray at this pixel
const uint DISTANCE_DV_DN = 1u;  // Wyman's blend of d_V and the per-vertex d_N by refraction angle

float fresnel_dielectric(float cos_i, float eta_i, float eta_t) {
  cos_i = clamp(cos_i, 0.0, 1.0);
  float sin_t = eta_i / eta_t * sqrt(max(0.0, 1.0 - cos_i * cos_i));
  if (sin_t >= 1.0) return 1.0;
  float cos_t = sqrt(max(0.0, 1.0 - sin_t * sin_t));
  float rs = (eta_i * cos_i - eta_t * cos_t) / (eta_i * cos_i + eta_t * cos_t);
  float rp = (eta_t * cos_i - eta_i * cos_t) / (eta_t * cos_i + eta_i * cos_t);
  return 0.5 * (rs * rs + rp * rp);
}

// Projects a world point; returns false when it is behind the eye or off screen.
bool project_to_screen(vec3 p, out vec2 uv, out float depth) {
  vec4 clip = frame.view_proj * vec4(p, 1.0);
  if (clip.w <= 1e-6) return false;
  vec3 ndc = clip.xyz / clip.w;
  uv = ndc.xy * 0.5 + 0.5;
  depth = ndc.z;
  return all(greaterThanEqual(uv, vec2(0.0))) && all(lessThanEqual(uv, vec2(1.0)));
}

// Follows the exit ray through the background's depth buffer: linear steps until the ray passes
// behind the stored surface, then bisection. Off screen or past the search distance: the sky.
vec3 background_along(vec3 origin, vec3 direction) {
  float step_length = params.search_distance / float(params.search_steps);
  float t_before = 0.0;
  for (uint i = 1u; i <= params.search_steps; ++i) {
    float t = step_length * float(i);
    vec2 uv;
    float ray_depth;
    if (!project_to_screen(origin + direction * t, uv, ray_depth)) return frame.sky_ambient.rgb;
    if (ray_depth >= texture(depth_tex, uv).r) {
      float lo = t_before, hi = t;
      for (int b = 0; b < 6; ++b) {
        float mid = 0.5 * (lo + hi);
        if (project_to_screen(origin + direction * mid, uv, ray_depth) && ray_depth >= texture(depth_tex, uv).r) hi = mid;
        else lo = mid;
      }
      project_to_screen(origin + direction * hi, uv, ray_depth);
      return texture(background_tex, uv).rgb;
    }
    t_before = t;
  }
  return frame.sky_ambient.rgb;
}

// Radiance seen through a refractor whose front surface is at p1 with outward normal n1.
vec3 refracted_radiance(vec3 p1, vec3 n1, float front_distance, float dn, uint object_index, vec2 pixel_uv) {
  ObjectData object = objects[object_index];
  float ior = object.absorption_ior.a;
  vec3 v = normalize(p1 - frame.camera_position.xyz);
  if (dot(v, n1) > 0.0) n1 = -n1;  // interpolated normals can face away at silhouettes
  float cos_i = -dot(v, n1);
  float reflectance_in = fresnel_dielectric(cos_i, 1.0, ior);
  vec3 t1 = refract(v, n1, 1.0 / ior);

  // Distance to the back surface.
  vec4 back_here = texture(back_tex, pixel_uv);
  float dv = back_here.y > 0.0 ? max(back_here.y - front_distance, 0.0) : dn;
  float d = dv;
  if (params.distance_mode == DISTANCE_DV_DN && dn > 0.0) {
    float theta_i = acos(clamp(cos_i, 0.0, 1.0));
    float theta_t = acos(clamp(-dot(t1, n1), 0.0, 1.0));
    float w = theta_i > 1e-4 ? theta_t / theta_i : 1.0;
    d = w * dv + (1.0 - w) * dn;
  }
  vec3 p2 = p1 + t1 * d;

  // Second interface: the back normal where p2 lands on screen.
  vec3 exit_direction = t1;
  float transmit_out = 1.0;
  vec2 uv2;
  float depth2;
  if (project_to_screen(p2, uv2, depth2)) {
    vec4 back = texture(back_tex, uv2);
    if (back.y > 0.0) {
      vec3 n2 = unpack_normal(back.x);  // outward
      vec3 inward = dot(t1, n2) > 0.0 ? -n2 : n2;
      vec3 t2 = refract(t1, inward, ior);
      if (dot(t2, t2) == 0.0) {
        // Total internal reflection: the ray reflects and, in this two-interface model, leaves
        // along the reflected direction with all its energy (no black pixels, no NaN).
        exit_direction = reflect(t1, inward);
        atomicAdd(counters[params.tir_counter], 1u);
      } else {
        transmit_out = 1.0 - fresnel_dielectric(-dot(t1, inward), ior, 1.0);
        exit_direction = t2;
      }
    }
  }
  vec3 absorbed = exp(-object.absorption_ior.rgb * d);
  vec3 behind = background_along(p2, normalize(exit_direction));
  return reflectance_in * frame.sky_ambient.rgb + (1.0 - reflectance_in) * transmit_out * absorbed * behind;
}

#endif
