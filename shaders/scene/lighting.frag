#version 460
// Direct lighting of the G-buffer: every light with its inverse-square falloff and spot cone through
// the surface's BRDF (scene/surface.glsl; with MATERIAL, glTF's sheen, anisotropy, diffuse
// transmission, specular, index, thin film and clear coat from the material target and the objects (with LAYERS their
// textures' texels from the layers target), and the light
// translucent surfaces pass on), each shadowed through its shadow map where it has one (3x3 PCF; a point light's
// six cube faces) and adding its caustic map where one is bound, plus ambient sky light
// (occluded by the emission target's alpha) and emitted light. Sky where empty.
#extension GL_GOOGLE_include_directive : require
#include "scene/scene.glsl"
#ifdef MATERIAL
#define SURFACE_LAYERS 1
#endif
#include "scene/surface.glsl"
SCENE_FRAME
layout(set = 0, binding = 1) uniform sampler2D depth_tex;
layout(set = 0, binding = 2) uniform sampler2D normal_tex;
layout(set = 0, binding = 3) uniform sampler2D albedo_tex;
// Light i's shadow map where bit i of params.shadowed is set: one layer, or a point light's six faces.
// SHADOWS and CAUSTICS are the arrays' lengths: as far as the pass binds elements (lighting.cpp).
#ifdef SHADOWS
layout(set = 0, binding = 4) uniform sampler2DArray shadow_maps[SHADOWS];
#endif
// Caustic view i's map where bit i of params.caustic_lights is set: flux per texel in its image
// plane, a layer per colour channel; where bit i of params.caustic_depths is, what that view sees
// without refractors (the receiver test). Unset elements hold another view's (unread).
#ifdef CAUSTICS
layout(set = 0, binding = 5) uniform sampler2DArray caustic_maps[CAUSTICS];
layout(set = 0, binding = 6) uniform sampler2D caustic_depths[CAUSTICS];
#endif
#ifdef EMISSION
layout(set = 0, binding = 7) uniform sampler2D emission_tex;
#endif
// What the G-buffer's material and layers targets hold (scene/material_targets.glsl): the
// anisotropy, the clear coat's normal and the object whose extensions' values the surface takes;
// with LAYERS, the texels of those extensions that textures set.
#ifdef MATERIAL
#include "scene/material_targets.glsl"
layout(set = 0, binding = 8) uniform sampler2D material_tex;
#ifdef LAYERS
layout(set = 0, binding = 11) uniform usampler2D layers_tex;
#endif
layout(set = 0, binding = 9, std430) readonly buffer ObjectBlock {
  ObjectData objects[];
};
// Patches of the translucent surfaces (scene/translucent_samples.h), frame.translucent_samples of them.
layout(set = 0, binding = 10, std430) readonly buffer TranslucentBlock {
  TranslucentSample translucent[];
};
#endif

layout(push_constant) uniform Params {
  float shadow_bias;
  uint shadowed;        // bit i: light i has a shadow map
  uint caustic_lights;  // bit i: caustic view i has a caustic map
  uint caustic_depths;  // bit i: and its receiver depth
}
params;

layout(location = 0) out vec4 out_color;

// Distance along the light's axis for a depth-buffer value of its projection.
float linear_depth(LightData light, float depth) {
  float n = light.clip.x, f = light.clip.y;
  if (light_is_directional(light)) return n + depth * (f - n);  // orthographic: depth is linear
  return n * f / (f - depth * (f - n));
}

// How far a receiver at depth z (along the light's axis) lies in front of what it sees in a light-view
// depth map before it counts as behind it: the graph's shadow_bias, plus what the map's own depth
// values cannot tell apart at z. A perspective depth d = f (z - n) / (z (f - n)) changes by
// dz n f / (z^2 (f - n)), and a d32f value near 1 resolves 2^-24; 16 of those steps cover the
// rasterizer's interpolation. Without it a scene far larger than the bias, or far from the
// origin (a model at z = -1000, 80 units across), shadows its own floor in streaks.
float depth_bias(LightData light, float z) {
  float n = light.clip.x, f = light.clip.y;
  float step = light_is_directional(light) ? (f - n) : z * z * (f - n) / (n * f);
  return params.shadow_bias + step * exp2(-20.0);
}

// A texel's side at p in a light-view map of `size` texels: the view's side over its texels, times
// the distance for a perspective one; and the cosine of the light's angle to the normal n.
// `tan_half`: the view's (clip.z), or a point light's cube face's (clip.w).
float light_texel(LightData light, float tan_half, vec3 p, vec3 n, float size, out float cos_theta) {
  float d2;
  cos_theta = clamp(dot(n, toward_light(light, p, d2)), 0.0, 1.0);
  return 2.0 * tan_half * (light_is_directional(light) ? 1.0 : sqrt(d2)) / size;
}

// Where a receiver at p with normal n looks itself up in a light-view depth map whose texel at p is
// `texel` wide: moved off the surface along its normal by two texels, scaled by the sine of the
// light's angle to the normal. At grazing light one texel of the map spans a long stretch of the
// surface whose depth changes across it, and without the offset the surface shadows itself in
// stripes (shadow acne); a constant bias alone would have to grow large enough to detach every
// shadow from its caster.
vec3 normal_offset(vec3 p, vec3 n, float texel, float cos_theta) {
  return p + n * (2.0 * texel * sqrt(1.0 - cos_theta * cos_theta));
}

#ifdef SHADOWS
float shadow_factor(uint i, LightData light, vec3 p, vec3 n) {
  // The 3x3 filter compares with the neighbouring texels, which see the receiver one texel further
  // along; on a surface the light meets at angle theta its depth changes by texel tan(theta) there:
  // a bias in units of the map's texels, so that it holds at any scale of the scene.
  vec2 size = vec2(textureSize(shadow_maps[i], 0).xy);
  float cos_theta;
  float texel = light_texel(light, light_is_point(light) ? light.clip.w : light.clip.z, p, n, size.x, cos_theta);
  float slope_bias = texel * min(sqrt(1.0 - cos_theta * cos_theta) / max(cos_theta, 1e-3), 8.0);
  p = normal_offset(p, n, texel, cos_theta);
  mat4 view_proj = light.view_proj;
  float layer = 0.0;
  if (light_is_point(light)) {
    uint face = cube_face(p - light.position_type.xyz);
    view_proj = frame.light_faces[6u * i + face];
    layer = float(face);
  }
  vec4 clip = view_proj * vec4(p, 1.0);
  if (clip.w <= 0.0) return 0.0;
  vec3 ndc = clip.xyz / clip.w;
  vec2 uv = ndc.xy * 0.5 + 0.5;
  // Outside a spot's frustum is outside its cone; outside a directional light's prism nothing that
  // casts a shadow lies (it is fitted around the scene); a point light's faces cover every direction.
  if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) return light_is_directional(light) ? 1.0 : 0.0;
  // The bias is a distance: a fixed bias in depth-buffer units would grow with the square of the
  // distance from the light.
  float z = linear_depth(light, ndc.z);
  float receiver = z - depth_bias(light, z) - slope_bias;
  float lit = 0.0;
  for (int y = -1; y <= 1; ++y)
    for (int x = -1; x <= 1; ++x)
      lit += receiver <= linear_depth(light, texture(shadow_maps[i], vec3(uv + vec2(x, y) / size, layer)).r) ? 1.0 : 0.0;
  return lit / 9.0;
}
#endif

// Irradiance from caustic view i's map (`light` as that view sees it, FrameData::caustic_lights;
// a point light's cube faces each hold the photons of their own directions, so that their maps
// add up where they overlap): a texel's flux spread over the receiver area its solid
// angle covers at this point, dw r^2 / cos(theta); with its receivers' depth, only on the surface
// the light sees first (the receiver depth test, like a shadow map).
#ifdef CAUSTICS
vec3 caustic_irradiance(uint i, LightData light, vec3 p, vec3 n) {
  bool receiver_test = (params.caustic_depths & (1u << i)) != 0u;
  float cos_light;
  float size_x = float(receiver_test ? textureSize(caustic_depths[i], 0).x : textureSize(caustic_maps[i], 0).x);
  float texel = light_texel(light, light.clip.z, p, n, size_x, cos_light);
  vec4 clip = light.view_proj * vec4(normal_offset(p, n, texel, cos_light), 1.0);
  if (clip.w <= 0.0) return vec3(0.0);
  vec3 ndc = clip.xyz / clip.w;
  vec2 uv = ndc.xy * 0.5 + 0.5;
  if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) return vec3(0.0);
  float z = linear_depth(light, ndc.z);
  if (receiver_test && z - depth_bias(light, z) > linear_depth(light, texture(caustic_depths[i], uv).r)) return vec3(0.0);
  vec2 size = vec2(textureSize(caustic_maps[i], 0).xy);
  float r2;
  float cos_theta = max(dot(n, toward_light(light, p, r2)), 0.0);
  vec3 flux =
      vec3(texture(caustic_maps[i], vec3(uv, 0.0)).r, texture(caustic_maps[i], vec3(uv, 1.0)).r, texture(caustic_maps[i], vec3(uv, 2.0)).r);
  // The area a texel covers across the light's direction: its share of a directional light's square,
  // or its solid angle times r^2.
  float texel_area = 4.0 * light.clip.z * light.clip.z / (size.x * size.y);
  if (!light_is_directional(light)) {
    vec2 plane = (uv * 2.0 - 1.0) * light.clip.z;
    float cos_axis = inversesqrt(1.0 + dot(plane, plane));
    texel_area *= cos_axis * cos_axis * cos_axis * r2;
  }
  return light.radiant.rgb / max(light.radiant.a, 1e-20) * flux * cos_theta / texel_area;
}
#endif

#ifdef MATERIAL
// The light that translucent surfaces (KHR_materials_diffuse_transmission) pass on to p, which
// faces n, from their patches (object `self`'s own left out): each patch of area A at q, lit from
// one side with irradiance E, sends (1 - metallic) factor colour E / pi from its other side, and
// p on that side receives it with cos_q cos_p A / (r^2 + A / pi): a small patch's r^2 falloff, and
// no more than a whole plane's pi L where p comes close. Neither the patch's own shadow nor
// anything between the patch and p is seen (docs/gltf.md, "Diffuse transmission").
vec3 translucent_irradiance(vec3 p, vec3 n, uint self) {
  vec3 irradiance = vec3(0.0);
  for (uint i = 0; i < frame.light_count; ++i) {
    LightData light = frame.lights[i];
    for (uint k = 0; k < frame.translucent_samples; ++k) {
      TranslucentSample patch_k = translucent[k];
      vec3 q = patch_k.position_area.xyz, n_q = patch_k.normal_object.xyz, to_p = p - q;
      float r2 = max(dot(to_p, to_p), 1e-12), area = patch_k.position_area.w;
      vec3 w = to_p * inversesqrt(r2);
      float cos_p = -dot(n, w), cos_q = dot(n_q, w), d2;
      vec3 l = toward_light(light, q, d2);
      float n_l = dot(n_q, l);
      // Only onto p on the patch's far side from the light, and not onto its own object.
      if (cos_p <= 0.0 || n_l * cos_q >= 0.0 || uint(patch_k.normal_object.w) == self) continue;
      irradiance += patch_k.passed.rgb * light.radiant.rgb * (abs(n_l) / d2 * spot_cone(light, -l) * abs(cos_q) * cos_p * area /
                                                              (r2 + area / PI));
    }
  }
  return irradiance;
}
#endif

#ifdef MATERIAL
// The sheen's albedo table at roughness r: the object's own where no texture sets the roughness,
// else interpolated between the frame's rows (FrameData::sheen_albedo_rows).
void set_sheen_albedo(inout Surface s, ObjectData object) {
  s.sheen_albedo = object.sheen_albedo;
  if (object.surface_maps[1].row_u.w < 0.0) return;
  float x = clamp(s.sheen_roughness, 0.0, 1.0) * 15.0;
  int row = min(int(x), 14);
  for (int k = 0; k < 4; ++k) s.sheen_albedo[k] = mix(frame.sheen_albedo_rows[4 * row + k], frame.sheen_albedo_rows[4 * row + 4 + k], x - float(row));
}

// The surface's extensions from the material target (and the layers target's texels, with LAYERS;
// the objects' means without it).
void set_extensions(inout Surface s, vec4 material) {
  ObjectData object = objects[uint(material.w)];
  s.anisotropy = material.y;
  s.anisotropy_t = s.anisotropy > 0.0 ? unpack_direction(material.x) : vec3(0.0);
  if (material.z >= 0.0) s.coat_n = unpack_direction(material.z);
  float f0_root = (object.absorption_ior.a - 1.0) / (object.absorption_ior.a + 1.0);
  s.dielectric_f0 = f0_root * f0_root;
  s.film_ior = object.layers.w;
#ifdef LAYERS
  uvec4 texels = texelFetch(layers_tex, ivec2(gl_FragCoord.xy), 0);
  vec4 sheen = object.sheen_factors * unpack_colour_texel(texels.x);
  vec4 passed = object.diffuse_transmission_factors * unpack_colour_texel(texels.y);
  vec4 coat_film = unpackUnorm4x8(texels.w);
  s.sheen_color = sheen.rgb;
  s.sheen_roughness = sheen.a;
  s.transmission_color = passed.rgb;
  s.transmission = passed.a;
  s.specular = object.specular_factors * unpack_colour_texel(texels.z);
  s.coat = object.layer_factors.x * coat_film.r;
  s.coat_roughness = object.layer_factors.y * coat_film.g;
  s.film = object.layer_factors.z * coat_film.b;
  s.film_thickness = object.layer_maps[5].row_u.w >= 0.0 ? mix(object.film.y, object.film.z, coat_film.a) : object.film.x;
#else
  s.sheen_color = object.sheen.rgb;
  s.sheen_roughness = object.sheen.a;
  s.transmission_color = object.diffuse_transmission.rgb;
  s.transmission = object.diffuse_transmission.a;
  s.specular = object.specular;
  s.coat = object.layers.x;
  s.coat_roughness = object.layers.y;
  s.film = object.layers.z;
  s.film_thickness = object.film.x;
#endif
  set_sheen_albedo(s, object);
}
#endif

void main() {
  vec2 uv = gl_FragCoord.xy * frame.sizes.zw;
  float depth = texture(depth_tex, uv).r;
  if (depth >= 1.0) {
    out_color = vec4(frame.sky_ambient.rgb, 1.0);
    return;
  }
  vec3 p = world_from_depth(frame.inv_view_proj, uv, depth);
  vec4 normal_roughness = texture(normal_tex, uv), albedo_metallic = texture(albedo_tex, uv);
  Surface s = plain_surface(normalize(normal_roughness.xyz), albedo_metallic.rgb, albedo_metallic.a, normal_roughness.w);
#ifdef MATERIAL
  vec4 material = texture(material_tex, uv);
  set_extensions(s, material);
#endif
  vec3 n = s.n;
  vec3 v = normalize(frame.camera_position.xyz - p);
  vec3 radiance = frame.sky_ambient.a * frame.sky_ambient.rgb * ambient_reflectance(s, v);
#ifdef EMISSION
  vec4 emission_occlusion = texture(emission_tex, uv);
  radiance = radiance * emission_occlusion.a + emission_occlusion.rgb;
#endif
#ifdef MATERIAL
  // As a caustic's, the translucent surfaces' light arrives from many directions: diffuse only.
  if (frame.translucent_samples > 0u) radiance += diffuse_reflected(s) / PI * translucent_irradiance(p, n, uint(material.w));
#endif
#ifdef CAUSTICS
  // The caustic's light arrives through the refractor from many directions: diffuse only.
  for (uint bits = params.caustic_lights; bits != 0u; bits &= bits - 1u) {
    uint i = uint(findLSB(bits));
    radiance += diffuse_reflected(s) / PI * caustic_irradiance(i, frame.caustic_lights[i], p, n);
  }
#endif
  for (uint i = 0; i < frame.light_count; ++i) {
    LightData light = frame.lights[i];
    float d2;
    vec3 l = toward_light(light, p, d2);
    // Direct light only where it falls: outside a spot's cone and on faces turned away from the light
    // the shadow map's nine taps would weigh nothing (with three lights, half the pass's time). A
    // surface that transmits diffusely is lit from behind too, shadowed as its far side sees the light.
    float cone = spot_cone(light, -l), n_l = dot(n, l);
    if (cone <= 0.0 || n_l == 0.0 || (n_l < 0.0 && !transmits_diffusely(s))) continue;
    vec3 lit_side = n_l > 0.0 ? n : -n;
#ifdef SHADOWS
    if ((params.shadowed & (1u << i)) != 0u) cone *= shadow_factor(i, light, p, lit_side);
#endif
    radiance += brdf(s, v, l) * light.radiant.rgb * abs(n_l) / d2 * cone;
  }
  out_color = vec4(radiance, 1.0);
}
