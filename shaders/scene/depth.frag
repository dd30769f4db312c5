#version 460
// Depth only (shadow and light maps): the fixed-function depth write does the work; MASK
// materials cut out where their coverage is below the cutoff, so light passes there.
#extension GL_GOOGLE_include_directive : require
#include "scene/scene.glsl"
SCENE_OBJECTS
#include "scene/textures.glsl"

layout(location = 3) flat in uint object_index;
layout(location = 4) in vec4 texcoords;

void main() {
  if (cut_out(objects[object_index], texcoords)) discard;
}
