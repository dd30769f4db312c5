// The textures a glTF file's materials name: decoded from the file's images (PNG, JPEG) when a
// material first uses them, with their samplers and KHR_texture_transform.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "scene/gltf_material.h"
#include "scene/mesh_formats.h"

#include <tiny_gltf.h>  // the implementation is Debian's libtinygltf

namespace caustica::scene::gltf {

using formats::fail;

TextureRef TextureTable::reference(const tinygltf::TextureInfo& info, const std::string& at, bool srgb) {
  TextureRef ref;
  if (info.index < 0) return ref;
  if (static_cast<size_t>(info.index) >= model_.textures.size())
    fail(path_, 0, at + "/index: texture " + std::to_string(info.index) + " does not exist");
  ref.texcoord = info.texCoord;
  if (const auto t = info.extensions.find("KHR_texture_transform"); t != info.extensions.end()) {
    read_transform(t->second, at + "/extensions/KHR_texture_transform", ref);
  }
  if (ref.texcoord < 0 || ref.texcoord > 1)
    fail(path_, 0, at + "/texCoord: TEXCOORD_" + std::to_string(ref.texcoord) + " is not read (caustica reads sets 0 and 1)");
  const auto key = std::make_pair(info.index, srgb);
  if (const auto found = index_.find(key); found != index_.end()) {
    ref.texture = found->second;
  } else {
    ref.texture = static_cast<int>(textures_.size());
    textures_.push_back(decode(info.index, srgb));
    index_[key] = ref.texture;
  }
  return ref;
}

glm::vec4 TextureTable::mean(int index) const {
  const Texture& t = textures_[static_cast<size_t>(index)];
  glm::dvec4 sum(0.0);
  for (uint32_t y = 0; y < t.height; ++y) {
    for (uint32_t x = 0; x < t.width; ++x) {
      sum += glm::dvec4(t.sample((glm::vec2(x, y) + 0.5f) / glm::vec2(static_cast<float>(t.width), static_cast<float>(t.height))));
    }
  }
  return glm::vec4(sum / std::max(1.0, static_cast<double>(t.width) * t.height));
}

void TextureTable::read_transform(const tinygltf::Value& v, const std::string& at, TextureRef& ref) const {
  auto pair = [&](const char* key, glm::vec2 fallback) {
    if (!v.Has(key)) return fallback;
    const auto& a = v.Get(key);
    if (!a.IsArray() || a.ArrayLen() != 2 || !a.Get(0).IsNumber() || !a.Get(1).IsNumber())
      fail(path_, 0, at + "/" + key + ": needs 2 numbers");
    const glm::vec2 out(a.Get(0).GetNumberAsDouble(), a.Get(1).GetNumberAsDouble());
    if (!std::isfinite(out.x) || !std::isfinite(out.y)) fail(path_, 0, at + "/" + key + ": must be finite numbers");
    return out;
  };
  const glm::vec2 offset = pair("offset", glm::vec2(0.0f)), scale = pair("scale", glm::vec2(1.0f));
  float rotation = 0.0f;
  if (v.Has("rotation")) {
    if (!v.Get("rotation").IsNumber() || !std::isfinite(v.Get("rotation").GetNumberAsDouble()))
      fail(path_, 0, at + "/rotation: must be a finite number");
    rotation = static_cast<float>(v.Get("rotation").GetNumberAsDouble());
  }
  if (v.Has("texCoord")) {
    if (!v.Get("texCoord").IsInt()) fail(path_, 0, at + "/texCoord: must be an integer");
    ref.texcoord = v.Get("texCoord").GetNumberAsInt();
  }
  const float c = std::cos(rotation), s = std::sin(rotation);
  const glm::mat3 translate(glm::vec3(1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(offset, 1));
  const glm::mat3 rotate(glm::vec3(c, -s, 0), glm::vec3(s, c, 0), glm::vec3(0, 0, 1));
  const glm::mat3 stretch(glm::vec3(scale.x, 0, 0), glm::vec3(0, scale.y, 0), glm::vec3(0, 0, 1));
  ref.transform = translate * rotate * stretch;
}

Texture TextureTable::decode(int index, bool srgb) const {
  const std::string at = "/textures/" + std::to_string(index);
  const auto& texture = model_.textures[static_cast<size_t>(index)];
  if (texture.source < 0 || static_cast<size_t>(texture.source) >= model_.images.size()) {
    fail(path_, 0,
         at + "/source: " + (texture.source < 0 ? std::string("missing") : "image " + std::to_string(texture.source) + " does not exist") +
             " (caustica decodes PNG and JPEG images, not KHR_texture_basisu or EXT_texture_webp)");
  }
  const auto& image = model_.images[static_cast<size_t>(texture.source)];
  const std::string image_at = "/images/" + std::to_string(texture.source);
  Texture out;
  out.name = path_ + ": " + at;
  out.srgb = srgb;
  tinygltf::Image decoded;
  std::string error, warning;
  if (image.image.empty() || image.image.size() > static_cast<size_t>(std::numeric_limits<int>::max()) ||
      !tinygltf::LoadImageData(&decoded, texture.source, &error, &warning, 0, 0, image.image.data(), static_cast<int>(image.image.size()),
                               nullptr)) {
    fail(path_, 0,
         image_at + ": cannot decode the image" + (image.uri.empty() || image.uri.rfind("data:", 0) == 0 ? "" : " '" + image.uri + "'") +
             " (caustica decodes PNG and JPEG)");
  }
  if (decoded.component != 4 || (decoded.bits != 8 && decoded.bits != 16) || decoded.width <= 0 || decoded.height <= 0)
    fail(path_, 0, image_at + ": the image decodes to a layout caustica does not read");
  out.width = static_cast<uint32_t>(decoded.width);
  out.height = static_cast<uint32_t>(decoded.height);
  const size_t values = size_t{out.width} * out.height * 4;
  out.rgba.resize(values);
  if (decoded.bits == 8) {
    std::memcpy(out.rgba.data(), decoded.image.data(), values);
  } else {  // 16 bits: the high byte (host order, as stb_image gives them)
    for (size_t i = 0; i < values; ++i) {
      uint16_t v = 0;
      std::memcpy(&v, decoded.image.data() + 2 * i, 2);
      out.rgba[i] = static_cast<uint8_t>(v >> 8);
    }
  }
  if (texture.sampler >= 0) {
    if (static_cast<size_t>(texture.sampler) >= model_.samplers.size())
      fail(path_, 0, at + "/sampler: sampler " + std::to_string(texture.sampler) + " does not exist");
    const auto& sampler = model_.samplers[static_cast<size_t>(texture.sampler)];
    const std::string sampler_at = "/samplers/" + std::to_string(texture.sampler);
    auto wrap = [&](int mode, const char* key) {
      switch (mode) {
        case TINYGLTF_TEXTURE_WRAP_REPEAT: return Wrap::repeat;
        case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE: return Wrap::clamp;
        case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT: return Wrap::mirror;
        default: fail(path_, 0, sampler_at + "/" + key + ": " + std::to_string(mode) + " is not a wrap mode (10497, 33071 or 33648)");
      }
    };
    out.wrap_u = wrap(sampler.wrapS, "wrapS");
    out.wrap_v = wrap(sampler.wrapT, "wrapT");
    if (sampler.magFilter != -1 && sampler.magFilter != TINYGLTF_TEXTURE_FILTER_NEAREST &&
        sampler.magFilter != TINYGLTF_TEXTURE_FILTER_LINEAR)
      fail(path_, 0, sampler_at + "/magFilter: " + std::to_string(sampler.magFilter) + " is not a filter (9728 or 9729)");
    out.nearest = sampler.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST;
  }
  return out;
}

}  // namespace caustica::scene::gltf
