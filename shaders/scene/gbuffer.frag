#version 460
// Opaque geometry seen from the camera: world normal (facing the viewer) and albedo.
#extension GL_GOOGLE_include_directive : require
#include "scene/scene.glsl"
SCENE_OBJECTS

layout(location = 0) in vec3 world_position;
layout(location = 1) in vec3 world_normal;
layout(location = 2) in float normal_distance;
layout(location = 3) flat in uint object_index;
layout(location = 0) out vec4 out_normal;
layout(location = 1) out vec4 out_albedo;

void main() {
  vec3 n = normalize(world_normal);
  out_normal = vec4(gl_FrontFacing ? n : -n, 1.0);
  out_albedo = vec4(objects[object_index].albedo_refractor.rgb, 1.0);
}
