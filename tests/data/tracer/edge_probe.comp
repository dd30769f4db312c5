#version 460
// Rays aimed at the edges of a ball (the tracers' test, tests/tracer_test.cpp): invocation i takes
// triangle i mod N of the tracer's TriangleBlock and one of its edges, a point a hashed fraction
// along it (never exactly representable), and shoots a ray at it from outside. The ball is met at
// that point, so a watertight tracer never misses; a test that loses the rays through the crack
// between two triangles does. The
// same ray with the receivers' mask alone must pass the refractor, and as a shadow ray be occluded.
#extension GL_GOOGLE_include_directive : require
#include "scene/scene.glsl"
SCENE_FRAME
SCENE_OBJECTS
#include "scene/trace.glsl"

layout(set = 0, binding = 3, rgba32f) uniform writeonly image2D hits;
layout(set = 0, binding = 4, std430) buffer CounterBlock { uint counters[]; };
layout(push_constant) uniform Params {
  uint object;  // the convex refractor aimed at
} params;

layout(local_size_x = 8, local_size_y = 8) in;

uint hash(uint v) {
  v = v * 747796405u + 2891336453u;
  uint w = ((v >> ((v >> 28u) + 4u)) ^ v) * 277803737u;
  return (w >> 22u) ^ w;
}

float unit(uint v) { return float(hash(v) >> 8) / 16777216.0; }

void main() {
  ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = imageSize(hits);
  if (any(greaterThanEqual(texel, size))) return;
  uint i = uint(texel.y * size.x + texel.x);
  uint triangle = i % (uint(triangle_vertices.length()) / 3u);
  Vertex v0 = vertices[triangle_vertices[3u * triangle]];
  if (uint(v0.normal_object.w + 0.5) != params.object) {
    imageStore(hits, texel, vec4(-1.0));
    return;
  }
  vec3 corners[3] = vec3[3](v0.position_dn.xyz, vertices[triangle_vertices[3u * triangle + 1u]].position_dn.xyz,
                            vertices[triangle_vertices[3u * triangle + 2u]].position_dn.xyz);
  uint edge = (i / 7u) % 3u;
  vec3 target = mix(corners[edge], corners[(edge + 1u) % 3u], 0.001 + 0.998 * unit(i));
  // From outside, within about 17 degrees of the way in from the ball's centre: never grazing, so a
  // target within rounding of the edge (inside or outside it) is met at the edge.
  vec3 centre = 0.5 * (objects[params.object].bounds_min_thin.xyz + objects[params.object].bounds_max_spread.xyz);
  vec3 tilt = vec3(unit(i ^ 0x1234567u), unit(i ^ 0x7654321u), unit(i ^ 0x5a5a5a5u)) * 2.0 - 1.0;
  vec3 origin = target + 0.5 * normalize(normalize(target - centre) + 0.3 * tilt);
  float reach = length(target - origin);
  vec3 direction = (target - origin) / reach;
  atomicAdd(counters[0], 1u);
  SurfaceHit h = trace_surface(origin, direction, 0.0, CAUSTICA_ALL_INSTANCES);
  bool met = h.hit && h.t <= reach * 1.0001 + 1e-6;
  if (!met) atomicAdd(counters[1], 1u);
  SurfaceHit past = trace_surface(origin, direction, 0.0, CAUSTICA_RECEIVER_INSTANCES);
  if (past.hit && past.object == params.object) atomicAdd(counters[2], 1u);
  if (!occluded(origin, direction, reach * 1.0001 + 1e-6)) atomicAdd(counters[3], 1u);
  imageStore(hits, texel, vec4(met ? h.t / reach : 0.0, float(h.object), float(past.object), 1.0));
}
