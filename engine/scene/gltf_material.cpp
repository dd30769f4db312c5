// A glTF material: the core metallic-roughness model, then the ratified KHR_materials_* extensions
// caustica reads (docs/gltf.md), then what the image-space methods take from texture means.
#include "scene/gltf_material.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "io/json_reader.h"
#include "scene/mesh_formats.h"

#include <tiny_gltf.h>  // the implementation is Debian's libtinygltf

namespace caustica::scene::gltf {
namespace {

using formats::fail;

double in_unit_interval(double v, const std::string& pointer, const std::string& path) {
  if (!(v >= 0.0 && v <= 1.0)) fail(path, 0, pointer + ": " + JsonReader::format_number(v) + " is outside [0, 1]");
  return v;
}

// `key` of an extension object at JSON pointer `extension_at`, finite; `fallback` when absent.
double extension_number(const tinygltf::Value& v, const std::string& extension_at, const char* key, double fallback,
                        const std::string& path) {
  if (!v.Has(key)) return fallback;
  const std::string pointer = extension_at + "/" + key;
  if (!v.Get(key).IsNumber()) fail(path, 0, pointer + ": must be a number");
  const double value = v.Get(key).GetNumberAsDouble();
  if (!std::isfinite(value)) fail(path, 0, pointer + ": must be a finite number");
  return value;
}

// A factor in [0, 1] at `key` of extension object `v` (at JSON pointer `extension_at`); `fallback`
// when absent.
double unit_factor(const tinygltf::Value& v, const std::string& extension_at, const char* key, double fallback, const std::string& path) {
  return in_unit_interval(extension_number(v, extension_at, key, fallback, path), extension_at + "/" + key, path);
}

// The core model: base colour, metal and roughness, normal, emissive and occlusion textures, alpha.
void read_core_material(const tinygltf::Material& mat, const std::string& at, const std::string& path, TextureTable& textures,
                        Material& m) {
  auto in_unit = [&](double v, const std::string& pointer) { return in_unit_interval(v, pointer, path); };
  const auto& base = mat.pbrMetallicRoughness.baseColorFactor;
  if (base.size() != 4) fail(path, 0, at + "/pbrMetallicRoughness/baseColorFactor: needs 4 numbers");
  for (size_t c = 0; c < 4; ++c) in_unit(base[c], at + "/pbrMetallicRoughness/baseColorFactor/" + std::to_string(c));
  m.albedo = glm::vec3(base[0], base[1], base[2]);
  m.alpha = static_cast<float>(base[3]);
  m.base_color_texture = textures.reference(mat.pbrMetallicRoughness.baseColorTexture, at + "/pbrMetallicRoughness/baseColorTexture", true);
  m.double_sided = mat.doubleSided;
  m.metallic_roughness = true;
  m.metallic = static_cast<float>(in_unit(mat.pbrMetallicRoughness.metallicFactor, at + "/pbrMetallicRoughness/metallicFactor"));
  m.roughness = static_cast<float>(in_unit(mat.pbrMetallicRoughness.roughnessFactor, at + "/pbrMetallicRoughness/roughnessFactor"));
  m.metallic_roughness_texture =
      textures.reference(mat.pbrMetallicRoughness.metallicRoughnessTexture, at + "/pbrMetallicRoughness/metallicRoughnessTexture", false);
  tinygltf::TextureInfo normal;  // a normalTextureInfo: textureInfo and a scale
  normal.index = mat.normalTexture.index;
  normal.texCoord = mat.normalTexture.texCoord;
  normal.extensions = mat.normalTexture.extensions;
  m.normal_texture = textures.reference(normal, at + "/normalTexture", false);
  if (!std::isfinite(mat.normalTexture.scale)) fail(path, 0, at + "/normalTexture/scale: must be a finite number");
  m.normal_scale = static_cast<float>(mat.normalTexture.scale);
  if (mat.emissiveFactor.size() != 3) fail(path, 0, at + "/emissiveFactor: needs 3 numbers");
  for (int c = 0; c < 3; ++c)
    m.emissive[c] = static_cast<float>(in_unit(mat.emissiveFactor[static_cast<size_t>(c)], at + "/emissiveFactor/" + std::to_string(c)));
  m.emissive_texture = textures.reference(mat.emissiveTexture, at + "/emissiveTexture", true);
  tinygltf::TextureInfo occlusion;  // an occlusionTextureInfo: textureInfo and a strength
  occlusion.index = mat.occlusionTexture.index;
  occlusion.texCoord = mat.occlusionTexture.texCoord;
  occlusion.extensions = mat.occlusionTexture.extensions;
  m.occlusion_texture = textures.reference(occlusion, at + "/occlusionTexture", false);
  m.occlusion_strength = static_cast<float>(in_unit(mat.occlusionTexture.strength, at + "/occlusionTexture/strength"));
  if (mat.alphaMode == "MASK") {
    m.alpha_mode = AlphaMode::mask;
  } else if (mat.alphaMode == "BLEND") {
    m.alpha_mode = AlphaMode::blend;
  } else if (mat.alphaMode != "OPAQUE") {
    fail(path, 0, at + "/alphaMode: '" + mat.alphaMode + "' is not OPAQUE, MASK or BLEND");
  }
  if (!(mat.alphaCutoff >= 0.0) || !std::isfinite(mat.alphaCutoff))
    fail(path, 0, at + "/alphaCutoff: " + JsonReader::format_number(mat.alphaCutoff) + " must be 0 or more");
  m.alpha_cutoff = static_cast<float>(mat.alphaCutoff);
}

// A textureInfo at `key` of extension object `v` (at JSON pointer `extension_at`), with its
// KHR_texture_transform; unused where absent.
TextureRef extension_texture(const tinygltf::Value& v, const std::string& extension_at, const char* key, const std::string& path,
                             TextureTable& textures, bool srgb) {
  if (!v.Has(key)) return {};
  const auto& info = v.Get(key);
  const std::string info_at = extension_at + "/" + key;
  if (!info.IsObject() || !info.Has("index") || !info.Get("index").IsInt()) fail(path, 0, info_at + ": needs an integer \"index\"");
  tinygltf::TextureInfo texture;
  texture.index = info.Get("index").GetNumberAsInt();
  if (info.Has("texCoord")) {
    if (!info.Get("texCoord").IsInt()) fail(path, 0, info_at + "/texCoord: must be an integer");
    texture.texCoord = info.Get("texCoord").GetNumberAsInt();
  }
  if (info.Has("extensions") && info.Get("extensions").Has("KHR_texture_transform"))
    texture.extensions["KHR_texture_transform"] = info.Get("extensions").Get("KHR_texture_transform");
  return textures.reference(texture, info_at, srgb);
}

// A texture's mean in `channel` (0 red .. 3 alpha), 1 where it is unused: what the per-object
// value of a factor that a texture multiplies takes from it.
float texture_mean(const TextureTable& textures, const TextureRef& ref, int channel) {
  return ref.used() ? textures.mean(ref.texture)[channel] : 1.0f;
}

// KHR_materials_transmission, the extension object `t` at JSON pointer `extension_at`.
void read_transmission(const tinygltf::Value& t, const std::string& extension_at, const std::string& path, TextureTable& textures,
                       Material& m) {
  const double factor = unit_factor(t, extension_at, "transmissionFactor", 0.0, path);
  m.refractor = factor > 0.0;
  m.transmission = static_cast<float>(factor);
  m.tint = m.albedo;  // the specification tints transmitted light with the base colour
  m.thin = true;      // until a volume with a thickness says otherwise
  // The specification's transmission is as rough as the surface's reflection; refraction and
  // caustics take one roughness per object: the factor times the texture's mean (green channel).
  m.transmission_roughness = m.roughness * texture_mean(textures, m.metallic_roughness_texture, 1);
  // Per texel on exact paths; the image-space methods take the texture's mean (red channel).
  m.transmission_texture = extension_texture(t, extension_at, "transmissionTexture", path, textures, false);
  if (m.transmission_texture.used()) {
    m.transmission_factor = m.transmission;
    m.transmission *= texture_mean(textures, m.transmission_texture, 0);
  }
}

// A colour factor, 3 finite numbers, each in [0, 1] (`unit`) or else 0 or more, named by its JSON pointer
// when not; `fallback` where the key is absent.
glm::vec3 color_factor(const tinygltf::Value& v, const std::string& extension_at, const char* key, glm::vec3 fallback,
                       const std::string& path, bool unit) {
  if (!v.Has(key)) return fallback;
  const auto& c = v.Get(key);
  const std::string at = extension_at + "/" + key;
  if (!c.IsArray() || c.ArrayLen() != 3) fail(path, 0, at + ": needs 3 numbers");
  glm::vec3 color;
  for (int k = 0; k < 3; ++k) {
    const std::string element = at + "/" + std::to_string(k);
    if (!c.Get(k).IsNumber() || !std::isfinite(c.Get(k).GetNumberAsDouble())) fail(path, 0, element + ": must be a finite number");
    const double value = c.Get(k).GetNumberAsDouble();
    if (unit) {
      color[k] = static_cast<float>(in_unit_interval(value, element, path));
    } else {
      if (value < 0.0) fail(path, 0, element + ": " + JsonReader::format_number(value) + " must be 0 or more");
      color[k] = static_cast<float>(value);
    }
  }
  return color;
}

// An interface layer's factor in [0, 1] at `factor_key` and the data texture at `texture_key` whose
// `channel` scales it: both kept in `factor` and `texture` (the exact paths read them per texel);
// returns the factor times the texture's mean, what image space and the lighting pass read.
float layer_factor(const tinygltf::Value& v, const std::string& extension_at, const char* factor_key, double fallback,
                   const char* texture_key, int channel, const std::string& path, TextureTable& textures, float& factor,
                   TextureRef& texture) {
  factor = static_cast<float>(unit_factor(v, extension_at, factor_key, fallback, path));
  texture = extension_texture(v, extension_at, texture_key, path, textures, false);
  return factor * texture_mean(textures, texture, channel);
}

// A colour factor (in [0, 1] where `unit`) and the sRGB texture whose rgb multiplies it: the factor
// times the texture's mean.
glm::vec3 colour_layer(const tinygltf::Value& v, const std::string& extension_at, const char* factor_key, glm::vec3 fallback, bool unit,
                       const char* texture_key, const std::string& path, TextureTable& textures, glm::vec3& factor, TextureRef& texture) {
  factor = color_factor(v, extension_at, factor_key, fallback, path, unit);
  texture = extension_texture(v, extension_at, texture_key, path, textures, true);
  return texture.used() ? factor * glm::vec3(textures.mean(texture.texture)) : factor;
}

// KHR_materials_specular: the dielectric's reflectance scaled (specularFactor, the texture's
// alpha) and its F0 coloured (specularColorFactor, the texture's rgb); the fields hold the
// textures' means, layer_textures the factors and textures.
void read_specular(const tinygltf::Value& v, const std::string& extension_at, const std::string& path, TextureTable& textures,
                   Material& m) {
  LayerTextures& layers = m.layer_textures;
  m.specular =
      layer_factor(v, extension_at, "specularFactor", 1.0, "specularTexture", 3, path, textures, layers.specular_factor, layers.specular);
  m.specular_color = colour_layer(v, extension_at, "specularColorFactor", glm::vec3(1.0f), false, "specularColorTexture", path, textures,
                                  layers.specular_color_factor, layers.specular_color);
}

// KHR_materials_clearcoat: a clear coat of index 1.5 over the base, its factor (the texture's
// red) and roughness (the texture's green), and its own normal map (clearcoatNormalTexture with its
// scale; without one the coat follows the geometry's normal, not the base's normal map).
void read_clearcoat(const tinygltf::Value& v, const std::string& extension_at, const std::string& path, TextureTable& textures,
                    Material& m) {
  LayerTextures& layers = m.layer_textures;
  m.clearcoat = layer_factor(v, extension_at, "clearcoatFactor", 0.0, "clearcoatTexture", 0, path, textures, layers.clearcoat_factor,
                             layers.clearcoat);
  m.clearcoat_roughness = layer_factor(v, extension_at, "clearcoatRoughnessFactor", 0.0, "clearcoatRoughnessTexture", 1, path, textures,
                                       layers.clearcoat_roughness_factor, layers.clearcoat_roughness);
  SurfaceTextures& surface = m.surface_textures;
  surface.clearcoat_normal = extension_texture(v, extension_at, "clearcoatNormalTexture", path, textures, false);
  if (surface.clearcoat_normal.used() && v.Get("clearcoatNormalTexture").Has("scale")) {
    const auto& scale = v.Get("clearcoatNormalTexture").Get("scale");
    if (!scale.IsNumber()) fail(path, 0, extension_at + "/clearcoatNormalTexture/scale: must be a number");
    surface.clearcoat_normal_scale = static_cast<float>(scale.GetNumberAsDouble());
  }
}

// KHR_materials_iridescence: a thin film of iridescenceIor between the outside and the base, as
// thick as the thickness texture's green places it between the minimum and the maximum (the
// maximum without one), mixed in by iridescenceFactor (the texture's red).
void read_iridescence(const tinygltf::Value& v, const std::string& extension_at, const std::string& path, TextureTable& textures,
                      Material& m) {
  LayerTextures& layers = m.layer_textures;
  m.iridescence = layer_factor(v, extension_at, "iridescenceFactor", 0.0, "iridescenceTexture", 0, path, textures,
                               layers.iridescence_factor, layers.iridescence);
  const double ior = extension_number(v, extension_at, "iridescenceIor", 1.3, path);
  if (ior < 1.0 || ior > 4.0) {
    fail(path, 0, extension_at + "/iridescenceIor: " + JsonReader::format_number(ior) + " is outside [1, 4] (the range caustica renders)");
  }
  m.film_ior = static_cast<float>(ior);
  const double thinnest = extension_number(v, extension_at, "iridescenceThicknessMinimum", 100.0, path);
  const double thickest = extension_number(v, extension_at, "iridescenceThicknessMaximum", 400.0, path);
  if (thinnest < 0.0) fail(path, 0, extension_at + "/iridescenceThicknessMinimum: must be 0 or more");
  if (thickest < 0.0) fail(path, 0, extension_at + "/iridescenceThicknessMaximum: must be 0 or more");
  layers.thickness_min = static_cast<float>(thinnest);
  layers.thickness_max = static_cast<float>(thickest);
  layers.thickness = extension_texture(v, extension_at, "iridescenceThicknessTexture", path, textures, false);
  const auto along = static_cast<double>(texture_mean(textures, layers.thickness, 1));
  m.film_thickness_nm = static_cast<float>(thinnest + (thickest - thinnest) * along);
}

// KHR_materials_sheen: the sheen's colour (the texture's rgb) and roughness (the texture's alpha);
// the fields hold the textures' means, surface_textures the factors and textures.
void read_sheen(const tinygltf::Value& v, const std::string& extension_at, const std::string& path, TextureTable& textures, Material& m) {
  SurfaceTextures& surface = m.surface_textures;
  m.sheen_color = colour_layer(v, extension_at, "sheenColorFactor", glm::vec3(0.0f), true, "sheenColorTexture", path, textures,
                               surface.sheen_color_factor, surface.sheen_color);
  m.sheen_roughness = layer_factor(v, extension_at, "sheenRoughnessFactor", 0.0, "sheenRoughnessTexture", 3, path, textures,
                                   surface.sheen_roughness_factor, surface.sheen_roughness);
}

// KHR_materials_anisotropy: strength in [0, 1] and rotation (radians), the texture per texel.
void read_anisotropy(const tinygltf::Value& v, const std::string& extension_at, const std::string& path, TextureTable& textures,
                     Material& m) {
  m.anisotropy = static_cast<float>(unit_factor(v, extension_at, "anisotropyStrength", 0.0, path));
  m.anisotropy_rotation = static_cast<float>(extension_number(v, extension_at, "anisotropyRotation", 0.0, path));
  m.anisotropy_texture = extension_texture(v, extension_at, "anisotropyTexture", path, textures, false);
}

// KHR_materials_diffuse_transmission: the share (the texture's alpha) and colour (the texture's
// rgb) of the diffuse light that passes through; the fields hold the textures' means,
// surface_textures the factors and textures.
void read_diffuse_transmission(const tinygltf::Value& v, const std::string& extension_at, const std::string& path, TextureTable& textures,
                               Material& m) {
  SurfaceTextures& surface = m.surface_textures;
  m.diffuse_transmission = layer_factor(v, extension_at, "diffuseTransmissionFactor", 0.0, "diffuseTransmissionTexture", 3, path, textures,
                                        surface.diffuse_transmission_factor, surface.diffuse_transmission);
  m.diffuse_transmission_color =
      colour_layer(v, extension_at, "diffuseTransmissionColorFactor", glm::vec3(1.0f), true, "diffuseTransmissionColorTexture", path,
                   textures, surface.diffuse_transmission_color_factor, surface.diffuse_transmission_color);
}

// KHR_materials_volume, the extension object `v` at JSON pointer `extension_at`.
void read_volume(const tinygltf::Value& v, const std::string& extension_at, const std::string& path, Material& m) {
  const double thickness = extension_number(v, extension_at, "thicknessFactor", 0.0, path);
  if (thickness < 0.0) fail(path, 0, extension_at + "/thicknessFactor: must be 0 or more");
  m.thin = thickness == 0.0;  // the specification: a thickness of 0 is a thin wall
  const double distance = extension_number(v, extension_at, "attenuationDistance", std::numeric_limits<double>::infinity(), path);
  if (!(distance > 0.0)) fail(path, 0, extension_at + "/attenuationDistance: must be above 0");
  glm::dvec3 color(1.0);
  if (v.Has("attenuationColor")) {
    const auto& c = v.Get("attenuationColor");
    if (!c.IsArray() || c.ArrayLen() != 3) fail(path, 0, extension_at + "/attenuationColor: needs 3 numbers");
    for (int k = 0; k < 3; ++k) {
      if (!c.Get(k).IsNumber()) fail(path, 0, extension_at + "/attenuationColor/" + std::to_string(k) + ": must be a number");
      color[k] = in_unit_interval(c.Get(k).GetNumberAsDouble(), extension_at + "/attenuationColor/" + std::to_string(k), path);
    }
  }
  if (std::isfinite(distance)) {
    for (int k = 0; k < 3; ++k)
      m.absorption[k] = static_cast<float>(-std::log(std::max(color[k], 1e-6)) / distance);  // colour reached after `distance`
  }
}

// The ratified KHR_materials_* extensions caustica reads (docs/gltf.md); others are left alone.
void read_material_extensions(const tinygltf::Material& mat, const std::string& at, const std::string& path, TextureTable& textures,
                              Material& m) {
  auto ext = [&](const char* name) -> const tinygltf::Value* {
    auto it = mat.extensions.find(name);
    return it == mat.extensions.end() ? nullptr : &it->second;
  };
  if (const auto* t = ext("KHR_materials_transmission"))
    read_transmission(*t, at + "/extensions/KHR_materials_transmission", path, textures, m);
  if (const auto* i = ext("KHR_materials_ior")) {
    const double ior = extension_number(*i, at + "/extensions/KHR_materials_ior", "ior", 1.5, path);
    if (ior < 1.0 || ior > 4.0) {
      fail(path, 0,
           at + "/extensions/KHR_materials_ior/ior: " + JsonReader::format_number(ior) + " is outside [1, 4] (the range caustica renders)");
    }
    m.ior = static_cast<float>(ior);
  }
  if (const auto* e = ext("KHR_materials_emissive_strength")) {
    const double strength = extension_number(*e, at + "/extensions/KHR_materials_emissive_strength", "emissiveStrength", 1.0, path);
    if (strength < 0.0) fail(path, 0, at + "/extensions/KHR_materials_emissive_strength/emissiveStrength: must be 0 or more");
    m.emissive *= static_cast<float>(strength);
  }
  if (const auto* d = ext("KHR_materials_dispersion")) {
    const double dispersion = extension_number(*d, at + "/extensions/KHR_materials_dispersion", "dispersion", 0.0, path);
    if (dispersion < 0.0) fail(path, 0, at + "/extensions/KHR_materials_dispersion/dispersion: must be 0 or more");
    m.dispersion = static_cast<float>(dispersion);
  }
  if (const auto* v = ext("KHR_materials_volume")) read_volume(*v, at + "/extensions/KHR_materials_volume", path, m);
  if (const auto* v = ext("KHR_materials_specular")) read_specular(*v, at + "/extensions/KHR_materials_specular", path, textures, m);
  if (const auto* v = ext("KHR_materials_clearcoat")) read_clearcoat(*v, at + "/extensions/KHR_materials_clearcoat", path, textures, m);
  if (const auto* v = ext("KHR_materials_iridescence"))
    read_iridescence(*v, at + "/extensions/KHR_materials_iridescence", path, textures, m);
  if (const auto* v = ext("KHR_materials_sheen")) read_sheen(*v, at + "/extensions/KHR_materials_sheen", path, textures, m);
  if (const auto* v = ext("KHR_materials_anisotropy")) read_anisotropy(*v, at + "/extensions/KHR_materials_anisotropy", path, textures, m);
  if (const auto* v = ext("KHR_materials_diffuse_transmission"))
    read_diffuse_transmission(*v, at + "/extensions/KHR_materials_diffuse_transmission", path, textures, m);
}

// What the image-space methods, which read one value per object, take from a refractor's or a
// BLEND surface's textures: their means.
void apply_texture_means(TextureTable& textures, Material& m) {
  if (m.refractor && m.base_color_texture.used()) {
    // Per texel where a method reads the texture (docs/gltf.md); `tint` keeps the texture's mean
    // colour times the factor for a graph whose image-space passes do not.
    m.tint_factor = m.tint;
    m.tint *= glm::vec3(textures.mean(m.base_color_texture.texture));
  }
  if (m.alpha_mode == AlphaMode::blend && !m.refractor) {
    // BLEND: drawn as a thin wall that passes the uncovered share 1 - alpha of the light unbent,
    // tinted by the base colour, and reflects the rest diffusely; no sorting is needed (docs/gltf.md).
    const float coverage = m.alpha * (m.base_color_texture.used() ? textures.mean(m.base_color_texture.texture).a : 1.0f);
    if (coverage < 1.0f) {
      m.refractor = true;
      m.thin = true;
      m.ior = 1.0f;
      m.coverage_transmits = true;
      m.transmission = 1.0f - coverage;  // with the texture's mean coverage; per texel where a method reads the texture
      m.tint_factor = m.albedo;
      m.tint = m.albedo * (m.base_color_texture.used() ? glm::vec3(textures.mean(m.base_color_texture.texture)) : glm::vec3(1.0f));
    }
  }
}

}  // namespace

Material gltf_material(const tinygltf::Model& model, int index, const std::string& from, const std::string& path, TextureTable& textures) {
  Material m;
  if (index < 0) {  // the specification's default material: opaque, base colour white, metal 1, roughness 1
    m.albedo = glm::vec3(1.0f);
    m.metallic_roughness = true;
    m.double_sided = false;
    return m;
  }
  if (static_cast<size_t>(index) >= model.materials.size()) fail(path, 0, from + ": material " + std::to_string(index) + " does not exist");
  const auto& mat = model.materials[static_cast<size_t>(index)];
  const std::string at = "/materials/" + std::to_string(index);
  read_core_material(mat, at, path, textures, m);
  read_material_extensions(mat, at, path, textures, m);
  apply_texture_means(textures, m);
  return m;
}

}  // namespace caustica::scene::gltf
