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

// KHR_materials_transmission, the extension object `t` at JSON pointer `extension_at`.
void read_transmission(const tinygltf::Value& t, const std::string& extension_at, const std::string& path, TextureTable& textures,
                       Material& m) {
  const double factor =
      in_unit_interval(extension_number(t, extension_at, "transmissionFactor", 0.0, path), extension_at + "/transmissionFactor", path);
  m.refractor = factor > 0.0;
  m.transmission = static_cast<float>(factor);
  m.tint = m.albedo;  // the specification tints transmitted light with the base colour
  m.thin = true;      // until a volume with a thickness says otherwise
  // The specification's transmission is as rough as the surface's reflection; refraction and
  // caustics take one roughness per object: the factor times the texture's mean (green channel).
  m.transmission_roughness =
      m.roughness * (m.metallic_roughness_texture.used() ? textures.mean(m.metallic_roughness_texture.texture).g : 1.0f);
  tinygltf::TextureInfo transmission_texture;
  if (t.Has("transmissionTexture")) {
    const auto& info = t.Get("transmissionTexture");
    const std::string info_at = extension_at + "/transmissionTexture";
    if (!info.IsObject() || !info.Has("index") || !info.Get("index").IsInt()) fail(path, 0, info_at + ": needs an integer \"index\"");
    transmission_texture.index = info.Get("index").GetNumberAsInt();
    if (info.Has("texCoord")) transmission_texture.texCoord = info.Get("texCoord").GetNumberAsInt();
    if (info.Has("extensions") && info.Get("extensions").Has("KHR_texture_transform"))
      transmission_texture.extensions["KHR_texture_transform"] = info.Get("extensions").Get("KHR_texture_transform");
    // Per texel on exact paths; the image-space methods take the texture's mean (red channel).
    m.transmission_factor = m.transmission;
    m.transmission_texture = textures.reference(transmission_texture, info_at, false);
    m.transmission *= textures.mean(m.transmission_texture.texture).r;
  }
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
