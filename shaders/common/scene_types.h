// Struct layouts shared by C++ (engine/scene/gpu_scene.h) and GLSL (std430 / std140 compatible:
// only vec4, mat4 and scalars in groups of four).
#ifndef CAUSTICA_SCENE_TYPES_H
#define CAUSTICA_SCENE_TYPES_H

#ifdef __cplusplus
#include <glm/glm.hpp>
namespace caustica::scene::gpu {
using vec4 = glm::vec4;
using mat4 = glm::mat4;
using uint = uint32_t;
#endif

#define CAUSTICA_MAX_LIGHTS 8
// A light's caustic views (scene::caustic_views): one each, or a point light's cube faces; at most
// one per bit of a uint (lighting's mask of bound caustic maps).
#define CAUSTICA_MAX_CAUSTIC_VIEWS 32
// Instance masks of the top-level acceleration structure (engine/scene/acceleration.cpp): a ray
// query that takes CAUSTICA_RECEIVER_INSTANCES alone passes through every refractor.
#define CAUSTICA_RECEIVER_INSTANCES 0x01u
#define CAUSTICA_REFRACTOR_INSTANCES 0x02u
#define CAUSTICA_ALL_INSTANCES 0xFFu
// The deepest BVH the compute tracer walks (engine/scene/bvh.h; scene/trace_bvh.glsl's stack).
#define CAUSTICA_BVH_MAX_DEPTH 48
#define CAUSTICA_MAX_TEXTURES 128  // the scene's texture array (set 1); unused slots hold a white texel
// Colour bands of a dispersive material (KHR_materials_dispersion): red, green and blue refract with
// the index at the Fraunhofer C, d and F lines, in nm. scene::Material::band_iors and refraction.glsl's
// band_ior both place the bands from these.
#define CAUSTICA_LINE_C_NM 656.27
#define CAUSTICA_LINE_D_NM 587.56
#define CAUSTICA_LINE_F_NM 486.13

struct Vertex {
  vec4 position_dn;    // xyz world position, w: d_N (distance through the object along -normal)
  vec4 normal_object;  // xyz world normal, w: object index as a float
  vec4 texcoords;      // TEXCOORD_0 in xy, TEXCOORD_1 in zw
  vec4 tangent;        // xyz world tangent, w the bitangent's sign (glTF TANGENT); w 0: none
};

// Where a material reads a texture: the affine map of its texture coordinates (KHR_texture_transform)
// as two rows, the texture's slot in the scene's array (-1: none) and the TEXCOORD set.
struct TextureSlot {
  vec4 row_u;  // xyz: u' = dot(xyz, (u, v, 1)); w: texture slot, -1 for none
  vec4 row_v;  // xyz: v' = dot(xyz, (u, v, 1)); w: TEXCOORD set (0 or 1)
};

struct ObjectData {
  vec4 albedo_refractor;               // rgb albedo, a: 0 opaque, 1 a refractor, 2 a convex solid refractor (Object::convex)
  vec4 absorption_ior;                 // rgb absorption per unit length, a: index of refraction
  vec4 tint_transmission;              // rgb: colour of transmitted light, a: transmission factor (refractors)
  vec4 bounds_min_thin;                // xyz: world-space bounding box; w: 1 for a thin-walled refractor
  vec4 bounds_max_spread;              // xyz: world-space bounding box; w: n_F - n_C (dispersion; 0: none)
  TextureSlot base_color;              // multiplies albedo_refractor.rgb and alpha_cutoff.x
  vec4 alpha_cutoff;                   // x: base colour alpha; y: MASK cutoff (coverage below it cuts out), -2 for a BLEND
                                       // surface drawn as a thin wall (Material::coverage_transmits), else -1;
                                       // z: 1 when single-sided (the camera's view culls its back faces); w: occlusion strength
  TextureSlot metallic_roughness_map;  // b scales metallic, g roughness
  TextureSlot normal;                  // tangent-space normal map
  TextureSlot emissive;                // multiplies emissive_normal_scale.rgb
  vec4 emissive_normal_scale;          // rgb: emitted radiance; w: the normal map's scale
  vec4 metallic_roughness;             // x metallic, y roughness; z: 1 for glTF's metallic-roughness BRDF, 0 Lambertian;
                                       // w: a refractor's transmission roughness (0: specular)
  TextureSlot occlusion;               // red: ambient occlusion, applied with alpha_cutoff.w's strength
  TextureSlot transmission_map;        // red: multiplies tint_transmission_factors.a (refractors)
  vec4 tint_transmission_factors;      // tint_transmission before the base colour's and the transmission texture's
                                       // means (which a graph without front_tint takes): textures.glsl reads them per texel
  // The layers glTF's material extensions put on a refractor's interface (scene::Material; the
  // model in refraction/interface.glsl):
  vec4 specular;  // rgb: KHR_materials_specular's colour of F0, a: its weight
  vec4 layers;    // x: the clear coat's weight, y: its roughness; z: the thin film's weight (iridescence), w: the film's index
  vec4 film;      // x: the thin film's thickness in nm; y, z: the thinnest and thickest the thickness texture gives; w: 0
  // The same layers per texel where an exact path meets the surface (scene::LayerTextures;
  // scene/trace.glsl's layers_at): each texture scales its factor.
  // The textures: KHR_materials_specular's weight (alpha: specular_factors.a) and colour (rgb:
  // specular_factors.rgb), the clear coat's (red: layer_factors.x) and its roughness's (green:
  // layer_factors.y), the film's weight (red: layer_factors.z) and thickness (green: from film.y
  // to film.z).
  TextureSlot layer_maps[6];
  vec4 specular_factors;  // rgb: KHR_materials_specular's colour factor, a: its factor
  vec4 layer_factors;     // x: clearcoat, y: clearcoat roughness, z: iridescence; w: 1 where a refractor's layers have textures
                          // (scene::has_layer_textures: the coat's own normal map too)
  // What glTF's extensions put on an opaque surface's BRDF (scene::Material; the model in scene/surface.glsl):
  vec4 sheen;                  // rgb: the sheen's colour, a: its roughness
  vec4 sheen_albedo[4];        // the sheen's directional albedo at cosines (k / 15)^2, k = 0..15 (reference/surface_physics.h)
  vec4 anisotropy;             // x: strength, y and z: cosine and sine of the rotation from the tangent; w: 0
  TextureSlot anisotropy_map;  // rg: direction in the tangent frame, b: multiplies the strength
  vec4 diffuse_transmission;   // rgb: the colour of the light that passes, a: its share of the diffuse light
  // The same per texel (scene::SurfaceTextures; the G-buffer reads them, gbuffer.frag): the sheen's
  // colour (rgb: sheen_factors.rgb) and roughness (alpha: sheen_factors.a), the diffuse
  // transmission's share (alpha: diffuse_transmission_factors.a) and colour (rgb:
  // diffuse_transmission_factors.rgb), and the clear coat's normal map (its scale coat_normal.x).
  TextureSlot surface_maps[5];
  vec4 sheen_factors;
  vec4 diffuse_transmission_factors;
  vec4 coat_normal;  // x: the scale of the coat's normal map; y, z, w: 0 (image space's copy of a refractor at a
                     // texel: the coat's normal there, where its map bends it: refraction.glsl's coat_cos_outside)
};

struct LightData {
  mat4 view_proj;  // the light's frustum (spot and directional: shadow and caustic maps; point: its caustic view)
  mat4 inv_view_proj;
  vec4 position_type;  // xyz, w: 0 spot, 1 point, 2 directional (view_proj orthographic from the plane through xyz)
  vec4 direction_cos;  // xyz axis, w: cosine of the cone's half angle (spot)
  vec4 radiant;        // rgb: colour * intensity (W/sr; directional: irradiance, W/m^2), a: intensity
  vec4 clip;           // near and far plane of view_proj (for linear depth), tan(fov / 2) (directional: half the view's side),
                       // w: tan of half a point light's cube face (kCubeFaceTan)
  vec4 face;           // x: the cube face (0..5: +x, -x, +y, -y, +z, -z) whose directions alone a caustic view emits, -1: every one;
                       // y: the solid refractor the light stands in (scene::Light::inside), -1: none
};

// A patch of a translucent surface (scene/translucent_samples.h), which passes on part of the light
// that falls on one side to what lies on the other.
struct TranslucentSample {
  vec4 position_area;  // xyz world position, w: the area it stands for
  vec4 normal_object;  // xyz: the surface's geometric normal, w: the object's index
  vec4 passed;         // rgb: what it passes, (1 - metallic) diffuseTransmissionFactor colour / pi (per unit irradiance and steradian)
};

struct FrameData {
  mat4 view_proj;
  mat4 inv_view_proj;
  vec4 camera_position;  // xyz, w: output width / height
  vec4 sky_ambient;      // rgb sky radiance, a: ambient fraction
  vec4 sizes;            // output width, height, 1/width, 1/height
  uint light_count;
  uint caustic_view_count;
  uint translucent_samples;  // the patches of translucent surfaces (TranslucentSample) the lighting pass gathers from
  uint pad1;
  // The sheen's directional albedo at roughness j / 15 in row j (4 vec4s), at cosines (k / 15)^2 as
  // ObjectData::sheen_albedo, for sheens whose roughness a texture sets; 0 where the scene has none.
  vec4 sheen_albedo_rows[64];
  LightData lights[CAUSTICA_MAX_LIGHTS];
  // Light i's cube faces (+x, -x, +y, -y, +z, -z) at 6 i + face, where it is a point light: its shadow map's layers.
  mat4 light_faces[6 * CAUSTICA_MAX_LIGHTS];
  // Each caustic view (scene::caustic_views; view i < light_count is light i's first) as the caustic
  // passes see it: its view, clip and position the view's (a frustum or prism fitted to its
  // refractors, or a cube face), its cone, colour and intensity its light's. Light-space refractor
  // buffers, receiver depths, photons and caustic maps are all in this view.
  LightData caustic_lights[CAUSTICA_MAX_CAUSTIC_VIEWS];
};

#ifdef __cplusplus
}  // namespace caustica::scene::gpu
#endif
#endif
