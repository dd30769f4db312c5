#ifndef CAUSTICA_TRACE_GLSL
#define CAUSTICA_TRACE_GLSL
// The scene's exact geometry, for the passes that trace exact paths (passes/refraction.h,
// TracedScene): trace_surface (the nearest hit) and occluded (a shadow ray), by one of two tracers
// that the plan chooses (graph::Tracer): ray queries (GL_EXT_ray_query; binding 14 the top-level
// acceleration structure, engine/scene/acceleration.cpp), or, with CAUSTICA_COMPUTE_TRACER, a BVH
// walked by this shader (binding 14 the BvhBlock of engine/scene/bvh.h; scene/trace_bvh.glsl). Both
// bind at 15 the vertex indices of every triangle in their own order. Needs SCENE_OBJECTS-style
// bindings 0 to 2 in the including shader, and the scene's textures (set 1): a MASK material's
// surface is passed by where its coverage is below the cutoff.
#include "scene/scene.glsl"
#include "scene/textures.glsl"
SCENE_VERTICES
layout(set = 0, binding = 15, std430) readonly buffer TriangleBlock {
  uint triangle_vertices[];
};

struct SurfaceHit {
  bool hit;
  float t;
  vec3 normal;  // interpolated, unit
  uint object;
  vec4 texcoords;  // interpolated: TEXCOORD_0 in xy, TEXCOORD_1 in zw
  uint triangle;   // in TriangleBlock's order
  vec2 barycentrics;  // v1's and v2's weights
};

// Whether triangle `triangle` (of TriangleBlock) is there at barycentrics `b` (v1's and v2's
// weights): false where its MASK material cuts it out.
bool covered(uint triangle, vec2 b) {
  Vertex v0 = vertices[triangle_vertices[3u * triangle]];
  Vertex v1 = vertices[triangle_vertices[3u * triangle + 1u]];
  Vertex v2 = vertices[triangle_vertices[3u * triangle + 2u]];
  vec4 texcoords = (1.0 - b.x - b.y) * v0.texcoords + b.x * v1.texcoords + b.y * v2.texcoords;
  return !cut_out_at_full_resolution(objects[uint(v0.normal_object.w + 0.5)], texcoords);
}

// The hit at distance `t` on triangle `triangle` at barycentrics `b`.
SurfaceHit surface_hit(uint triangle, vec2 b, float t) {
  Vertex v0 = vertices[triangle_vertices[3u * triangle]];
  Vertex v1 = vertices[triangle_vertices[3u * triangle + 1u]];
  Vertex v2 = vertices[triangle_vertices[3u * triangle + 2u]];
  SurfaceHit h;
  h.hit = true;
  h.t = t;
  vec3 n = (1.0 - b.x - b.y) * v0.normal_object.xyz + b.x * v1.normal_object.xyz + b.y * v2.normal_object.xyz;
  vec3 geometric = cross(v1.position_dn.xyz - v0.position_dn.xyz, v2.position_dn.xyz - v0.position_dn.xyz);
  h.normal = dot(n, n) > 1e-20 ? normalize(n) : normalize(geometric);
  h.object = uint(v0.normal_object.w + 0.5);
  h.texcoords = (1.0 - b.x - b.y) * v0.texcoords + b.x * v1.texcoords + b.y * v2.texcoords;
  h.triangle = triangle;
  h.barycentrics = b;
  return h;
}

SurfaceHit missed_surface() {
  SurfaceHit h;
  h.hit = false;
  h.t = 0.0;
  h.normal = vec3(0.0, 1.0, 0.0);
  h.object = 0u;
  h.texcoords = vec4(0.0);
  h.triangle = 0u;
  h.barycentrics = vec2(0.0);
  return h;
}

// trace_surface(origin, direction, t_min, instances): the nearest surface along a ray among the
// instances of mask `instances` (scene_types.h) at least t_min away; occluded(origin, direction,
// t_max): whether anything lies on the segment from origin to origin + direction * t_max.
#ifdef CAUSTICA_COMPUTE_TRACER
#include "scene/trace_bvh.glsl"
#else
#include "scene/trace_ray_query.glsl"
#endif

// The surface that the exit ray of an image-space path through refractor `own` meets. The estimated
// exit point `origin` may lie inside the surface it leaves, by up to `slack` along the ray: a first
// hit that leaves `own` within it is that surface, and the ray goes on from there (`origin` becomes
// where the returned hit's distance is measured from). A ray that leaves a convex solid cannot meet
// it again: it asks for the receivers alone (CAUSTICA_RECEIVER_INSTANCES), which passes by every
// refractor's structure, and the caller checks the other refractors' bounds. One call site of
// trace_surface, in a loop of at most two rounds, because every inlined copy of it lengthens
// lavapipe's shader compile, which under the sanitizers happens inside the first frame's time limit.
SurfaceHit trace_exit_ray(inout vec3 origin, vec3 direction, uint own, float slack, float t_min) {
  uint instances = convex_solid(objects[own]) ? CAUSTICA_RECEIVER_INSTANCES : CAUSTICA_ALL_INSTANCES;
  SurfaceHit h;
  for (bool passing = true; passing;) {
    h = trace_surface(origin, direction, t_min, instances);
    passing = h.hit && h.object == own && dot(h.normal, direction) > 0.0 && h.t <= slack;
    if (passing) {
      origin += direction * h.t;
      slack = -1.0;  // once
    }
  }
  return h;
}

// A refractor's transmission roughness where a ray meets it: per texel where its material has a
// metallic-roughness texture (roughnessFactor times its green channel, at the full-resolution
// level, as the Embree references read it); the image-space methods take the object's mean
// (transmission_roughness in refraction/refraction.glsl), which is what metallic_roughness.w holds.
float roughness_at(SurfaceHit h) {
  ObjectData object = objects[h.object];
  TextureSlot map = object.metallic_roughness_map;
  if (object.metallic_roughness.w <= 0.0 || map.row_u.w < 0.0) return object.metallic_roughness.w;
  return object.metallic_roughness.y * sample_slot_at_full_resolution(map, h.texcoords).g;
}

// A refractor's interface layers where a ray meets it (the fields of ObjectData that
// interface.glsl reads: specular, layers.xyz, film.x), for an object with layer textures
// (layer_factors.w > 0): each factor times its texture at the full-resolution level, as the Embree
// references read them; the image-space methods take the textures' means, which the object holds.
// Read from the objects' buffer rather than from a copy of the object, and written into the
// caller's: passing the whole ObjectData in and out lengthened the exact kernels' compile on
// lavapipe by a quarter.
float layer_texel(uint object, int map, vec4 texcoords, int channel) {
  TextureSlot slot = objects[object].layer_maps[map];
  return slot.row_u.w >= 0.0 ? sample_slot_at_full_resolution(slot, texcoords)[channel] : 1.0;
}
void layers_at(uint object, vec4 texcoords, inout vec4 specular, inout vec4 layers, inout float film_thickness) {
  TextureSlot color = objects[object].layer_maps[1];
  vec3 tint = color.row_u.w >= 0.0 ? sample_slot_at_full_resolution(color, texcoords).rgb : vec3(1.0);
  vec4 factors = objects[object].specular_factors;
  specular = vec4(factors.rgb * tint, factors.a * layer_texel(object, 0, texcoords, 3));
  layers.xyz = objects[object].layer_factors.xyz *
               vec3(layer_texel(object, 2, texcoords, 0), layer_texel(object, 3, texcoords, 1), layer_texel(object, 4, texcoords, 0));
  vec4 film = objects[object].film;
  film_thickness = objects[object].layer_maps[5].row_u.w >= 0.0 ? mix(film.y, film.z, layer_texel(object, 5, texcoords, 1)) : film.z;
}

// KHR_materials_clearcoat's normal where a ray meets a refractor whose coat has its own normal map
// (clearcoatNormalTexture, ObjectData::surface_maps[4]): the hit's outward normal bent by the map in
// the triangle's tangent frame, turned to the side of `facing`; `facing` where the object has none.
// The frame is the vertices' TANGENT, or without one the triangle's direction of increasing u (as
// the G-buffer derives it from screen derivatives, and the references from the triangle).
vec3 coat_normal_at(SurfaceHit h, vec3 facing) {
  TextureSlot map = objects[h.object].surface_maps[4];
  if (map.row_u.w < 0.0) return facing;
  Vertex v0 = vertices[triangle_vertices[3u * h.triangle]];
  Vertex v1 = vertices[triangle_vertices[3u * h.triangle + 1u]];
  Vertex v2 = vertices[triangle_vertices[3u * h.triangle + 2u]];
  vec2 b = h.barycentrics;
  vec3 n = h.normal;
  vec4 tangent = (1.0 - b.x - b.y) * v0.tangent + b.x * v1.tangent + b.y * v2.tangent;
  vec3 t = tangent.xyz - n * dot(n, tangent.xyz);
  float sign = tangent.w < 0.0 ? -1.0 : 1.0;
  if (v0.tangent.w == 0.0 || dot(t, t) <= 1e-20) {
    vec2 uv0 = slot_uv(map, v0.texcoords), d1 = slot_uv(map, v1.texcoords) - uv0, d2 = slot_uv(map, v2.texcoords) - uv0;
    float det = d1.x * d2.y - d2.x * d1.y;
    vec3 e1 = v1.position_dn.xyz - v0.position_dn.xyz, e2 = v2.position_dn.xyz - v0.position_dn.xyz;
    t = det != 0.0 ? (e1 * d2.y - e2 * d1.y) / det : vec3(0.0);
    t -= n * dot(n, t);
    sign = 1.0;
  }
  if (dot(t, t) <= 1e-20) return facing;
  t = normalize(t);
  vec3 m = sample_slot_at_full_resolution(map, h.texcoords).xyz * 2.0 - 1.0;
  m = normalize(vec3(m.xy * objects[h.object].coat_normal.x, m.z));
  vec3 coat = normalize(t * m.x + sign * cross(n, t) * m.y + n * m.z);
  return dot(n, facing) < 0.0 ? -coat : coat;
}

// A refractor's tint (rgb) and transmission (a) where a ray meets it: per texel where its material
// has a base colour or a transmission texture (the factor times the texture, at the full-resolution
// level, as the Embree references read them; the image-space methods read the refractor buffers'
// front_tint, drawn with the textures filtered).
vec4 tint_transmission_at(SurfaceHit h) {
  ObjectData object = objects[h.object];
  if (!transmittance_varies(object)) return object.tint_transmission;
  vec4 base_color = object.base_color.row_u.w >= 0.0 ? sample_slot_at_full_resolution(object.base_color, h.texcoords) : vec4(1.0);
  float transmission =
      object.transmission_map.row_u.w >= 0.0 ? sample_slot_at_full_resolution(object.transmission_map, h.texcoords).r : 1.0;
  return tint_transmission_from(object, base_color, transmission);
}

#endif
