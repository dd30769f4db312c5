#version 460
// Refractor surfaces, front or back faces depending on the pipeline's culling: the outward normal,
// the distance from the eye (along the axis for an orthographic view), d_N, and the object, in one
// rgba32f texel. MASK materials cut out where their coverage is below the cutoff. With
// REFRACTOR_TINT (the pass's optional tint port bound) also the surface's tint and transmission,
// and with REFRACTOR_LAYERS (its front_layers port) the texels of its interface layers, so that
// image space reads textured refractors per texel (tint_transmission_filtered,
// interface_layer_texels_filtered, and in z the coat's normal where its own map bends it:
// pack_coat_normal; an rg32ui target drops it).
#extension GL_GOOGLE_include_directive : require
#include "scene/scene.glsl"
SCENE_OBJECTS
#include "scene/textures.glsl"

layout(push_constant) uniform Draw {
  mat4 view_proj;
  vec4 eye;
  vec4 axis;  // w 1: orthographic (a directional light), distances along axis from the plane through eye
} draw;

layout(location = 0) in vec3 world_position;
layout(location = 1) in vec3 world_normal;
layout(location = 2) in float normal_distance;
layout(location = 3) flat in uint object_index;
layout(location = 4) in vec4 texcoords;
layout(location = 5) in vec4 tangent;
layout(location = 0) out vec4 out_surface;
#ifdef REFRACTOR_TINT
layout(location = 1) out vec4 out_tint_transmission;
#define LAYERS_LOCATION 2
#else
#define LAYERS_LOCATION 1
#endif
#ifdef REFRACTOR_LAYERS
#include "scene/tangent_frame.glsl"
layout(location = LAYERS_LOCATION) out uvec4 out_layers;
#endif

void main() {
  if (cut_out(objects[object_index], texcoords)) discard;  // MASK: no surface here
  float from_eye = draw.axis.w > 0.5 ? dot(world_position - draw.eye.xyz, draw.axis.xyz) : distance(world_position, draw.eye.xyz);
  out_surface = vec4(pack_normal(normalize(world_normal)), from_eye, normal_distance, float(object_index));
#ifdef REFRACTOR_TINT
  out_tint_transmission = tint_transmission_filtered(objects[object_index], texcoords);
#endif
#ifdef REFRACTOR_LAYERS
  out_layers = uvec4(interface_layer_texels_filtered(objects[object_index], texcoords),
                     pack_coat_normal(objects[object_index], coat_normal(objects[object_index], normalize(world_normal), texcoords)), 0u);
#endif
}
