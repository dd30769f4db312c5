// Texture sampling on the host, as a Vulkan sampler reads the full-resolution level: what the
// exact tracers see of a textured material.
#include <algorithm>
#include <array>
#include <cmath>

#include "scene/scene.h"

namespace caustica::scene {
namespace {

// Texel index i of a row or column of `size`, by the sampler's wrap mode.
int wrap_index(int i, int size, Wrap mode) {
  switch (mode) {
    case Wrap::clamp: return std::clamp(i, 0, size - 1);
    case Wrap::mirror: {
      const int period = 2 * size;
      int m = i % period;
      if (m < 0) m += period;
      return m < size ? m : period - 1 - m;
    }
    case Wrap::repeat:
    default: {
      const int m = i % size;
      return m < 0 ? m + size : m;
    }
  }
}

}  // namespace

float srgb_byte_to_linear(uint8_t byte) {
  static const std::array<float, 256> kDecoded = [] {
    std::array<float, 256> table{};
    for (size_t i = 0; i < 256; ++i) {
      const float encoded = static_cast<float>(i) / 255.0f;
      table[i] = encoded <= 0.04045f ? encoded / 12.92f : std::pow((encoded + 0.055f) / 1.055f, 2.4f);
    }
    return table;
  }();
  return kDecoded[byte];
}

glm::vec4 Texture::sample(glm::vec2 uv) const {
  if (width == 0 || height == 0) return glm::vec4(1.0f);
  // sRGB decoding per texel comes before filtering, as with an sRGB image format.
  auto texel = [&](int x, int y) {
    const size_t at = (static_cast<size_t>(wrap_index(y, static_cast<int>(height), wrap_v)) * width +
                       static_cast<size_t>(wrap_index(x, static_cast<int>(width), wrap_u))) *
                      4;
    glm::vec4 v;
    for (int c = 0; c < 4; ++c) {
      const uint8_t byte = rgba[at + static_cast<size_t>(c)];
      v[c] = srgb && c < 3 ? srgb_byte_to_linear(byte) : static_cast<float>(byte) / 255.0f;
    }
    return v;
  };
  // Guard against coordinates too large for an int texel index (they repeat anyway).
  const glm::vec2 p = glm::clamp(uv, glm::vec2(-1e6f), glm::vec2(1e6f)) * glm::vec2(static_cast<float>(width), static_cast<float>(height));
  if (nearest) return texel(static_cast<int>(std::floor(p.x)), static_cast<int>(std::floor(p.y)));
  const glm::vec2 c = p - 0.5f, base = glm::floor(c), f = c - base;
  const int x = static_cast<int>(base.x), y = static_cast<int>(base.y);
  return glm::mix(glm::mix(texel(x, y), texel(x + 1, y), f.x), glm::mix(texel(x, y + 1), texel(x + 1, y + 1), f.x), f.y);
}

glm::vec2 texture_coordinates(const TextureRef& ref, glm::vec4 uv) {
  return glm::vec2(ref.transform * glm::vec3(ref.texcoord == 1 ? glm::vec2(uv.z, uv.w) : glm::vec2(uv.x, uv.y), 1.0f));
}

glm::vec4 texel_at(const Scene& scene, const Object& object, const TextureRef& ref, uint32_t triangle, float u, float v) {
  if (!ref.used()) return glm::vec4(1.0f);
  glm::vec4 uv(0.0f);
  if (!object.mesh.texcoords.empty()) {
    const uint32_t* corner = &object.mesh.indices[3 * size_t{triangle}];
    uv = (1 - u - v) * object.mesh.texcoords[corner[0]] + u * object.mesh.texcoords[corner[1]] + v * object.mesh.texcoords[corner[2]];
  }
  return scene.textures[static_cast<size_t>(ref.texture)].sample(texture_coordinates(ref, uv));
}

}  // namespace caustica::scene
