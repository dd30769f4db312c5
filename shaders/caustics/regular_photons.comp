#version 460
// Regular caustic map: one photon per texel of an N x N grid over the light's image plane. Each
// photon that meets a refractor is refracted through two interfaces (as the camera's refraction),
// its landing point found in the light-view receiver depth, and its power added to the caustic map
// texel it lands in. Power is the flux of the photon's solid angle: intensity * (2 tan(fov/2) / N)^2
// * cos^3 of its angle to the light's axis, times the spot cone.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_atomic_float : require
#define REFRACTION_NO_CAMERA
#include "scene/scene.glsl"
SCENE_FRAME
SCENE_OBJECTS
layout(set = 0, binding = 3) uniform sampler2D front_tex;
layout(set = 0, binding = 4) uniform sampler2D back_tex;
layout(set = 0, binding = 5) uniform sampler2D receiver_depth;
layout(set = 0, binding = 6, r32f) uniform image2D caustic_map;
layout(set = 0, binding = 7, std430) buffer CounterBlock { uint counters[]; };
layout(set = 0, binding = 8, std430) buffer SumBlock { float sums[]; };  // the same buffer, float slots

layout(push_constant) uniform Params {
  uint distance_mode;
  uint search_steps;
  float search_distance;
  uint light;
  uint grid;
  uint fresnel;
  // Counter slots: processed, splatted, dropped_miss, dropped_tir (counts), then flux,
  // flux_entering, flux_dropped (sums).
  uint counter_slot[7];
  uint pad;
} params;

#include "refraction/refraction.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

// Per-workgroup totals, added to the counters once per group instead of once per photon. Sums
// are reduced without shared-memory float atomics (an optional feature few devices need here).
shared uint group_counts[4];
shared float photon_sums[3][64];

void main() {
  if (gl_LocalInvocationIndex < 4) group_counts[gl_LocalInvocationIndex] = 0u;
  float sums_here[3] = float[3](0.0, 0.0, 0.0);  // splatted, entering, dropped
  barrier();

  uvec2 id = gl_GlobalInvocationID.xy;
  if (all(lessThan(id, uvec2(params.grid)))) {
    LightData light = frame.lights[params.light];
    atomicAdd(group_counts[0], 1u);
    vec2 uv = (vec2(id) + 0.5) / float(params.grid);
    vec2 plane = (uv * 2.0 - 1.0) * light.clip.z;
    float cos_axis = inversesqrt(1.0 + dot(plane, plane));
    float texel = 2.0 * light.clip.z / float(params.grid);
    vec3 eye = light.position_type.xyz;
    vec3 direction = normalize(world_from_depth(light.inv_view_proj, uv, 0.5) - eye);
    // The spot's cone, with the soft edge of scene/lighting.frag.
    float cone = smoothstep(light.direction_cos.w, mix(light.direction_cos.w, 1.0, 0.02), dot(direction, light.direction_cos.xyz));
    float power = light.radiant.a * texel * texel * cos_axis * cos_axis * cos_axis * cone;

    vec4 front = texture(front_tex, uv);
    if (front.y <= 0.0 || power <= 0.0) {
      atomicAdd(group_counts[2], 1u);  // misses every refractor: direct light, not a caustic
    } else {
      sums_here[1] = power;
      ObjectData object = objects[uint(front.w)];
      vec3 p1 = eye + direction * front.y;
      TwoInterfaces path = refract_two_interfaces(light.view_proj, eye, p1, unpack_normal(front.x), front.y, front.z,
                                                  object.absorption_ior.a, uv);
      if (params.fresnel != 0u) power *= (1.0 - path.reflectance_in) * (path.tir ? 0.0 : path.transmit_out);
      // The caustic map holds one channel: the mean of the three absorption coefficients.
      power *= exp(-dot(object.absorption_ior.rgb, vec3(1.0 / 3.0)) * path.distance);
      vec2 landing;
      if (path.tir) {
        atomicAdd(group_counts[3], 1u);
        sums_here[2] = power;
      } else if (!march_depth(receiver_depth, light.view_proj, path.exit_point, path.exit_direction, landing)) {
        atomicAdd(group_counts[2], 1u);
        sums_here[2] = power;
      } else {
        ivec2 size = imageSize(caustic_map);
        imageAtomicAdd(caustic_map, clamp(ivec2(landing * vec2(size)), ivec2(0), size - 1), power);
        atomicAdd(group_counts[1], 1u);
        sums_here[0] = power;
      }
    }
  }

  for (int k = 0; k < 3; ++k) photon_sums[k][gl_LocalInvocationIndex] = sums_here[k];
  barrier();
  for (uint stride = 32u; stride > 0u; stride >>= 1) {
    if (gl_LocalInvocationIndex < stride) {
      for (int k = 0; k < 3; ++k) photon_sums[k][gl_LocalInvocationIndex] += photon_sums[k][gl_LocalInvocationIndex + stride];
    }
    barrier();
  }
  if (gl_LocalInvocationIndex < 4) atomicAdd(counters[params.counter_slot[gl_LocalInvocationIndex]], group_counts[gl_LocalInvocationIndex]);
  if (gl_LocalInvocationIndex < 3) atomicAdd(sums[params.counter_slot[4 + gl_LocalInvocationIndex]], photon_sums[gl_LocalInvocationIndex][0]);
}
