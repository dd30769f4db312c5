#pragma once
// A scene as the renderer sees it: a camera, lights, and objects whose meshes are already in world
// space (transforms are baked at load, since nothing moves an object after loading). Refractors
// carry, per vertex, the distance through the object along the inverted normal (d_N in Wyman 2005),
// ray cast once at load time.
#include <glm/glm.hpp>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "io/json_document.h"

namespace caustica::scene {

// A glTF texture's image, decoded once, with its sampler's wrap modes and magnification filter.
enum class Wrap { repeat, clamp, mirror };
struct Texture {
  std::string name;  // the file and the texture's JSON pointer, for messages and --stats
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> rgba;  // 8 bits per channel, top row first, as the file stores them
  bool srgb = false;          // colour data (base colour): sRGB-encoded, read as linear
  Wrap wrap_u = Wrap::repeat, wrap_v = Wrap::repeat;
  bool nearest = false;  // magnification filter NEAREST (else LINEAR)
  // The linear value at uv (glTF: origin at the image's top left), filtered as the GPU samples the
  // full-resolution level.
  glm::vec4 sample(glm::vec2 uv) const;
};

// An 8-bit sRGB-encoded value in linear light.
float srgb_byte_to_linear(uint8_t byte);

// Where a material reads a texture: glTF's textureInfo, with KHR_texture_transform folded into
// one affine map of the texture coordinates (offset, then rotation, then scale).
struct TextureRef {
  int texture = -1;  // index into Scene::textures; -1: none
  int texcoord = 0;  // which TEXCOORD_n set (0 or 1)
  glm::mat3 transform{1.0f};
  bool used() const { return texture >= 0; }
};

// The interface layers' textures and the factors they multiply (glTF's KHR_materials_specular,
// _clearcoat, _iridescence), read per texel where an exact path meets the surface; Material's
// specular, clearcoat and film fields hold each factor times its texture's mean, which image space
// takes (docs/gltf.md, "The interface").
struct LayerTextures {
  TextureRef specular;             // alpha scales specular_factor
  TextureRef specular_color;       // rgb scales specular_color_factor
  TextureRef clearcoat;            // red scales clearcoat_factor
  TextureRef clearcoat_roughness;  // green scales clearcoat_roughness_factor
  TextureRef iridescence;          // red scales iridescence_factor
  TextureRef thickness;            // green places the film between thickness_min and thickness_max (nm)
  float specular_factor = 1.0f;
  glm::vec3 specular_color_factor{1.0f};
  float clearcoat_factor = 0.0f, clearcoat_roughness_factor = 0.0f, iridescence_factor = 0.0f;
  float thickness_min = 100.0f, thickness_max = 400.0f;
  bool used() const {
    return specular.used() || specular_color.used() || clearcoat.used() || clearcoat_roughness.used() || iridescence.used() ||
           thickness.used();
  }
};

// The textures of what glTF's extensions put on an opaque surface's BRDF beside the interface
// layers (KHR_materials_sheen, _diffuse_transmission, and the clear coat's own normal map) and the
// factors they multiply, read per texel by the G-buffer and the reference (the coat's normal map on
// refractors too, by the exact paths); Material's sheen and diffuse transmission fields hold each
// factor times its texture's mean.
struct SurfaceTextures {
  TextureRef sheen_color;                 // rgb scales sheen_color_factor
  TextureRef sheen_roughness;             // alpha scales sheen_roughness_factor
  TextureRef diffuse_transmission;        // alpha scales diffuse_transmission_factor
  TextureRef diffuse_transmission_color;  // rgb scales diffuse_transmission_color_factor
  TextureRef clearcoat_normal;            // the coat's tangent-space normal; without it the coat follows the geometry's normal
  glm::vec3 sheen_color_factor{0.0f};
  float sheen_roughness_factor = 0.0f;
  glm::vec3 diffuse_transmission_color_factor{1.0f};
  float diffuse_transmission_factor = 0.0f;
  float clearcoat_normal_scale = 1.0f;
};

// What a texture multiplies, as the device and the translucent patches take it beside the texture
// (ObjectData's specular_factors, layer_factors, sheen_factors and diffuse_transmission_factors):
// the factor where the texture is used, else the material's value (the same there for a glTF
// material, and right for one that is not).
template <typename T>
T factor_or(const TextureRef& texture, T factor, T value) {
  return texture.used() ? factor : value;
}

// glTF alpha modes: coverage from the base colour's alpha. MASK cuts out where it is below the
// cutoff, everywhere the engine sees the surface (camera, shadow and light maps, the references).
enum class AlphaMode { opaque, mask, blend };

struct Material {
  glm::vec3 albedo{0.8f};
  bool refractor = false;
  float ior = 1.5f;
  glm::vec3 absorption{0.0f};  // per unit of distance travelled inside, per channel (Beer-Lambert)
  // Refractors, as glTF's KHR_materials_transmission gives them: the share of the light past the
  // surface's Fresnel reflection that is transmitted (the rest is diffusely reflected with `tint`),
  // the colour that multiplies transmitted light (glTF's baseColor), and whether the object is a
  // thin wall (transmission without a volume: light passes without bending).
  float transmission = 1.0f;
  glm::vec3 tint{1.0f};
  bool thin = false;
  // Rough transmission (glTF's roughness on a transmissive material): refraction and caustics
  // scatter about GGX microfacet normals with alpha = roughness^2 (docs/gltf.md); 0 is specular.
  float transmission_roughness = 0.0f;
  // KHR_materials_dispersion: 20 / the Abbe number V_d = (n_d - 1) / (n_F - n_C); 0 disperses nothing.
  float dispersion = 0.0f;
  // n_F - n_C: how much the index of blue light exceeds that of red (`ior` is n_d).
  float ior_spread() const { return dispersion > 0.0f ? (ior - 1.0f) * dispersion / 20.0f : 0.0f; }
  // The index in each colour band: red at the C line (656.27 nm), green at d (587.56 nm), blue at F
  // (486.13 nm), on the two-term Cauchy curve n = A + B / lambda^2 the specification gives.
  glm::vec3 band_iors() const;
  // Where a ray meets the surface (the exact paths and the references) tint and transmission are
  // per texel: tint_factor times baseColorTexture's rgb, transmission_factor times
  // transmissionTexture's red, each where its texture is used. `tint` and `transmission` hold the
  // same with each texture's mean, which image space takes where a graph does not bind the
  // refractor buffers' front_tint (docs/gltf.md).
  glm::vec3 tint_factor{1.0f};
  float transmission_factor = 1.0f;
  TextureRef transmission_texture;
  // The layers glTF's material extensions put on a refractor's interface (docs/gltf.md, "The
  // interface"), each changing its reflectance R per colour channel (the rest, 1 - R, crosses):
  // KHR_materials_specular scales the dielectric's Fresnel curve to F0 * specular_color (at most 1)
  // and weights it by `specular`; KHR_materials_iridescence mixes in, by `iridescence`, the
  // reflectance of a thin film of index `film_ior` and `film_thickness_nm` between the outside and
  // the base, at each channel's wavelength; KHR_materials_clearcoat puts a clear coat (index 1.5,
  // F0 0.04) of weight `clearcoat` over all of it. Textures enter as their means (one value per
  // object).
  float specular = 1.0f;
  glm::vec3 specular_color{1.0f};
  float clearcoat = 0.0f;
  float clearcoat_roughness = 0.0f;
  float iridescence = 0.0f;
  float film_ior = 1.3f;
  float film_thickness_nm = 400.0f;
  LayerTextures layer_textures;
  // What glTF's extensions put on an opaque surface's BRDF, in the lighting of direct and sky light
  // (docs/gltf.md, "Opaque surfaces"; the model in scene/surface.glsl and reference/surface_physics.h):
  // KHR_materials_sheen's Charlie sheen of `sheen_color` and `sheen_roughness` over the rest,
  // which it dims by its own albedo; KHR_materials_anisotropy's stretched GGX lobe, `anisotropy`
  // its strength and `anisotropy_rotation` (radians) turning its direction from the tangent, both
  // per texel with `anisotropy_texture` (rg: direction, b: strength); KHR_materials_diffuse_transmission's
  // share of the diffuse light that passes to the other side, coloured. These fields hold the
  // textures' means; surface_textures (with layer_textures) keeps the textures, which the G-buffer
  // and the reference read per texel.
  glm::vec3 sheen_color{0.0f};
  float sheen_roughness = 0.0f;
  float anisotropy = 0.0f;
  float anisotropy_rotation = 0.0f;
  TextureRef anisotropy_texture;
  float diffuse_transmission = 0.0f;
  glm::vec3 diffuse_transmission_color{1.0f};
  SurfaceTextures surface_textures;

  // glTF's baseColorTexture: multiplies albedo (and tint) with its rgb, alpha with its a.
  TextureRef base_color_texture;
  // glTF's metallic-roughness model: opaque surfaces of glTF materials reflect with its BRDF (a
  // GGX specular lobe over a diffuse one that metal takes away); scene-file materials and OBJ/OFF
  // meshes are Lambertian, as before. The texture's blue channel scales metallic, green roughness.
  bool metallic_roughness = false;
  float metallic = 1.0f, roughness = 1.0f;
  TextureRef metallic_roughness_texture;
  // Tangent-space normal map (scaled in xy by normal_scale) and emitted radiance (emissiveFactor
  // times KHR_materials_emissive_strength, times the texture's rgb).
  TextureRef normal_texture;
  float normal_scale = 1.0f;
  glm::vec3 emissive{0.0f};
  TextureRef emissive_texture;
  // glTF's occlusionTexture: its red channel darkens the ambient (sky) light a surface receives, as
  // 1 + strength * (red - 1); direct light and emission are not occluded.
  TextureRef occlusion_texture;
  float occlusion_strength = 1.0f;
  float alpha = 1.0f;  // baseColorFactor's alpha
  AlphaMode alpha_mode = AlphaMode::opaque;
  float alpha_cutoff = 0.5f;
  // BLEND drawn as a thin wall (docs/gltf.md): its transmission is the uncovered share, 1 - alpha
  // times the base colour texture's alpha where it has one (per texel where the method reads it).
  bool coverage_transmits = false;
  // glTF's doubleSided: false culls the back faces of opaque surfaces in the camera's view (they
  // still cast shadows, as the engine's shadow maps draw both sides). Scene-file materials are.
  bool double_sided = true;
};

// Whether an opaque surface's extensions have textures (its sheen's, diffuse transmission's, or
// specular, coat or film ones), which the G-buffer's layers target and the reference read per texel.
bool has_surface_textures(const Material& m);
// Whether a refractor's interface has textures (its specular, coat or film layers', or the coat's own
// normal map), which the exact paths and the references read per texel.
bool has_layer_textures(const Material& m);

struct Mesh {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;
  std::vector<uint32_t> indices;       // triangles
  std::vector<float> normal_distance;  // d_N per vertex; refractors only
  std::vector<glm::vec4> texcoords;    // per vertex: TEXCOORD_0 in xy, TEXCOORD_1 in zw; empty without
  // Per vertex: glTF's TANGENT, xyz the unit tangent (along increasing u of the normal map's
  // texture coordinates), w the bitangent's sign (bitangent = w normal x tangent); empty without,
  // and then normal maps take their frame from the texture coordinates' derivatives.
  std::vector<glm::vec4> tangents;
};

struct Object {
  std::string name;
  std::string pointer;  // JSON pointer of the object in the scene file, for messages
  Mesh mesh;
  Material material;
  glm::vec3 bounds_min{0.0f}, bounds_max{0.0f};
  // The sphere about center() through its farthest vertex (a ball's own, where the box's corners
  // would make it sqrt(3) times larger); 0 where it was not measured (then the box's).
  float radius = 0.0f;
  glm::vec3 center() const { return 0.5f * (bounds_min + bounds_max); }
  float bounding_radius() const { return radius > 0.0f ? radius : 0.5f * glm::length(bounds_max - bounds_min); }
};

// A perspective view with Vulkan clip conventions (depth 0..1, y down in framebuffer space).
struct View {
  glm::vec3 position{0.0f, 2.0f, 5.0f};
  glm::vec3 target{0.0f};
  float fov_y_degrees = 45.0f;
  float near_plane = 0.05f;
  float far_plane = 100.0f;
  glm::mat4 view_matrix() const;
  glm::mat4 projection(float aspect) const;
  glm::mat4 view_projection(float aspect) const { return projection(aspect) * view_matrix(); }
  // Turned about the vertical axis through its target (the viewer's and render's scripted orbit).
  void orbit(float degrees);
};

enum class LightType { spot, point, directional };
// As scene files write it: "spot", "point" or "directional".
const char* light_type_name(LightType type);

// A point light's shadow map is a cube: six square views along +x, -x, +y, -y, +z, -z, a little wider
// than a quarter turn (tan of the half angle 1.05 against 1), so that the 3x3 filter of a receiver
// near a face's edge still finds its taps inside that face.
inline constexpr float kCubeFaceTan = 1.05f;
// A light's caustic view (fit_caustic_view) holds the refractors it reaches, its tangent (a
// directional light's half side) twice theirs so that light bent outwards still lands in it: on the
// bundled ball lenses and prisms the exact photons landing off such a map stayed within 1% of those
// off the light's whole view at twice, and lost 2-7% more at 1.5 and 1.1 (docs/caustics.md). No
// frustum is fitted wider than a cone of 70 degrees about its axis: a spot or directional light
// then, or where the fit is no narrower, throws through its own view, and a point light (then among
// its refractors, or with them all around it) through the faces of a cube about it.
inline constexpr float kCausticViewMargin = 2.0f;
inline constexpr float kMaxFittedViewHalfDegrees = 70.0f;
// A point light's caustic cube face emits only the directions of its face (tan of the half angle 1)
// and keeps what lands within tan 1.5 of its axis: light bent out of the face still lands in its map.
inline constexpr float kCubeFaceCausticTan = 1.5f;

struct Light {
  LightType type = LightType::spot;
  // spot: position, target and the cone as a square frustum; directional: the direction from
  // position to target, and an orthographic view from the plane through position across it.
  View view;
  float intensity = 10.0f;  // radiant intensity (W/sr) along the axis; directional: irradiance (W/m^2)
  glm::vec3 color{1.0f};
  float extent = 0.0f;  // directional: half the side of the orthographic view's square (world units)
  // What its caustic passes draw and emit photons through (light-space refractor buffers, receiver
  // depth, photons, the caustic map; fit_caustic_view): a frustum (a directional light's prism,
  // caustic_extent its half side) fitted around the refractors it reaches, or a spot or directional
  // light's own view where the scene asks for it (own_caustic_view) or the fit is no narrower; a
  // point light may have none. A point light's shadow is the six cube faces about view.position.
  View caustic_view;
  float caustic_extent = 0.0f;
  bool has_caustic_view = false;
  bool own_caustic_view = false;  // the scene's "caustic_view": "light"
  // A point light that no frustum holds its refractors in throws through the faces of a cube about
  // it instead (bit F: face F, face_axis), those whose pyramid holds part of a refractor: each face
  // a caustic view of its own (caustic_views), caustic_view the first's. They stay the same faces
  // when the light moves, as the graph's instances were made for them.
  uint32_t caustic_faces = 0;
  // The solid refractor it stands in (a bulb inside a glass globe), whose glass its photons start
  // in; -1 for none (fit_caustic_view finds it: a spot or point light's position inside the mesh).
  int inside = -1;

  glm::vec3 axis() const { return glm::normalize(view.target - view.position); }
  glm::mat4 view_projection() const;  // its shadow map's (spot, directional)
  glm::mat4 caustic_view_projection() const;
  // This light with its caustic view for its view (and caustic_extent for its extent): what its
  // caustic passes see; its spot cone is still the light's own (axis() and view.fov_y_degrees of *this).
  Light as_caustic_view() const;
  // How many caustic views it has (each a graph's "for_each": "caustic_view" instance): 0, 1, or
  // one per face of caustic_faces.
  uint32_t caustic_view_count() const;
  // The view of cube face `face` that it throws caustics through (kCubeFaceCausticTan).
  View caustic_face_view(uint32_t face) const;
  // A point light's cube face `face` (0..5: +x, -x, +y, -y, +z, -z): its axis, and its view (kCubeFaceTan).
  static glm::vec3 face_axis(uint32_t face);
  glm::mat4 face_view_projection(uint32_t face) const;
  // Whether light from it can reach a part of the box (a spot light's frustum, conservatively as the
  // cone through its corners; a directional light's prism; a point light every direction).
  bool reaches(glm::vec3 bounds_min, glm::vec3 bounds_max) const;
};

struct Scene {
  std::string path;
  std::string name;
  View camera;
  std::vector<Light> lights;
  std::vector<Object> objects;
  std::vector<Texture> textures;      // what materials sample (TextureRef::texture)
  size_t file_images = 0;             // images in the scene's glTF files, used or not (only `textures` are decoded)
  glm::vec3 sky{0.35f, 0.45f, 0.6f};  // radiance of everything that is not geometry
  float ambient = 0.03f;              // fraction of albedo lit without a light
  // What its files say and the engine does not draw (ModelFile::warnings), each naming its file:
  // the commands print them as warnings.
  std::vector<std::string> warnings;

  size_t refractor_count() const;
  size_t triangle_count() const;
  // Whether a refractor disperses light: light is then traced once per colour band.
  bool disperses() const;
  // Whether an opaque surface has glTF's sheen, anisotropy, diffuse transmission, or a specular, index,
  // thin film or clear coat that changes its metallic-roughness BRDF: only then do the
  // G-buffer and lighting passes write and read their `material` target.
  bool has_surface_layers() const;
  // Whether such a surface has textures that set those extensions' values (the sheen's, the diffuse
  // transmission's, or the specular, coat or film ones): only then do the G-buffer and lighting
  // passes write and read their `layers` target, the texels.
  bool has_surface_textures() const;
  // Whether a refractor's interface layers have textures, which the exact paths read per texel.
  bool has_layer_textures() const;
  // Whether a refractor's tint or transmission varies over its surface (a base colour or a
  // transmission texture): only then do the refractor buffers draw their front_tint.
  bool tints_per_texel() const;
  // How far a ray starts off the surface it leaves: 1e-4 of the largest object's diagonal, at least
  // 1e-4. The exact tracers (Embree and ray queries) share it.
  float ray_epsilon() const;
  // The box around every object (both corners at the origin when there is none).
  std::pair<glm::vec3, glm::vec3> bounds() const;
  // The length of that box's diagonal: how far the image-space searches reach unless told.
  float diagonal() const;
  // What graph expressions see of the scene: scene.refractors, scene.lights, scene.objects,
  // scene.dispersive (1 where a refractor disperses light, else 0), scene.diagonal and
  // scene.ray_epsilon (a user pass's exact tracer offsets its rays as the built-ins do); per light K,
  // scene.lightK.spot, .point and .directional (1 for its type), .view (1 where it has a caustic view),
  // .objects and .refractors (how many its light reaches, Light::reaches), which a per-light pass
  // reads as light.NAME (graph/per_light.h); scene.caustic_views (how many, caustic_views) and per
  // view K scene.causticK.view (1 where present), .light (its light) and .face (its cube face, -1
  // for none), to which the graph compiler adds its light's other values: what a per-view pass
  // reads as light.NAME.
  std::map<std::string, double> expression_values() const;
};

// One view that a light's caustic passes draw through and emit photons into: one instance of a
// graph's "for_each": "caustic_view" passes (graph/per_light.h), FrameData::caustic_lights[K] on
// the device, one map of the photon reference.
struct CausticView {
  uint32_t light = 0;  // whose
  int face = -1;       // a point light's cube face (0..5) whose directions alone it emits; -1: every direction of its view
  bool present = false;
  // The light as these passes see it (Light::as_caustic_view): its view (and extent) this view's,
  // its cone, colour and intensity its own.
  Light seen;
};
// View K < lights.size() is light K's first (present where it has one: has_caustic_view); the
// further faces of point lights that throw through cube faces follow, light by light, face by face.
std::vector<CausticView> caustic_views(const std::vector<Light>& lights);
// Whether `direction` (from the light) leaves through cube face `face` (0..5): its largest
// component is along the face's axis, ties going to x before y before z (so that every direction
// has one face, as the shaders' cube_face).
bool leaves_through_face(glm::vec3 direction, int face);

// The views fitted to the scene's objects (scene/light_views.cpp): a directional light's prism
// around the first `fitted` objects (where the scene gave no extent), and every light's caustic
// view. fit_caustic_view fits one light's again (a moved light) and returns has_caustic_view.
void fit_light_views(Scene& scene, size_t fitted);
bool fit_caustic_view(Light& light, const Scene& scene);
// Moves light `index` of the scene by `offset` (its position; a spot keeps its target) and fits its
// caustic view again, as the engine does for a light the viewer moves (GpuScene::replace_view).
void move_light(Scene& scene, size_t index, glm::vec3 offset);

// The coordinates texture `ref` reads at a point whose TEXCOORD sets are `uv` (set 0 in xy, set 1
// in zw): its set, through its transform.
glm::vec2 texture_coordinates(const TextureRef& ref, glm::vec4 uv);
// Texture `ref` of `object` at barycentric (u, v) of its triangle `triangle` (the weights of the
// triangle's second and third vertices), as Texture::sample reads it; 1 where `ref` is unused.
glm::vec4 texel_at(const Scene& scene, const Object& object, const TextureRef& ref, uint32_t triangle, float u, float v);

// Throws InputError naming the file, line and JSON pointer (or the mesh file and its line).
// A scene file, or a model file opened as a scene (load_model_scene).
Scene load_scene_file(const std::string& path, bool stage = true);
Scene load_scene(const JsonDocument& doc);

// One primitive of a mesh file with its material, if the file gives one (glTF does, OBJ and OFF
// do not). Positions are in the file's space with glTF node transforms applied.
struct MeshPart {
  std::string name;
  Mesh mesh;
  std::optional<Material> material;  // its textures index ModelFile::textures
};

// .gltf, .glb, .obj, .off: the parts alone (load_model_file for their textures). Throws InputError
// naming `path` (and the line, for text formats).
std::vector<MeshPart> load_mesh_file(const std::string& path);

// A light as a glTF file gives it (KHR_lights_punctual): type "spot", "point" or "directional",
// where it is and where it points in world space, candela (lux for directional), the spot's cone.
struct ModelLight {
  std::string type;
  glm::vec3 position{0.0f}, direction{0.0f, -1.0f, 0.0f};
  float intensity = 1.0f;
  glm::vec3 color{1.0f};
  float cone_degrees = 90.0f;  // full angle: twice outerConeAngle
};

// A mesh file with what else it holds: a glTF file's first camera and its lights.
struct ModelFile {
  std::vector<MeshPart> parts;
  std::vector<Texture> textures;  // only those the parts' materials use: no other image is decoded
  size_t images = 0;              // images in the file
  std::optional<View> camera;
  bool camera_is_orthographic = false;
  std::vector<ModelLight> lights;
  std::vector<std::string> warnings;  // what the file says and caustica does not draw (an extension it does not read)
};
ModelFile load_model_file(const std::string& path);

// A model file (.gltf, .glb, .obj, .off) opened as a scene of its own: the file's camera, or one
// that frames the model; its lights, or a spot light placed above and behind it for a caustic; a
// floor under it when `stage`.
Scene load_model_scene(const std::string& path, bool stage = true);
// Whether a path names a model file rather than a scene file (by its extension).
bool is_model_file(const std::string& path);
void compute_smooth_normals(Mesh& mesh);
// A TANGENT (xyz, w the bitangent's sign) carried by a transform: the tangent as a direction on the
// surface, the sign flipped by a mirroring transform, since the cross product of the carried normal
// and tangent flips with it. A tangent that degenerates comes out zero (the normal map then takes
// the derivative frame).
glm::vec4 carry_tangent(const glm::mat4& transform, glm::vec4 tangent);

// Primitives in object space, centred on the origin (the plane faces +y).
Mesh make_sphere(float radius, int slices = 64, int stacks = 32);
Mesh make_plane(float width, float depth);
Mesh make_box(glm::vec3 size);
Mesh make_torus(float major_radius, float minor_radius, int segments = 64, int sides = 32);

// The corners of the box around a mesh's positions (a mesh with none: both zero).
std::pair<glm::vec3, glm::vec3> mesh_bounds(const Mesh& mesh);

// d_N: for every vertex, the distance from it along -normal to where the ray leaves the mesh; 0
// where it never does (open meshes). Ray cast with Embree.
std::vector<float> normal_distances(const Mesh& mesh);

// Whether the mesh bounds a convex solid: closed (after welding vertices closer than 1e-5 of its
// size), consistently wound counter-clockwise from outside, connected, and convex at every edge.
bool is_convex_solid(const Mesh& mesh);

// A solid refractor whose mesh bounds a convex body: light that leaves it cannot meet it again, so
// the hybrids trace its exit rays past every refractor (shaders/scene/ray_query.glsl). Derived from
// the mesh whenever asked (the scene's upload asks), so that a mesh changed after loading is never
// taken for the convex one it was.
bool is_convex_refractor(const Object& object);

}  // namespace caustica::scene
