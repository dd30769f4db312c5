#ifndef CAUSTICA_TRACE_BVH_GLSL
#define CAUSTICA_TRACE_BVH_GLSL
// trace.glsl's compute tracer, for devices without ray queries (and where it is the faster): a
// stack walk of the binary BVH that engine/scene/bvh.h builds and lays out (its comment has the
// words' layout), both children's boxes tested from their parent, the nearer visited first, a
// subtree skipped where none of its instance masks is asked for; triangles by the watertight test
// of Woop, Benthin and Wald (2013), so that a ray through an edge or a vertex shared by two
// triangles meets one of them.
layout(set = 0, binding = 14, std430) readonly buffer BvhBlock { vec4 bvh[]; };

const uint BVH_MASKED_MATERIAL = 256u;  // bvh.h's kBvhMaskedMaterial
const float BVH_FAR = 1e30;

// A ray set up once for its boxes (the inverse direction, every component finite) and its
// triangles (Woop et al.'s shear: the largest component's axis becomes z; as a matrix, so that
// no component is indexed by a variable).
struct BvhRay {
  vec3 origin;
  vec3 inverse_direction;
  mat3 shear;
};

BvhRay bvh_ray(vec3 origin, vec3 direction) {
  BvhRay r;
  r.origin = origin;
  r.inverse_direction = slab_inverse(direction);
  vec3 a = abs(direction);
  // The permuted axes (kx, ky, kz) as unit vectors, kx and ky swapped for a negative kz so that
  // the triangles' winding is kept.
  vec3 ez = a.x > a.y ? (a.x > a.z ? vec3(1, 0, 0) : vec3(0, 0, 1)) : (a.y > a.z ? vec3(0, 1, 0) : vec3(0, 0, 1));
  vec3 ex = ez.yzx, ey = ez.zxy;
  float dz = dot(direction, ez);
  if (dz < 0.0) {
    vec3 swap = ex;
    ex = ey;
    ey = swap;
  }
  float sx = dot(direction, ex) / dz, sy = dot(direction, ey) / dz, sz = 1.0 / dz;
  // Rows: ex - sx ez, ey - sy ez, sz ez (GLSL's matrices are built by columns).
  r.shear = transpose(mat3(ex - sx * ez, ey - sy * ez, sz * ez));
  return r;
}

// Where the ray enters the box within [t_min, t_max], or BVH_FAR past it. The far side is widened
// by a few ulps, so that rounding cannot let a ray that grazes a box miss it (Ize 2013).
float bvh_box_entry(BvhRay r, vec3 lo, vec3 hi, float t_min, float t_max) {
  vec3 t0 = (lo - r.origin) * r.inverse_direction, t1 = (hi - r.origin) * r.inverse_direction;
  vec3 near3 = min(t0, t1), far3 = max(t0, t1);
  float near = max(max(near3.x, near3.y), max(near3.z, t_min));
  float far = min(min(far3.x, far3.y), far3.z) * 1.0000004;
  return near <= min(far, t_max) ? near : BVH_FAR;
}

// Triangle `triangle`'s hit within [t_min, t_max]: its distance in x and barycentrics (v1's and
// v2's weights) in yz, or x < 0 where the ray passes it. The edge functions are `precise` (no
// fused multiply-add), so an edge shared by two triangles gives each the same value.
vec3 bvh_triangle_hit(BvhRay r, uint first_word, uint triangle, float t_min, float t_max) {
  uint w = first_word + 3u * triangle;
  vec3 a = r.shear * (bvh[w].xyz - r.origin), b = r.shear * (bvh[w + 1u].xyz - r.origin), c = r.shear * (bvh[w + 2u].xyz - r.origin);
  precise float u = c.x * b.y - c.y * b.x;
  precise float v = a.x * c.y - a.y * c.x;
  precise float s = b.x * a.y - b.y * a.x;
  if ((u < 0.0 || v < 0.0 || s < 0.0) && (u > 0.0 || v > 0.0 || s > 0.0)) return vec3(-1.0);
  float det = u + v + s;
  if (det == 0.0) return vec3(-1.0);
  float t = (u * a.z + v * b.z + s * c.z) / det;
  if (!(t >= t_min && t <= t_max)) return vec3(-1.0);
  return vec3(t, v / det, s / det);
}

// The BVH walk both queries share: the nearest hit among the triangles of mask `instances` within
// [t_min, t_max] (its triangle, or 0xFFFFFFFF, and in `found` its distance and barycentrics), or
// with `any_hit` the first found. A node's nearer child is visited next and its farther pushed, with
// the distance at which the ray enters it, so that it is passed by once a nearer hit is found. One
// call site of bvh_triangle_hit, for the shader's size.
uint bvh_walk(vec3 origin, vec3 direction, float t_min, float t_max, uint instances, bool any_hit, out vec3 found) {
  BvhRay r = bvh_ray(origin, direction);
  uint first_word = floatBitsToUint(bvh[0].x);
  uint best = 0xFFFFFFFFu;
  found = vec3(t_max, 0.0, 0.0);
  uint stack[CAUSTICA_BVH_MAX_DEPTH];  // children, as 1 + 2 * (node * 2 + which): their first word
  float entry[CAUSTICA_BVH_MAX_DEPTH];
  uint depth = 0u;
  uint child = 0u;  // the child word to visit; 0: node 0, the root
  for (;;) {
    uint link = 0u, count = 0u;
    if (child != 0u) {
      link = floatBitsToUint(bvh[child].w);
      count = floatBitsToUint(bvh[child + 1u].w) >> 8;
    }
    child = 0u;
    if (count == 0u) {
      uint at = 1u + 4u * link;
      uint mask0 = floatBitsToUint(bvh[at + 1u].w) & instances & 0xFFu, mask1 = floatBitsToUint(bvh[at + 3u].w) & instances & 0xFFu;
      float near0 = mask0 != 0u ? bvh_box_entry(r, bvh[at].xyz, bvh[at + 1u].xyz, t_min, found.x) : BVH_FAR;
      float near1 = mask1 != 0u ? bvh_box_entry(r, bvh[at + 2u].xyz, bvh[at + 3u].xyz, t_min, found.x) : BVH_FAR;
      bool second_nearer = near1 < near0;
      float near = min(near0, near1), far = max(near0, near1);
      if (near < BVH_FAR) child = second_nearer ? at + 2u : at;
      if (far < BVH_FAR) {
        stack[depth] = second_nearer ? at : at + 2u;
        entry[depth++] = far;
      }
    } else {
      for (uint triangle = link; triangle < link + count; ++triangle) {
        uint flags = floatBitsToUint(bvh[first_word + 3u * triangle].w);
        if ((flags & instances & 0xFFu) == 0u) continue;
        vec3 hit = bvh_triangle_hit(r, first_word, triangle, t_min, found.x);
        if (hit.x < 0.0 || ((flags & BVH_MASKED_MATERIAL) != 0u && !covered(triangle, hit.yz))) continue;
        found = hit;
        best = triangle;
        if (any_hit) return best;
      }
    }
    // Nothing to go down to: the nearest pushed child that a hit found since has not passed.
    while (child == 0u && depth > 0u) {
      --depth;
      if (entry[depth] <= found.x) child = stack[depth];
    }
    if (child == 0u) break;
  }
  return best;
}

SurfaceHit trace_surface(vec3 origin, vec3 direction, float t_min, uint instances) {
  vec3 found;
  uint triangle = bvh_walk(origin, direction, t_min, BVH_FAR, instances, false, found);
  return triangle == 0xFFFFFFFFu ? missed_surface() : surface_hit(triangle, found.yz, found.x);
}

bool occluded(vec3 origin, vec3 direction, float t_max) {
  vec3 found;
  return bvh_walk(origin, direction, 0.0, t_max, CAUSTICA_ALL_INSTANCES, true, found) != 0xFFFFFFFFu;
}

#endif
