#ifndef CAUSTICA_TRACE_RAY_QUERY_GLSL
#define CAUSTICA_TRACE_RAY_QUERY_GLSL
// trace.glsl's tracer through ray queries: the top-level acceleration structure at binding 14,
// one instance per object whose custom index is the object's first triangle in TriangleBlock
// (engine/scene/acceleration.cpp). Only MASK materials' geometry is built non-opaque, so only it
// reaches confirm_if_covered.
#extension GL_EXT_ray_query : require
layout(set = 0, binding = 14) uniform accelerationStructureEXT scene_tlas;

void confirm_if_covered(rayQueryEXT query) {
  if (rayQueryGetIntersectionTypeEXT(query, false) != gl_RayQueryCandidateIntersectionTriangleEXT) return;
  uint triangle = uint(rayQueryGetIntersectionInstanceCustomIndexEXT(query, false) + rayQueryGetIntersectionPrimitiveIndexEXT(query, false));
  if (covered(triangle, rayQueryGetIntersectionBarycentricsEXT(query, false))) rayQueryConfirmIntersectionEXT(query);
}

SurfaceHit trace_surface(vec3 origin, vec3 direction, float t_min, uint instances) {
  rayQueryEXT query;
  rayQueryInitializeEXT(query, scene_tlas, gl_RayFlagsNoneEXT, instances, origin, t_min, direction, 1e30);
  while (rayQueryProceedEXT(query)) confirm_if_covered(query);
  if (rayQueryGetIntersectionTypeEXT(query, true) != gl_RayQueryCommittedIntersectionTriangleEXT) return missed_surface();
  uint triangle = uint(rayQueryGetIntersectionInstanceCustomIndexEXT(query, true) + rayQueryGetIntersectionPrimitiveIndexEXT(query, true));
  return surface_hit(triangle, rayQueryGetIntersectionBarycentricsEXT(query, true), rayQueryGetIntersectionTEXT(query, true));
}

bool occluded(vec3 origin, vec3 direction, float t_max) {
  rayQueryEXT query;
  rayQueryInitializeEXT(query, scene_tlas, gl_RayFlagsTerminateOnFirstHitEXT, 0xFFu, origin, 0.0, direction, t_max);
  while (rayQueryProceedEXT(query)) confirm_if_covered(query);
  return rayQueryGetIntersectionTypeEXT(query, true) != gl_RayQueryCommittedIntersectionNoneEXT;
}

#endif
