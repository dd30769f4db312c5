#version 460
// Deferred refraction: one full-screen pass over the refractor buffers; each pixel is shaded once,
// for the nearest refractor surface only.
#extension GL_GOOGLE_include_directive : require
#include "scene/scene.glsl"
SCENE_FRAME
SCENE_OBJECTS
layout(set = 0, binding = 3) uniform sampler2D background_tex;
layout(set = 0, binding = 4) uniform sampler2D depth_tex;
layout(set = 0, binding = 5) uniform sampler2D front_tex;
layout(set = 0, binding = 6) uniform sampler2D back_tex;
layout(set = 0, binding = 7, std430) buffer CounterBlock { uint counters[]; };

layout(push_constant) uniform Params {
  uint distance_mode;
  uint search_steps;
  float search_distance;
  uint tir_counter;
} params;

#include "refraction/refraction.glsl"

layout(location = 0) out vec4 out_color;

void main() {
  vec2 uv = gl_FragCoord.xy * frame.sizes.zw;
  vec4 front = texelFetch(front_tex, ivec2(gl_FragCoord.xy), 0);
  vec3 background = texture(background_tex, uv).rgb;
  if (front.y <= 0.0) {
    out_color = vec4(background, 1.0);
    return;
  }
  vec3 eye = frame.camera_position.xyz;
  vec3 ray = normalize(world_from_depth(frame.inv_view_proj, uv, 0.5) - eye);
  vec3 p1 = eye + ray * front.y;
  float opaque_depth = texture(depth_tex, uv).r;
  vec2 ignored_uv;
  float front_depth;
  project_to_screen(p1, ignored_uv, front_depth);
  if (opaque_depth < front_depth) {  // an opaque surface in front of the refractor
    out_color = vec4(background, 1.0);
    return;
  }
  out_color = vec4(refracted_radiance(p1, unpack_normal(front.x), front.y, front.z, uint(front.w), uv), 1.0);
}
