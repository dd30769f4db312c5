#ifndef CAUSTICA_REFRACTION_GLSL
#define CAUSTICA_REFRACTION_GLSL
// Image-space refraction through two interfaces (Wyman 2005), shared by the forward and the
// deferred pass so that they differ only in where the front surface comes from.
//
// Needs, declared by the including shader: `frame` (SCENE_FRAME), `objects` (SCENE_OBJECTS),
// back_tex (the refractor's back surfaces, as written by refractor.frag), `params` with
// distance_mode, search (search_steps()), search_distance; and for camera passes (unless
// REFRACTION_NO_CAMERA is defined) background_tex (the image behind the refractor), depth_tex (its
// depth) and a `counters` buffer with params.tir_counter.
#include "scene/scene.glsl"
#include "refraction/interface.glsl"
#include "scene/material_targets.glsl"

const uint DISTANCE_DV = 0u;     // d_V: front-to-back distance along the view ray at this pixel
const uint DISTANCE_DV_DN = 1u;  // Wyman's blend of d_V and the per-vertex d_N by refraction angle
// Exact paths with ray queries (photons in caustics/photon.glsl, camera rays in the deferred pass):
// everywhere, or where the image-space search cannot be trusted (untrusted_exit).
const uint DISTANCE_RAY_QUERY = 2u;
const uint DISTANCE_HYBRID = 3u;
// Image-space search along the refracted ray against the back-surface buffer (Umenhoffer et al.
// 2007; Davis and Wyman 2007): see find_crossing. The hybrid starts from it too.
const uint DISTANCE_SEARCH = 4u;
// Chosen from the material met first: exact paths (ray queries) through a solid refractor, image
// space through a thin wall, where image space sees the exact path.
const uint DISTANCE_MATERIAL = 5u;
// The pass's mode. A kernel that traces exact paths is compiled for its one mode
// (CAUSTICA_DISTANCE_MODE, passes/refraction.cpp's TracedScene), so that the modes it does not run
// are no code at all: lavapipe compiles a kernel within its first frame, and the hybrid camera
// kernel's cold compile took 41 s with the image-space modes' code in it and 22 s without. The
// image-space modes share one kernel and read the mode from the push constants (each of them alone
// compiled no faster than a third of the shared kernel).
#ifdef CAUSTICA_DISTANCE_MODE
#define DISTANCE_MODE CAUSTICA_DISTANCE_MODE
#else
#define DISTANCE_MODE params.distance_mode
#endif
// The modes that find the exit by the image-space search rather than estimate it.
bool exit_searched() { return DISTANCE_MODE == DISTANCE_SEARCH || DISTANCE_MODE == DISTANCE_HYBRID; }
// params.search, packed as passes/refraction.h's RefractionPush says: the background search's steps, and
// the total internal reflections that the search follows inside (search_bounces). A push constant
// rather than a define, so that a change of either reuses the compiled pipeline. A user pass, whose
// push constants are its parameters, defines REFRACTION_SEARCH (packed so) and
// REFRACTION_SEARCH_DISTANCE (how far the search goes) before inclusion, and CAUSTICA_DISTANCE_MODE
// for the mode (docs/shader_api.md).
#ifndef REFRACTION_SEARCH
#define REFRACTION_SEARCH params.search
#endif
#ifndef REFRACTION_SEARCH_DISTANCE
#define REFRACTION_SEARCH_DISTANCE params.search_distance
#endif
uint search_steps() { return REFRACTION_SEARCH & 0xffffu; }
int search_tir_bounces() { return int(REFRACTION_SEARCH >> 16u); }


// A hash-based generator: a photon or a pixel (by its position) and a seed draw the same numbers on
// every device and in every run.
uint pcg_hash(uint v) {
  uint state = v * 747796405u + 2891336453u;
  uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}
float next_uniform(inout uint state) {
  state = pcg_hash(state);
  return float(state >> 8) * (1.0 / 16777216.0);
}

// Rough transmission (glTF's roughness on a transmissive material; scene::Material::
// transmission_roughness): every interface refracts or reflects about a microfacet normal drawn
// from GGX's distribution D(m) (m.n) with alpha = roughness^2, a facet that faces the ray; the
// shadowing-masking weight is left out (the path keeps its power), as in the references
// (reference/exact_scene.h, microfacet_normal). Smooth surfaces draw no numbers.
float transmission_roughness(ObjectData object) { return object.metallic_roughness.w; }
vec3 microfacet_normal(vec3 n, vec3 direction, float roughness, inout uint rng) {
  if (roughness <= 0.0) return n;
  float a2 = roughness * roughness * roughness * roughness;
  // A frame around n without a branch on its direction (Duff et al. 2017).
  float s = n.z >= 0.0 ? 1.0 : -1.0;
  float k = -1.0 / (s + n.z);
  vec3 t = vec3(1.0 + s * n.x * n.x * k, s * n.x * n.y * k, -s * n.x), b = vec3(n.x * n.y * k, s + n.y * n.y * k, -n.y);
  for (int attempt = 0; attempt < 4; ++attempt) {
    float u1 = next_uniform(rng), u2 = next_uniform(rng);
    float cos2 = (1.0 - u1) / (1.0 + (a2 - 1.0) * u1);
    float sin_theta = sqrt(max(0.0, 1.0 - cos2)), phi = 6.28318530718 * u2;
    vec3 m = t * (sin_theta * cos(phi)) + b * (sin_theta * sin(phi)) + n * sqrt(cos2);
    if (dot(m, direction) < 0.0) return m;
  }
  return n;
}
// A direction scattered about a microfacet kept on its side of the surface (n faces the incoming
// ray): reflected light above it (`above` true), transmitted light below; one that a tilted facet
// sends to the wrong side is mirrored back across the surface.
vec3 on_side(vec3 direction, vec3 n, bool above) { return (dot(direction, n) > 0.0) == above ? direction : direction - 2.0 * dot(direction, n) * n; }
// Through a thin wall about facet m: the facet's mirror direction, mirrored through the wall (the
// unbent ray where m = n).
vec3 through_thin(vec3 direction, vec3 m, vec3 n) { return on_side(reflect(direction, m), n, false); }

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

// How far along origin + t direction (t <= t_max) the ray stays in front of the eye and inside the
// image of `view_proj`: each bound is linear in t in clip space. The march's last step stops there,
// so that a ray which meets a receiver near the image's edge is not lost to a step that overshoots
// the edge (with a search distance as long as the scene's diagonal, such steps are long).
float length_in_view(mat4 view_proj, vec3 origin, vec3 direction, float t_max) {
  vec4 a = view_proj * vec4(origin, 1.0), b = view_proj * vec4(direction, 0.0);
  vec4 at_origin[2] = vec4[2](vec4(a.w - a.x, a.w + a.x, a.w - a.y, a.w + a.y), vec4(a.w - 1e-6));
  vec4 slope[2] = vec4[2](vec4(b.w - b.x, b.w + b.x, b.w - b.y, b.w + b.y), vec4(b.w));
  float t_end = t_max;
  for (int i = 0; i < 2; ++i) {
    for (int c = 0; c < 4; ++c) {
      if (slope[i][c] < 0.0) t_end = min(t_end, max(-at_origin[i][c] / slope[i][c], 0.0));
    }
  }
  return t_end;
}

// True where a point at `ray_depth` lies behind the surface stored at `uv`. A cleared texel (depth
// 1: nothing there) has nothing to be behind; without this a ray that runs past the far plane would
// "meet" the sky texel it projects to, and hybrid tracing would trust that.
bool behind_stored_depth(sampler2D depth_image, vec2 uv, float ray_depth) {
  float stored = texture(depth_image, uv).r;
  return stored < 1.0 && ray_depth >= stored;
}

// What a march along a ray through a depth image found.
const uint MARCH_MISS = 0u;    // nothing: the ray left the image or went past the search distance
const uint MARCH_HIT = 1u;     // a surface the ray passes through
const uint MARCH_HIDDEN = 2u;  // no surface, but the ray slipped behind one's outline (below)

// Follows a ray through a depth image seen through `view_proj`: linear steps until the ray goes from
// in front of the stored surfaces to behind one, then bisection. Where the ray is then farther behind
// the surface it found than one step, it did not pass through that surface but behind its outline
// (a ray that slips past a floor's far edge and falls below it seems to "meet" the floor from
// behind): the march goes on for a real crossing. `uv` is where the ray meets a surface (MARCH_HIT)
// or, failing one, the first outline it slipped behind (MARCH_HIDDEN): where the image sees
// whatever hides the rest of the ray.
uint march_depth(sampler2D depth_image, mat4 view_proj, vec3 origin, vec3 direction, out vec2 uv) {
  float step_length = REFRACTION_SEARCH_DISTANCE / float(search_steps());
  float t_end = length_in_view(view_proj, origin, direction, REFRACTION_SEARCH_DISTANCE);
  float t_before = 0.0;
  bool in_front_before = true;
  uint found = MARCH_MISS;
  vec2 outline_uv = vec2(0.0);
  float ray_depth;
  // Each round steps to the next place where the ray passes behind a stored surface, then bisects
  // there: in rounds rather than inside the stepping loop, so that invocations in lockstep, which
  // get there at different steps, bisect together rather than once per step that one of them
  // stopped at.
  uint i = 1u;
  bool more = search_steps() > 0u;
  while (more) {
    float lo = 0.0, hi = 0.0;
    bool bracketed = false;
    while (more && !bracketed) {
      float t = min(step_length * float(i), t_end);
      ++i;
      if (!project_with(view_proj, origin + direction * t, uv, ray_depth)) {
        more = false;
        break;
      }
      bool behind = behind_stored_depth(depth_image, uv, ray_depth);
      bracketed = behind && in_front_before;
      lo = t_before;
      hi = t;
      in_front_before = !behind;
      t_before = t;
      more = t < t_end && i <= search_steps();
    }
    if (!bracketed) break;
    [[dont_unroll]] for (int b = 0; b < 6; ++b) {
      float mid = 0.5 * (lo + hi);
      if (project_with(view_proj, origin + direction * mid, uv, ray_depth) && behind_stored_depth(depth_image, uv, ray_depth)) hi = mid;
      else lo = mid;
    }
    vec3 on_ray = origin + direction * hi;
    project_with(view_proj, on_ray, uv, ray_depth);
    if (distance(on_ray, world_from_depth(inverse(view_proj), uv, texture(depth_image, uv).r)) <= step_length) return MARCH_HIT;
    if (found == MARCH_MISS) {
      found = MARCH_HIDDEN;
      outline_uv = uv;
    }
  }
  uv = outline_uv;
  return found;
}

// A refractor buffer's outward normal at uv, blended bilinearly from the nearest four texels that
// show the same refractor at about the distance of `here` (the texel at uv): a buffer holds one
// normal per texel, and nearest normals facet a smooth surface into texel-wide steps, which a
// sharp focus or a magnified view through the glass shows. A neighbour whose normal turns away
// from the texel's by more than about 18 degrees fades out by 37 (a box's edge stays hard), and
// fades rather than drops, so that a small move of the light changes the blend continuously.
vec3 smooth_normal(sampler2D surfaces, vec2 uv, vec4 here) {
  vec2 f = fract(uv * vec2(textureSize(surfaces, 0)) - 0.5);
  vec4 packed = textureGather(surfaces, uv, 0), distances = textureGather(surfaces, uv, 1), objects = textureGather(surfaces, uv, 3);
  vec4 weights = vec4((1.0 - f.x) * f.y, f.x * f.y, f.x * (1.0 - f.y), (1.0 - f.x) * (1.0 - f.y));  // textureGather's order
  vec3 centre = unpack_normal(here.x), n = vec3(0.0);
  for (int k = 0; k < 4; ++k) {
    vec3 nk = unpack_normal(packed[k]);
    if (objects[k] == here.w && distances[k] > 0.0 && abs(distances[k] - here.y) < 0.05 * here.y) n += weights[k] * smoothstep(0.8, 0.95, dot(nk, centre)) * nk;
  }
  return dot(n, n) > 1e-12 ? normalize(n) : centre;
}

// The search finds where a ray leaves to within a fraction of a texel, so the normal there is its
// leading error, and it reads the buffers' normals blended. d_V and d_V/d_N read the nearest texel,
// as the paper does: their exit points are estimates, and blending moved their error by a few
// thousandths either way while the adaptive traversal needed a quarter more photons for it (the
// bunny at 8192^2: 2.39% of the regular grid instead of 1.90%; docs/refraction.md).
vec3 buffer_normal(sampler2D surfaces, vec2 uv, vec4 here) {
  return exit_searched() ? smooth_normal(surfaces, uv, here) : unpack_normal(here.x);
}

// The searches below march a signed gap along a ray: negative before the crossing they look for,
// positive after it (or no value at all: off the image, no surface there). Linear steps so that no
// crossing is missed, then false position (the Illinois variant, which keeps the bracket and
// converges superlinearly on smooth surfaces; bisection where an end has no value).
// The searches' loops stay rolled ([[dont_unroll]]): each step calls exit_gap or project_with, and
// unrolled, every call is one more inlined copy for the driver: lavapipe took 375 ms to create the
// default graph's photon pipeline with them unrolled and 290 rolled, the pictures bit for bit the
// same (docs/lavapipe.md).
const int EXIT_SEARCH_STEPS = 8;
const int EXIT_REFINEMENTS = 4;
const uint GAP_BEHIND_BACK = 0u;      // behind the refractor's back surface (distance beyond it)
const uint GAP_OUTSIDE_REFRACTOR = 1u;  // outside the refractor (REFRACTION_FRONT_TEX only)

// Where a refractor buffer's distances are measured from: the eye (a perspective view), or the plane
// through `eye` across `axis` (an orthographic one: a directional light's view).
struct ViewOrigin {
  vec3 eye;
  vec3 axis;
  bool orthographic;
};
ViewOrigin perspective_origin(vec3 eye) { return ViewOrigin(eye, vec3(0.0), false); }
float view_distance(ViewOrigin o, vec3 q) { return o.orthographic ? dot(q - o.eye, o.axis) : distance(q, o.eye); }
vec3 view_direction(ViewOrigin o, vec3 q) { return o.orthographic ? o.axis : normalize(q - o.eye); }

float exit_gap(uint kind, mat4 view_proj, ViewOrigin eye, vec3 q, out bool valid) {
  vec2 uv;
  float depth;
  valid = false;
  if (!project_with(view_proj, q, uv, depth)) return 1.0;
  vec4 back = texture(back_tex, uv);
  if (back.y <= 0.0) return 1.0;
  float d = view_distance(eye, q);
#ifdef REFRACTION_FRONT_TEX
  if (kind == GAP_OUTSIDE_REFRACTOR) {
    vec4 front = texture(front_tex, uv);
    if (front.y <= 0.0) return 1.0;
    valid = true;
    return max(front.y - d, d - back.y);
  }
#endif
  valid = true;
  return d - back.y;
}

// Where the gap crosses zero between lo and hi: by false position where both ends have a gap of
// opposite signs, else halfway.
float crossing_estimate(float lo, float gap_lo, bool lo_valid, float hi, float gap_hi, bool hi_valid) {
  return lo_valid && hi_valid && gap_hi > gap_lo ? lo - gap_lo * (hi - lo) / (gap_hi - gap_lo) : 0.5 * (lo + hi);
}

// The crossing's distance along `direction` from `origin` within d_max (false when there is none):
// linear steps to bracket it, then refinement. The refinement follows the stepping loop rather than
// sitting inside it: invocations that run in lockstep (8 on lavapipe, 32 or 64 on a GPU) bracket their
// crossings at different steps, and inside the loop each of those steps ran the refinement again.
bool find_crossing(uint kind, mat4 view_proj, ViewOrigin eye, vec3 origin, vec3 direction, float d_max, out float t_cross) {
  float lo = 0.0, gap_lo = 0.0, hi = 0.0, gap_hi = 0.0;
  bool lo_valid = false, hi_valid = false, bracketed = false;
  [[dont_unroll]] for (int i = 1; i <= EXIT_SEARCH_STEPS && !bracketed; ++i) {
    hi = d_max * float(i) / float(EXIT_SEARCH_STEPS);
    gap_hi = exit_gap(kind, view_proj, eye, origin + direction * hi, hi_valid);
    bracketed = !hi_valid || gap_hi >= 0.0;
    if (!bracketed) {
      lo = hi;
      gap_lo = gap_hi;
      lo_valid = true;
    }
  }
  if (!bracketed) return false;
  int kept = 0;  // which end stayed last time: -1 lo, +1 hi (Illinois halves a twice-kept end's gap)
  [[dont_unroll]] for (int r = 0; r < EXIT_REFINEMENTS; ++r) {
    float t = clamp(crossing_estimate(lo, gap_lo, lo_valid, hi, gap_hi, hi_valid), lo + 0.01 * (hi - lo), hi - 0.01 * (hi - lo));
    bool valid;
    float gap = exit_gap(kind, view_proj, eye, origin + direction * t, valid);
    if (valid && gap < 0.0) {
      lo = t;
      gap_lo = gap;
      lo_valid = true;
      if (kept == 1) gap_hi *= 0.5;
      kept = 1;
    } else {
      hi = t;
      gap_hi = gap;
      hi_valid = valid;
      if (kept == -1) gap_lo *= 0.5;
      kept = -1;
    }
  }
  t_cross = crossing_estimate(lo, gap_lo, lo_valid, hi, gap_hi, hi_valid);
  return true;
}

// The distance along t1 from p1 to where the ray crosses the back surface, within d_max; the
// estimate `d` when no crossing is found.
float search_exit(mat4 view_proj, ViewOrigin eye, vec3 p1, vec3 t1, float d, float d_max) {
  float t;
  return find_crossing(GAP_BEHIND_BACK, view_proj, eye, p1, t1, d_max, t) ? t : d;
}

#ifdef REFRACTION_FRONT_TEX
// Total internal reflection followed inside by the search (Davis and Wyman 2007), where the
// including shader has the refractor's front surfaces too (front_tex): at most search_tir_bounces()
// bounces, the pass's search_bounces parameter.

// From p inside the refractor along `direction`: the distance to where the ray leaves it and the
// outward normal of the surface it leaves through, the front or the back one; false when it does
// not leave within d_max.
bool leave_refractor(mat4 view_proj, ViewOrigin eye, vec3 p, vec3 direction, float d_max, out float t_exit, out vec3 normal) {
  if (!find_crossing(GAP_OUTSIDE_REFRACTOR, view_proj, eye, p, direction, d_max, t_exit)) return false;
  vec2 uv;
  float depth;
  vec3 q = p + direction * t_exit;
  if (!project_with(view_proj, q, uv, depth)) return false;
  vec4 front = texture(front_tex, uv), back = texture(back_tex, uv);
  if (front.y <= 0.0 || back.y <= 0.0) return false;
  float d = view_distance(eye, q);
  normal = abs(d - front.y) < abs(d - back.y) ? smooth_normal(front_tex, uv, front) : smooth_normal(back_tex, uv, back);
  return true;
}
#endif

// The path through two interfaces from a front surface point p1 (outward normal n1) seen from
// `eye` through `view_proj`, whose refractor buffers are back_tex (and the front's distance).
struct TwoInterfaces {
  vec3 exit_point;
  vec3 exit_direction;  // unit
  float distance;       // travelled inside
  vec3 reflectance_in;  // per channel (refraction/interface.glsl)
  vec3 transmit_out;    // 1 - the reflectance at the exit; 1 when no back surface was found
  bool tir;             // the exit met total internal reflection; exit_direction is then the reflection
  bool followed;        // the search followed total internal reflection inside
  vec3 entry_reflection;  // unit: the Fresnel reflection off the entry (outside the refractor)
  vec3 exit_reflection;   // unit: the Fresnel reflection back inside at the exit (where it transmits)
  // What the hybrid tracer asks before trusting the estimate: whether the estimated exit point lands
  // on a back surface in the image, how far from it (along the view ray), and whose it is.
  bool back_found;
  float back_offset;
  float back_object;
};

// `object` refracts colour band `band` (BAND_WHITE: all); a rough refractor (`roughness` above 0)
// refracts about microfacet normals drawn from `rng` at both interfaces, and between them skips the
// `entry_draws` numbers that the exact tracer draws there (a photon's choices at the entry:
// entry_choice_draws), so that a path re-traced exactly from the same stream meets the same facets.
// (The hybrid trusts an image-space path by its own facets; re-traced with others, the paths it
// keeps would be a selection of those that got out, 1.10 of the reference on rough glass.)
TwoInterfaces refract_two_interfaces(mat4 view_proj, ViewOrigin eye, vec3 p1, vec3 n1, float front_distance, float dn, ObjectData object,
                                     uint band, vec2 pixel_uv, float roughness, uint entry_draws, inout uint rng) {
  TwoInterfaces r;
  float ior = band_ior(object, band);
  vec3 v = view_direction(eye, p1);
  if (dot(v, n1) > 0.0) n1 = -n1;  // interpolated normals can face away at silhouettes
  vec3 m1 = microfacet_normal(n1, v, roughness, rng);
  if (roughness > 0.0) {
    for (uint k = 0u; k < entry_draws; ++k) next_uniform(rng);
  }
  float cos_i = -dot(v, m1);
  r.reflectance_in = reflectance(interface_reflection(object, cos_i, coat_cos_outside(object, v, n1), 1.0, ior));
  vec3 t1 = on_side(refract(v, m1, 1.0 / ior), n1, false);
  r.entry_reflection = on_side(reflect(v, m1), n1, true);

  // Distance to the back surface.
  vec4 back_here = texture(back_tex, pixel_uv);
  float dv = back_here.y > 0.0 ? max(back_here.y - front_distance, 0.0) : dn;
  float d = dv;
  if (DISTANCE_MODE != DISTANCE_DV && dn > 0.0) {
    float theta_i = acos(clamp(cos_i, 0.0, 1.0));
    float theta_t = acos(clamp(-dot(t1, n1), 0.0, 1.0));
    float w = theta_i > 1e-4 ? theta_t / theta_i : 1.0;
    d = w * dv + (1.0 - w) * dn;
  }
  if (exit_searched()) d = search_exit(view_proj, eye, p1, t1, d, 2.0 * max(max(dv, dn), d) + 1e-4);
  r.distance = d;
  r.exit_point = p1 + t1 * d;
  r.exit_direction = t1;
  r.exit_reflection = t1;
  r.transmit_out = vec3(1.0);
  r.tir = false;
  r.followed = false;
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
      r.back_offset = abs(view_distance(eye, r.exit_point) - back.y);
      r.back_object = back.w;
      vec3 n2 = buffer_normal(back_tex, uv2, back);  // outward
      vec3 inward = dot(t1, n2) > 0.0 ? -n2 : n2;
      vec3 m2 = microfacet_normal(inward, t1, roughness, rng);
      vec3 t2 = refract(t1, m2, ior);
      // Two interfaces cannot follow light that a facet reflects back inside, where a real rough
      // surface lets most of it out nearby: where the surface itself would let the ray out, a facet
      // that reflects it totally is drawn again (up to 4 times), not dropped. Not where the exit is
      // searched: the search follows the reflection inside and the hybrid re-traces it exactly (with
      // the redraw they landed 1.095 and 1.115 of the reference on rough glass without Fresnel).
      bool leaves = roughness > 0.0 && !exit_searched() && dot(refract(t1, inward, ior), refract(t1, inward, ior)) > 0.0;
      for (int redraw = 0; redraw < 4 && leaves && dot(t2, t2) == 0.0; ++redraw) {
        m2 = microfacet_normal(inward, t1, roughness, rng);
        t2 = refract(t1, m2, ior);
      }
      if (dot(t2, t2) == 0.0) {
        r.tir = true;
        r.exit_direction = on_side(reflect(t1, m2), inward, true);
        r.transmit_out = vec3(1.0);
      } else {
        r.exit_direction = on_side(t2, inward, false);
        r.transmit_out = 1.0 - reflectance(interface_reflection(object, -dot(t1, m2), -dot(normalize(r.exit_direction), inward), ior, 1.0));
        r.exit_reflection = normalize(on_side(reflect(t1, m2), inward, true));
      }
    }
  }
#ifdef REFRACTION_FRONT_TEX
  // The search follows total internal reflection inside; the hybrid traces such paths exactly.
  if (DISTANCE_MODE == DISTANCE_SEARCH && r.tir) {
    float d_max = 2.0 * max(max(dv, dn), d) + 1e-4;
    for (int bounce = 0; bounce < search_tir_bounces() && r.tir; ++bounce) {
      float t;
      vec3 n_out;
      if (!leave_refractor(view_proj, eye, r.exit_point, r.exit_direction, d_max, t, n_out)) break;
      r.followed = true;
      r.exit_point += r.exit_direction * t;
      r.distance += t;
      vec3 inward = dot(r.exit_direction, n_out) > 0.0 ? -n_out : n_out;
      vec3 m = microfacet_normal(inward, r.exit_direction, roughness, rng);
      vec3 out_direction = refract(r.exit_direction, m, ior);
      if (dot(out_direction, out_direction) == 0.0) {
        r.exit_direction = on_side(reflect(r.exit_direction, m), inward, true);
      } else {
        r.tir = false;
        vec3 incident = r.exit_direction;
        r.exit_direction = on_side(normalize(out_direction), inward, false);
        r.transmit_out = 1.0 - reflectance(interface_reflection(object, -dot(incident, m), -dot(r.exit_direction, inward), ior, 1.0));
      }
    }
  }
#endif
  r.exit_direction = normalize(r.exit_direction);
  return r;
}

// Why the hybrid does not trust an image-space exit (the first that applies), or EXIT_TRUSTED: total
// internal reflection at the estimated exit, no back surface where the exit lands, another
// refractor at the exit or in the texel, the exit point off the back surface by more than
// `tolerance` times the distance travelled inside. The hybrid counters follow this order.
const uint EXIT_TRUSTED = 0u, EXIT_TIR = 1u, EXIT_EMPTY_BACK = 2u, EXIT_OFF_SURFACE = 3u, EXIT_MULTIPLE = 4u;
uint untrusted_exit(TwoInterfaces path, float front_object, vec4 back_here, float tolerance) {
  if (path.tir) return EXIT_TIR;
  if (!path.back_found) return EXIT_EMPTY_BACK;
  if (path.back_object != front_object || (back_here.y > 0.0 && back_here.w != front_object)) return EXIT_MULTIPLE;
  if (path.back_offset > tolerance * max(path.distance, 1e-6)) return EXIT_OFF_SURFACE;
  return EXIT_TRUSTED;
}

// Whether the segment from a to b passes through the bounding box of a refractor other than
// `own`: an image-space path (one refractor layer) cannot see a refractor that its exit ray
// crosses, hidden behind another in the image; the hybrids trace those paths exactly.
bool crosses_other_refractor(vec3 a, vec3 b, uint own) {
  vec3 d = b - a;
  vec3 inv = 1.0 / d;  // IEEE infinities for an axis the segment does not move along
  for (uint i = 0u; i < uint(objects.length()); ++i) {
    if (i == own || objects[i].albedo_refractor.a < 0.5) continue;
    vec3 t0 = (objects[i].bounds_min_thin.xyz - a) * inv, t1 = (objects[i].bounds_max_spread.xyz - a) * inv;
    vec3 lo = min(t0, t1), hi = max(t0, t1);
    if (max(max(lo.x, lo.y), max(lo.z, 0.0)) <= min(min(hi.x, hi.y), min(hi.z, 1.0))) return true;
  }
  return false;
}

// A thin-walled refractor (glTF transmission without a volume): light passes it without bending.
bool thin_walled(ObjectData object) { return object.bounds_min_thin.w > 0.5; }
// Where image space sees the exact path through a refractor (DISTANCE_MATERIAL's choice): a smooth
// thin wall without a mask, whose tint and transmission are the same all over (image space reads
// one per object: the textures' means), with a plain interface (photons replay the exact tracer's
// one Fresnel choice per wall; a layered one draws more).
bool image_space_is_exact(ObjectData object) {
  return thin_walled(object) && object.alpha_cutoff.y < 0.0 && transmission_roughness(object) == 0.0 && object.base_color.row_u.w < 0.0 &&
         object.transmission_map.row_u.w < 0.0 && !layered(object);
}
// DISTANCE_MATERIAL's choice, the same for photons and camera rays: a path that meets refractor `own`
// at `entry` and would reach what lies behind it at `behind` is traced exactly unless image space
// sees its exact path there and no other refractor lies between.
bool material_traces_exactly(uint own, vec3 entry, vec3 behind) {
  return !image_space_is_exact(objects[own]) || crosses_other_refractor(entry, behind, own);
}
// Whether a ray that met a thin-walled object's near wall at `front` (a refractor-buffer texel)
// meets its far wall too, at `back`: a closed thin object (a sphere) has two walls along a ray, a
// pane one (its back texel is then the near wall again, or empty).
bool thin_far_wall(vec4 front, vec4 back) { return back.y > front.y * (1.0 + 1e-4) && back.w == front.w; }
// The share of a photon's power past a refractor's surface (after Fresnel), per colour channel of
// the caustic map: the transmission times the tint (per texel where at_front_texel or the exact
// paths' tint_transmission_at gave them).
vec3 caustic_transmittance(ObjectData object) { return object.tint_transmission.a * object.tint_transmission.rgb; }

// The object with its interface layers (the fields interface_reflection reads: specular,
// layers.xyz, film.x) at the texels interface_layer_texels_filtered packed: each factor times its
// texel, as scene/trace.glsl's layers_at reads them where an exact path meets the surface.
ObjectData with_interface_layer_texels(ObjectData object, uvec2 texels) {
  vec4 coat_film = unpackUnorm4x8(texels.y);
  object.specular = object.specular_factors * unpack_colour_texel(texels.x);
  object.layers.xyz = object.layer_factors.xyz * coat_film.rgb;
  object.film.x = object.layer_maps[5].row_u.w >= 0.0 ? mix(object.film.y, object.film.z, coat_film.a) : object.film.x;
  return object;
}

#ifdef REFRACTION_FRONT_TEX
#ifdef REFRACTOR_TINT
layout(set = 0, binding = 16) uniform sampler2D front_tint_tex;
#endif
#ifdef REFRACTOR_LAYERS
layout(set = 0, binding = 17) uniform usampler2D front_layers_tex;
#endif
// The refractor seen at texel uv of the front refractor buffer, with its tint and transmission and
// its interface layers there where its textures vary them and the buffers carry them (the
// front_tint and front_layers ports, compiled in as REFRACTOR_TINT and REFRACTOR_LAYERS); else
// with its materials' means. The surface met first is the one whose texels count: a thin object's
// far wall, and a solid's exit, keep the entry's (the layers) or the means (the tint).
ObjectData at_front_texel(ObjectData object, vec2 uv) {
#ifdef REFRACTOR_TINT
  if (transmittance_varies(object)) object.tint_transmission = texture(front_tint_tex, uv);
#endif
#ifdef REFRACTOR_LAYERS
  if (object.layer_factors.w > 0.0) {
    ivec2 texel = min(ivec2(uv * vec2(textureSize(front_layers_tex, 0))), textureSize(front_layers_tex, 0) - 1);
    uvec4 texels = texelFetch(front_layers_tex, texel, 0);
    object = with_interface_layer_texels(object, texels.xy);
    if (texels.z > 0u) object.coat_normal.yzw = unpack_direction(float(texels.z - 1u));
  }
#endif
  return object;
}
#endif

#ifndef REFRACTION_NO_CAMERA
#include "refraction/camera.glsl"
#endif

#endif
