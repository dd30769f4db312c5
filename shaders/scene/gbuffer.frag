#version 460
// Opaque geometry seen from the camera: world normal (facing the viewer) and albedo (base colour,
// textured); MASK materials cut out where their coverage is below the cutoff.
#extension GL_GOOGLE_include_directive : require
#include "scene/scene.glsl"
SCENE_OBJECTS
SCENE_TEXTURES

layout(location = 0) in vec3 world_position;
layout(location = 1) in vec3 world_normal;
layout(location = 2) in float normal_distance;
layout(location = 3) flat in uint object_index;
layout(location = 4) in vec4 texcoords;
layout(location = 0) out vec4 out_normal;
layout(location = 1) out vec4 out_albedo;

void main() {
  ObjectData object = objects[object_index];
  vec4 base = base_color(object, texcoords);
  if (base.a < object.alpha_cutoff.y) discard;
  vec3 n = normalize(world_normal);
  out_normal = vec4(gl_FrontFacing ? n : -n, 1.0);
  out_albedo = vec4(base.rgb, 1.0);
}
