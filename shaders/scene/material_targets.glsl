#ifndef CAUSTICA_MATERIAL_TARGETS_GLSL
#define CAUSTICA_MATERIAL_TARGETS_GLSL
// How the G-buffer's material and layers targets hold what glTF's extensions put on an opaque
// surface (gbuffer.frag writes them, lighting.frag reads them):
// - material (rgba32f): x the anisotropy's direction in the world and z the clear coat's normal,
//   each a unit vector in 12 + 12 bits of the octahedral map kept as an integer below 2^24 (which a
//   float holds exactly; about 0.03 degrees apart), the coat's -1 where it is the shading normal
//   (no normal map on the surface or the coat: the common case keeps its full precision); y the
//   anisotropy's strength; w the object's index.
// - layers (rgba32ui): the extensions' texels, which lighting multiplies by the object's factors,
//   four 8-bit values to a word: x the sheen's colour (rgb) and roughness, y the diffuse
//   transmission's colour (rgb) and share, z KHR_materials_specular's colour (rgb) and weight, w the
//   clear coat's weight and roughness, the film's weight and where its thickness lies between the
//   thinnest and the thickest. Colours are kept as their square roots, which spends the 8 bits
//   evenly over what an sRGB texture's own 8 bits resolve; 1 where the object has no such texture.

vec2 octahedral(vec3 d) {
  d /= abs(d.x) + abs(d.y) + abs(d.z);
  vec2 folded = (1.0 - abs(d.yx)) * vec2(d.x >= 0.0 ? 1.0 : -1.0, d.y >= 0.0 ? 1.0 : -1.0);
  return d.z >= 0.0 ? d.xy : folded;
}

// 0 (the map's corner, a direction no caller reads) for no direction: the anisotropy of a round lobe.
float pack_direction(vec3 d) {
  if (dot(d, d) <= 0.0) return 0.0;
  uvec2 q = uvec2(round(clamp(octahedral(d) * 0.5 + 0.5, 0.0, 1.0) * 4095.0));
  return float(q.x | (q.y << 12u));
}

vec3 unpack_direction(float packed) {
  uint bits = uint(packed);
  vec2 e = vec2(float(bits & 4095u), float(bits >> 12u)) / 4095.0 * 2.0 - 1.0;
  vec3 d = vec3(e, 1.0 - abs(e.x) - abs(e.y));
  if (d.z < 0.0) d.xy = (1.0 - abs(d.yx)) * vec2(d.x >= 0.0 ? 1.0 : -1.0, d.y >= 0.0 ? 1.0 : -1.0);
  return normalize(d);
}

// A refractor's coat normal in the refractor buffers' front_layers (z): 1 + pack_direction where
// its own normal map bends it, 0 where the coat follows the surface (or the target has no z).
uint pack_coat_normal(ObjectData object, vec3 coat) {
  return object.surface_maps[4].row_u.w >= 0.0 ? 1u + uint(pack_direction(coat)) : 0u;
}

uint pack_colour_texel(vec3 rgb, float value) {
  return packUnorm4x8(vec4(sqrt(clamp(rgb, 0.0, 1.0)), value));
}

vec4 unpack_colour_texel(uint packed) {
  vec4 v = unpackUnorm4x8(packed);
  return vec4(v.rgb * v.rgb, v.a);
}

#endif
