#ifndef CAUSTICA_HYBRID_GLSL
#define CAUSTICA_HYBRID_GLSL
// The hybrid's trust in an image-space path (distance hybrid), one sequence for photons
// (caustics/photon.glsl) and camera rays (refraction/deferred_refraction.comp). Needs
// refraction/refraction.glsl and scene/ray_query.glsl included first, and params.exact_epsilon.

// Past untrusted_exit's reasons: the exit ray meets a refractor (its own again, another fold of a
// concave one, or another one), which one image-space layer cannot follow.
const uint EXIT_REFRACTOR_AHEAD = 5u;

// EXIT_TRUSTED, with where the path's exit ray, traced exactly, meets the scene (`hit` false where
// it meets nothing); or the first reason the path is not trusted: untrusted_exit's, then
// EXIT_REFRACTOR_AHEAD. The estimated exit point may lie inside the surface it leaves, by up to
// `tolerance` times the distance travelled inside; from a convex solid the ray asks for the
// receivers alone (trace_exit_ray). The caller then asks whether what the ray meets is where the
// estimate may land (on the caustic map, seen by the camera), and whether another refractor's bounds
// lie on the way (crosses_other_refractor), in that order: the hybrid counters follow it.
uint hybrid_exit_ray(TwoInterfaces path, vec4 front, vec4 back_here, float tolerance, out bool hit, out vec3 meets) {
  hit = false;
  meets = path.exit_point;
  uint reason = untrusted_exit(path, front.w, back_here, tolerance);
  if (reason != EXIT_TRUSTED) return reason;
  vec3 exit_from = path.exit_point;
  SurfaceHit h = trace_exit_ray(exit_from, path.exit_direction, uint(front.w), tolerance * path.distance + params.exact_epsilon, params.exact_epsilon);
  if (h.hit && objects[h.object].albedo_refractor.a >= 0.5) return EXIT_REFRACTOR_AHEAD;
  hit = h.hit;
  meets = exit_from + path.exit_direction * h.t;
  return EXIT_TRUSTED;
}

#endif
