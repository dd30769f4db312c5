#version 460
// Vertex pulling from the scene's vertex buffer; one shader for every view (camera or light).
#extension GL_GOOGLE_include_directive : require
#include "scene/scene.glsl"
SCENE_VERTICES

// passes/scene_draw.h's DrawPush, one block for every scene shader: axis is the fragment shaders'.
layout(push_constant) uniform Draw {
  mat4 view_proj;
  vec4 eye;
  vec4 axis;
} draw;

layout(location = 0) out vec3 world_position;
layout(location = 1) out vec3 world_normal;
layout(location = 2) out float normal_distance;
layout(location = 3) flat out uint object_index;
layout(location = 4) out vec4 texcoords;
layout(location = 5) out vec4 tangent;

void main() {
  Vertex v = vertices[gl_VertexIndex];
  world_position = v.position_dn.xyz;
  world_normal = v.normal_object.xyz;
  normal_distance = v.position_dn.w;
  object_index = uint(v.normal_object.w);
  texcoords = v.texcoords;
  tangent = v.tangent;
  gl_Position = draw.view_proj * vec4(world_position, 1.0);
}
