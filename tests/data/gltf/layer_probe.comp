#version 460
// The interface layers the exact paths read (scene/trace.glsl's layers_at) at two texture
// coordinates of a refractor, the middles of a 2 x 1 texture's texels (row y = 0: u = 0.25, row 1:
// u = 0.75): texel 0 holds the specular colour (rgb) and weight (a), texel 1 the coat (x), its
// roughness (y), the film's weight (z) and thickness in nm (w); texels 2 and 3 the object's own
// (the means image space takes). tests/surface_layers_test.cpp compares them with the factors and
// textures of tests/data/gltf/layered_pane.gltf.
#extension GL_GOOGLE_include_directive : require
#include "scene/scene.glsl"
SCENE_FRAME
SCENE_OBJECTS
#include "scene/trace.glsl"

layout(set = 0, binding = 3, rgba32f) uniform writeonly image2D values;
layout(push_constant) uniform Params {
  uint object;  // the refractor read
} params;

layout(local_size_x = 4, local_size_y = 2) in;

void main() {
  ivec2 at = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(at, imageSize(values)))) return;
  ObjectData layers = objects[params.object];
  if (at.x < 2) layers_at(params.object, vec4(at.y == 0 ? 0.25 : 0.75, 0.5, 0.0, 0.0), layers.specular, layers.layers, layers.film.x);
  imageStore(values, at, at.x % 2 == 0 ? layers.specular : vec4(layers.layers.xyz, layers.film.x));
}
