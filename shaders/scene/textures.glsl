#ifndef CAUSTICA_TEXTURES_GLSL
#define CAUSTICA_TEXTURES_GLSL
// The scene's textures (set 1, written once by the scene: scene/gpu_textures.h) and how materials
// read them. Indexed per object within a draw or a dispatch, so the index is not uniform.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_nonuniform_qualifier : require
#include "scene/scene.glsl"
#include "scene/material_targets.glsl"
layout(set = 1, binding = 0) uniform sampler2D scene_textures[CAUSTICA_MAX_TEXTURES];

vec2 slot_uv(TextureSlot slot, vec4 texcoords) {
  vec3 uv = vec3(slot.row_v.w > 0.5 ? texcoords.zw : texcoords.xy, 1.0);
  return vec2(dot(slot.row_u.xyz, uv), dot(slot.row_v.xyz, uv));
}

// Filtered over the mip chain: fragment shaders.
vec4 sample_slot(TextureSlot slot, vec4 texcoords, vec4 fallback) {
  if (slot.row_u.w < 0.0) return fallback;
  return texture(scene_textures[nonuniformEXT(int(slot.row_u.w))], slot_uv(slot, texcoords));
}
vec4 base_color(ObjectData object, vec4 texcoords) {
  return vec4(object.albedo_refractor.rgb, object.alpha_cutoff.x) * sample_slot(object.base_color, texcoords, vec4(1.0));
}
// MASK: no surface where the coverage is below the cutoff.
bool cut_out(ObjectData object, vec4 texcoords) {
  return object.alpha_cutoff.y >= 0.0 && base_color(object, texcoords).a < object.alpha_cutoff.y;
}

// The same at the full-resolution level, for stages without derivatives (ray queries in compute
// and full-screen shaders), as the Embree references sample it.
vec4 sample_slot_at_full_resolution(TextureSlot slot, vec4 texcoords) {
  return textureLod(scene_textures[nonuniformEXT(int(slot.row_u.w))], slot_uv(slot, texcoords), 0.0);
}
bool cut_out_at_full_resolution(ObjectData object, vec4 texcoords) {
  if (object.alpha_cutoff.y < 0.0) return false;
  float alpha = object.alpha_cutoff.x;
  if (object.base_color.row_u.w >= 0.0) alpha *= sample_slot_at_full_resolution(object.base_color, texcoords).a;
  return alpha < object.alpha_cutoff.y;
}

// A BLEND surface drawn as a thin wall: its transmission is its uncovered share, 1 - alpha.
bool coverage_transmits(ObjectData object) {
  return object.alpha_cutoff.y < -1.5;
}
// Both, given the base colour and transmission textures' texels where the surface is met (the
// textures' means, which tint_transmission holds, where it has neither).
vec4 tint_transmission_from(ObjectData object, vec4 base_color_texel, float transmission_texel) {
  vec4 result = object.tint_transmission;
  if (object.base_color.row_u.w >= 0.0) {
    result.rgb = object.tint_transmission_factors.rgb * base_color_texel.rgb;
    if (coverage_transmits(object)) result.a = 1.0 - object.alpha_cutoff.x * base_color_texel.a;
  }
  if (object.transmission_map.row_u.w >= 0.0) result.a = object.tint_transmission_factors.a * transmission_texel;
  return result;
}
// Filtered over the mip chain (fragment shaders: the refractor buffers' tint, forward refraction).
vec4 tint_transmission_filtered(ObjectData object, vec4 texcoords) {
  return tint_transmission_from(object, sample_slot(object.base_color, texcoords, vec4(1.0)),
                                sample_slot(object.transmission_map, texcoords, vec4(1.0)).r);
}

// The texels of the interface layers' textures (KHR_materials_specular's colour and weight; the
// clear coat's weight and roughness, the film's weight and thickness), packed as the G-buffer's
// layers target's z and w (material_targets.glsl), 1 where the object has no such texture; filtered
// over the mip chain. with_interface_layer_texels (refraction/refraction.glsl) reads them back.
uvec2 interface_layer_texels_filtered(ObjectData object, vec4 texcoords) {
  vec4 one = vec4(1.0);
  vec4 specular = vec4(sample_slot(object.layer_maps[1], texcoords, one).rgb, sample_slot(object.layer_maps[0], texcoords, one).a);
  vec4 coat_film = vec4(sample_slot(object.layer_maps[2], texcoords, one).r, sample_slot(object.layer_maps[3], texcoords, one).g,
                        sample_slot(object.layer_maps[4], texcoords, one).r, sample_slot(object.layer_maps[5], texcoords, one).g);
  return uvec2(pack_colour_texel(specular.rgb, specular.a), packUnorm4x8(coat_film));
}

#endif
