#version 460
// Opaque geometry seen from the camera: the shading normal (facing the viewer, normal map applied)
// with roughness, base colour (textured) with metallic, and emitted radiance with the ambient
// occlusion (glTF's occlusionTexture) in its alpha; MASK materials cut out where their coverage is
// below the cutoff; where MATERIAL is defined (its attachment's location), the anisotropy, the clear
// coat's normal and the object, and where LAYERS is, the texels of the object's other extensions
// (scene/material_targets.glsl says how they are held; lighting.frag multiplies them by the
// object's factors).
#extension GL_GOOGLE_include_directive : require
#include "scene/scene.glsl"
SCENE_OBJECTS
#include "scene/textures.glsl"

layout(location = 0) in vec3 world_position;
layout(location = 1) in vec3 world_normal;
layout(location = 2) in float normal_distance;
layout(location = 3) flat in uint object_index;
layout(location = 4) in vec4 texcoords;
layout(location = 5) in vec4 tangent;
layout(location = 0) out vec4 out_normal;
layout(location = 1) out vec4 out_albedo;
#ifdef EMISSION
layout(location = 2) out vec4 out_emission;
#endif
#ifdef MATERIAL
#include "scene/material_targets.glsl"
layout(location = MATERIAL) out vec4 out_material;
#endif
#ifdef LAYERS
layout(location = LAYERS) out uvec4 out_layers;
#endif

#include "scene/tangent_frame.glsl"

vec3 apply_normal_map(ObjectData object, vec3 n) {
  vec3 t, b;
  if (!tangent_frame(n, slot_uv(object.normal, texcoords), t, b)) return n;
  vec3 m = sample_slot(object.normal, texcoords, vec4(0.5, 0.5, 1.0, 1.0)).xyz * 2.0 - 1.0;
  m = normalize(vec3(m.xy * object.emissive_normal_scale.w, m.z));
  return normalize(t * m.x + b * m.y + n * m.z);
}

#ifdef MATERIAL
// KHR_materials_anisotropy's direction in the world (xyz) and strength (w): the texture's rg (the
// direction in the tangent frame; (1, 0) without one) turned by the rotation, and its blue times
// the strength. n is the shading normal before it flips for a back face.
vec4 anisotropy(ObjectData object, vec3 n) {
  if (object.anisotropy.x <= 0.0) return vec4(0.0);
  vec4 texel = sample_slot(object.anisotropy_map, texcoords, vec4(1.0, 0.5, 1.0, 1.0));
  vec2 d = texel.rg * 2.0 - 1.0;
  d = vec2(object.anisotropy.y * d.x - object.anisotropy.z * d.y, object.anisotropy.z * d.x + object.anisotropy.y * d.y);
  vec3 t, b;
  vec2 uv = slot_uv(object.anisotropy_map.row_u.w >= 0.0 ? object.anisotropy_map : object.normal, texcoords);
  if (dot(d, d) <= 1e-12 || !tangent_frame(n, uv, t, b)) return vec4(0.0);
  return vec4(normalize(t * d.x + b * d.y), object.anisotropy.x * texel.b);
}
#endif

#ifdef LAYERS
// The texels of the extensions that lighting reads per texel, 1 where the object has no such texture.
uvec4 layer_texels(ObjectData object) {
  vec4 one = vec4(1.0);
  vec4 sheen = vec4(sample_slot(object.surface_maps[0], texcoords, one).rgb, sample_slot(object.surface_maps[1], texcoords, one).a);
  vec4 passed = vec4(sample_slot(object.surface_maps[3], texcoords, one).rgb, sample_slot(object.surface_maps[2], texcoords, one).a);
  return uvec4(pack_colour_texel(sheen.rgb, sheen.a), pack_colour_texel(passed.rgb, passed.a), interface_layer_texels_filtered(object, texcoords));
}
#endif

void main() {
  ObjectData object = objects[object_index];
  if (!gl_FrontFacing && object.alpha_cutoff.z > 0.5) discard;  // single-sided: its back is culled
  vec4 base = base_color(object, texcoords);
  if (base.a < object.alpha_cutoff.y) discard;
  vec3 geometric = normalize(world_normal), n = geometric;
  if (object.normal.row_u.w >= 0.0) n = apply_normal_map(object, n);
#ifdef MATERIAL
  // The coat's normal where it differs from the shading normal (a normal map on either), -1 where
  // it is the same: lighting then takes the shading normal unquantized. Seen from behind, it flips
  // with the surface.
  vec4 stretch = anisotropy(object, n);
  bool own_coat_normal = object.normal.row_u.w >= 0.0 || object.surface_maps[4].row_u.w >= 0.0;
  float coat = own_coat_normal ? pack_direction(coat_normal(object, geometric, texcoords) * (gl_FrontFacing ? 1.0 : -1.0)) : -1.0;
  out_material = vec4(pack_direction(stretch.xyz), stretch.w, coat, float(object_index));
#endif
#ifdef LAYERS
  out_layers = layer_texels(object);
#endif
  // Seen from behind, the whole frame flips with the surface.
  if (!gl_FrontFacing) n = -n;
  float metallic = 0.0, roughness = -1.0;  // Lambertian
  if (object.metallic_roughness.z > 0.5) {
    vec4 mr = sample_slot(object.metallic_roughness_map, texcoords, vec4(1.0));
    metallic = object.metallic_roughness.x * mr.b;
    roughness = object.metallic_roughness.y * mr.g;
  }
  out_normal = vec4(n, roughness);
  out_albedo = vec4(base.rgb, metallic);
#ifdef EMISSION
  float occlusion = 1.0 + object.alpha_cutoff.w * (sample_slot(object.occlusion, texcoords, vec4(1.0)).r - 1.0);
  out_emission = vec4(object.emissive_normal_scale.rgb * sample_slot(object.emissive, texcoords, vec4(1.0)).rgb, occlusion);
#endif
}
