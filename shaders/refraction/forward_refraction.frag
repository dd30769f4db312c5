#version 460
// Forward refraction: the refraction shader runs for every rasterized front-face fragment of every
// refractor, hidden ones included (the paper's baseline).
#extension GL_GOOGLE_include_directive : require
#include "scene/scene.glsl"
SCENE_FRAME
SCENE_OBJECTS
#include "scene/textures.glsl"
layout(set = 0, binding = 3) uniform sampler2D background_tex;
layout(set = 0, binding = 4) uniform sampler2D depth_tex;
layout(set = 0, binding = 6) uniform sampler2D back_tex;
layout(set = 0, binding = 7, std430) buffer CounterBlock { uint counters[]; };

layout(push_constant) uniform Params {
  mat4 view_proj;
  vec4 eye;
  vec4 axis;  // passes/scene_draw.h's DrawPush; unused here
  uint distance_mode;
  uint search;  // refraction.glsl: search_steps() and search_tir_bounces()
  float search_distance;
  uint tir_counter;
  uint exact_max_interfaces;  // the rest of passes/refraction.h's RefractionPush, unused here
  float exact_epsilon;
  float hybrid_tolerance;
  uint exact_counters;
} params;

#include "refraction/refraction.glsl"

layout(location = 0) in vec3 world_position;
layout(location = 1) in vec3 world_normal;
layout(location = 2) in float normal_distance;
layout(location = 3) flat in uint object_index;
layout(location = 4) in vec4 texcoords;
layout(location = 5) in vec4 tangent;
layout(location = 0) out vec4 out_color;
#include "scene/tangent_frame.glsl"

void main() {
  vec2 uv = gl_FragCoord.xy * frame.sizes.zw;
  if (texture(depth_tex, uv).r < gl_FragCoord.z) discard;  // behind opaque geometry
  if (cut_out(objects[object_index], texcoords)) discard;   // MASK: no surface here
  float front_distance = distance(world_position, frame.camera_position.xyz);
  ObjectData object = objects[object_index];
  object.tint_transmission = tint_transmission_filtered(object, texcoords);  // per fragment, as the layers
  if (object.layer_factors.w > 0.0) {
    object = with_interface_layer_texels(object, interface_layer_texels_filtered(object, texcoords));
    if (object.surface_maps[4].row_u.w >= 0.0) object.coat_normal.yzw = coat_normal(object, normalize(world_normal), texcoords);
  }
  out_color = vec4(refracted_radiance(world_position, normalize(world_normal), front_distance, normal_distance, object_index, object, uv), 1.0);
}
