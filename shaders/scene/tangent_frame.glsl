#ifndef CAUSTICA_TANGENT_FRAME_GLSL
#define CAUSTICA_TANGENT_FRAME_GLSL
// Normal maps' tangent frame in a fragment shader (it takes screen derivatives), and the clear
// coat's normal bent by its own map: the G-buffer's for opaque surfaces, the refractor buffers' and
// forward refraction's for a refractor's coat. The includer declares the varyings `world_position`
// and `tangent` and includes scene/textures.glsl first.

// The normal map's tangent frame (KHR_materials_anisotropy takes the same): the file's TANGENT where
// the mesh has one (interpolated, made orthogonal to the normal; bitangent = sign * normal x
// tangent), else from the screen derivatives of position and texture coordinates `uv`: tangent
// along increasing u, bitangent = normal x tangent, as the Khronos sample viewer builds it.
// docs/gltf.md says where this differs from MikkTSpace. False where neither gives one.
bool tangent_frame(vec3 n, vec2 uv, out vec3 t, out vec3 b) {
  t = tangent.xyz;
  float sign = tangent.w < 0.0 ? -1.0 : 1.0;
  t -= n * dot(n, t);
  if (tangent.w == 0.0 || dot(t, t) <= 1e-20) {
    vec3 dp_dx = dFdx(world_position), dp_dy = dFdy(world_position);
    vec2 duv_dx = dFdx(uv), duv_dy = dFdy(uv);
    float det = duv_dx.x * duv_dy.y - duv_dy.x * duv_dx.y;
    t = det != 0.0 ? (dp_dx * duv_dy.y - dp_dy * duv_dx.y) / det : vec3(0.0);
    t -= n * dot(n, t);
    sign = 1.0;
  }
  b = vec3(0.0);
  if (dot(t, t) <= 1e-20) return false;
  t = normalize(t);
  b = sign * cross(n, t);
  return true;
}

// KHR_materials_clearcoat's normal: the geometry's `n` (the base's normal map does not reach the
// coat), bent by the coat's own normal map where it has one.
vec3 coat_normal(ObjectData object, vec3 n, vec4 texcoords) {
  TextureSlot map = object.surface_maps[4];
  vec3 t, b;
  if (map.row_u.w < 0.0 || !tangent_frame(n, slot_uv(map, texcoords), t, b)) return n;
  vec3 m = sample_slot(map, texcoords, vec4(0.5, 0.5, 1.0, 1.0)).xyz * 2.0 - 1.0;
  m = normalize(vec3(m.xy * object.coat_normal.x, m.z));
  return normalize(t * m.x + b * m.y + n * m.z);
}

#endif
