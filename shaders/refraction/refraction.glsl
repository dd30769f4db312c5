#ifndef CAUSTICA_REFRACTION_GLSL
#define CAUSTICA_REFRACTION_GLSL
// Image-space refraction through two interfaces (Wyman 2005), shared by the forward and the
// deferred pass so that they differ only in where the front surface comes from.
//
// Needs, declared by the including shader: `frame` (SCENE_FRAME), `objects` (SCENE_OBJECTS),
// back_tex (the refractor's back surfaces, as written by refractor.frag), `params` with
// distance_mode, search_steps, search_distance; and for camera passes (unless
// REFRACTION_NO_CAMERA is defined) background_tex (the image behind the refractor), depth_tex (its
// depth) and a `counters` buffer with params.tir_counter.
#include "scene/scene.glsl"

const uint DISTANCE_DV = 0u;     // d_V: front-to-back distance along the view ray at this pixel
const uint DISTANCE_DV_DN = 1u;  // Wyman's blend of d_V and the per-vertex d_N by refraction angle
// Photons only (caustics/photon.glsl): exact paths with ray queries, everywhere or where the d_V/d_N
// estimate cannot be trusted. Both estimate with the blend where they estimate at all.
const uint DISTANCE_RAY_QUERY = 2u;
const uint DISTANCE_HYBRID = 3u;
// Image-space search along the refracted ray against the back-surface buffer (Umenhoffer et al.
// 2007; Davis and Wyman 2007): linear steps so that no crossing is missed, then bisection. The
// hybrid starts from it too.
const uint DISTANCE_SEARCH = 4u;
const int EXIT_SEARCH_STEPS = 16;
const int EXIT_BISECTIONS = 8;


float fresnel_dielectric(float cos_i, float eta_i, float eta_t) {
  cos_i = clamp(cos_i, 0.0, 1.0);
  float sin_t = eta_i / eta_t * sqrt(max(0.0, 1.0 - cos_i * cos_i));
  if (sin_t >= 1.0) return 1.0;
  float cos_t = sqrt(max(0.0, 1.0 - sin_t * sin_t));
  float rs = (eta_i * cos_i - eta_t * cos_t) / (eta_i * cos_i + eta_t * cos_t);
  float rp = (eta_t * cos_i - eta_i * cos_t) / (eta_t * cos_i + eta_i * cos_t);
  return 0.5 * (rs * rs + rp * rp);
}

// Projects a world point through `view_proj`; false when it is behind the eye or outside the image.
bool project_with(mat4 view_proj, vec3 p, out vec2 uv, out float depth) {
  vec4 clip = view_proj * vec4(p, 1.0);
  if (clip.w <= 1e-6) return false;
  vec3 ndc = clip.xyz / clip.w;
  uv = ndc.xy * 0.5 + 0.5;
  depth = ndc.z;
  return all(greaterThanEqual(uv, vec2(0.0))) && all(lessThanEqual(uv, vec2(1.0)));
}

bool project_to_screen(vec3 p, out vec2 uv, out float depth) { return project_with(frame.view_proj, p, uv, depth); }

// Follows a ray through a depth image seen through `view_proj`: linear steps until the ray passes
// behind the stored surface, then bisection. Returns false when it leaves the image or goes past
// the search distance; else `uv` is where it meets the surface.
bool march_depth(sampler2D depth_image, mat4 view_proj, vec3 origin, vec3 direction, out vec2 uv) {
  float step_length = params.search_distance / float(params.search_steps);
  float t_before = 0.0;
  float ray_depth;
  for (uint i = 1u; i <= params.search_steps; ++i) {
    float t = step_length * float(i);
    if (!project_with(view_proj, origin + direction * t, uv, ray_depth)) return false;
    if (ray_depth >= texture(depth_image, uv).r) {
      float lo = t_before, hi = t;
      for (int b = 0; b < 6; ++b) {
        float mid = 0.5 * (lo + hi);
        if (project_with(view_proj, origin + direction * mid, uv, ray_depth) && ray_depth >= texture(depth_image, uv).r) hi = mid;
        else lo = mid;
      }
      project_with(view_proj, origin + direction * hi, uv, ray_depth);
      return true;
    }
    t_before = t;
  }
  return false;
}

// Whether q lies behind the refractor's back surface as `view_proj` sees it, or outside it.
bool behind_back_surface(mat4 view_proj, vec3 eye, vec3 q) {
  vec2 uv;
  float depth;
  if (!project_with(view_proj, q, uv, depth)) return true;
  vec4 back = texture(back_tex, uv);
  return back.y <= 0.0 || distance(q, eye) >= back.y;
}

// The distance along t1 from p1 to where the ray crosses the back surface, within d_max; the
// estimate `d` when no crossing is found.
float search_exit(mat4 view_proj, vec3 eye, vec3 p1, vec3 t1, float d, float d_max) {
  float before = 0.0;
  for (int i = 1; i <= EXIT_SEARCH_STEPS; ++i) {
    float t = d_max * float(i) / float(EXIT_SEARCH_STEPS);
    if (behind_back_surface(view_proj, eye, p1 + t1 * t)) {
      float lo = before, hi = t;
      for (int b = 0; b < EXIT_BISECTIONS; ++b) {
        float mid = 0.5 * (lo + hi);
        if (behind_back_surface(view_proj, eye, p1 + t1 * mid)) hi = mid;
        else lo = mid;
      }
      return 0.5 * (lo + hi);
    }
    before = t;
  }
  return d;
}

// The path through two interfaces from a front surface point p1 (outward normal n1) seen from
// `eye` through `view_proj`, whose refractor buffers are back_tex (and the front's distance).
struct TwoInterfaces {
  vec3 exit_point;
  vec3 exit_direction;  // unit
  float distance;       // travelled inside
  float reflectance_in;
  float transmit_out;   // 1 - Fresnel reflectance at the exit; 1 when no back surface was found
  bool tir;             // the exit met total internal reflection; exit_direction is then the reflection
  // What the hybrid tracer asks before trusting the estimate: whether the estimated exit point lands
  // on a back surface in the image, how far from it (along the view ray), and whose it is.
  bool back_found;
  float back_offset;
  float back_object;
};

TwoInterfaces refract_two_interfaces(mat4 view_proj, vec3 eye, vec3 p1, vec3 n1, float front_distance, float dn, float ior, vec2 pixel_uv) {
  TwoInterfaces r;
  vec3 v = normalize(p1 - eye);
  if (dot(v, n1) > 0.0) n1 = -n1;  // interpolated normals can face away at silhouettes
  float cos_i = -dot(v, n1);
  r.reflectance_in = fresnel_dielectric(cos_i, 1.0, ior);
  vec3 t1 = refract(v, n1, 1.0 / ior);

  // Distance to the back surface.
  vec4 back_here = texture(back_tex, pixel_uv);
  float dv = back_here.y > 0.0 ? max(back_here.y - front_distance, 0.0) : dn;
  float d = dv;
  if (params.distance_mode != DISTANCE_DV && dn > 0.0) {
    float theta_i = acos(clamp(cos_i, 0.0, 1.0));
    float theta_t = acos(clamp(-dot(t1, n1), 0.0, 1.0));
    float w = theta_i > 1e-4 ? theta_t / theta_i : 1.0;
    d = w * dv + (1.0 - w) * dn;
  }
  if (params.distance_mode >= DISTANCE_HYBRID) d = search_exit(view_proj, eye, p1, t1, d, 2.0 * max(max(dv, dn), d) + 1e-4);
  r.distance = d;
  r.exit_point = p1 + t1 * d;
  r.exit_direction = t1;
  r.transmit_out = 1.0;
  r.tir = false;
  r.back_found = false;
  r.back_offset = 0.0;
  r.back_object = -1.0;

  // Second interface: the back normal where the exit point lands in the image.
  vec2 uv2;
  float depth2;
  if (project_with(view_proj, r.exit_point, uv2, depth2)) {
    vec4 back = texture(back_tex, uv2);
    if (back.y > 0.0) {
      r.back_found = true;
      r.back_offset = abs(distance(r.exit_point, eye) - back.y);
      r.back_object = back.w;
      vec3 n2 = unpack_normal(back.x);  // outward
      vec3 inward = dot(t1, n2) > 0.0 ? -n2 : n2;
      vec3 t2 = refract(t1, inward, ior);
      if (dot(t2, t2) == 0.0) {
        r.tir = true;
        r.exit_direction = reflect(t1, inward);
        r.transmit_out = 1.0;
      } else {
        r.transmit_out = 1.0 - fresnel_dielectric(-dot(t1, inward), ior, 1.0);
        r.exit_direction = t2;
      }
    }
  }
  r.exit_direction = normalize(r.exit_direction);
  return r;
}

#ifndef REFRACTION_NO_CAMERA
// The background seen along an exit ray from the camera: the lit image where the ray meets the
// background's depth, the sky where it leaves the screen.
vec3 background_along(vec3 origin, vec3 direction) {
  vec2 uv;
  return march_depth(depth_tex, frame.view_proj, origin, direction, uv) ? texture(background_tex, uv).rgb : frame.sky_ambient.rgb;
}

// Radiance seen through a refractor whose front surface is at p1 with outward normal n1.
vec3 refracted_radiance(vec3 p1, vec3 n1, float front_distance, float dn, uint object_index, vec2 pixel_uv) {
  ObjectData object = objects[object_index];
  TwoInterfaces path = refract_two_interfaces(frame.view_proj, frame.camera_position.xyz, p1, n1, front_distance, dn,
                                              object.absorption_ior.a, pixel_uv);
  // Total internal reflection: the ray reflects and, in this two-interface model, leaves along the
  // reflected direction with all its energy (no black pixels, no NaN).
  if (path.tir) atomicAdd(counters[params.tir_counter], 1u);
  vec3 absorbed = exp(-object.absorption_ior.rgb * path.distance);
  vec3 behind = background_along(path.exit_point, path.exit_direction);
  return path.reflectance_in * frame.sky_ambient.rgb + (1.0 - path.reflectance_in) * path.transmit_out * absorbed * behind;
}
#endif

#endif
