#pragma once
// A glTF file's materials and the textures they name (gltf_material.cpp, gltf_textures.cpp), for
// load_gltf (gltf_loader.cpp). Errors name the file and the value's JSON pointer.
#include <glm/glm.hpp>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "scene/scene.h"

namespace tinygltf {
class Model;
class Value;
struct TextureInfo;
}  // namespace tinygltf

namespace caustica::scene::gltf {

// The textures a file's materials use, each decoded when a material first names it, so that an
// image no material reads is never decoded. One entry per glTF texture and colour space.
class TextureTable {
 public:
  TextureTable(const tinygltf::Model& model, const std::string& path) : model_(model), path_(path) {}

  // `info` is at JSON pointer `at`; `srgb` for colour data.
  TextureRef reference(const tinygltf::TextureInfo& info, const std::string& at, bool srgb);

  std::vector<Texture> take() { return std::move(textures_); }

  // The mean linear value of texture `index` over its texels.
  glm::vec4 mean(int index) const;

 private:
  // KHR_texture_transform: uv' = translation * rotation * scale * uv, as the extension defines it.
  void read_transform(const tinygltf::Value& v, const std::string& at, TextureRef& ref) const;
  Texture decode(int index, bool srgb) const;

  const tinygltf::Model& model_;
  std::string path_;
  std::map<std::pair<int, bool>, int> index_;
  std::vector<Texture> textures_;
};

// A material as the specification and its ratified extensions give it; a value outside their
// ranges or of the wrong type is an error naming its JSON pointer. `from` is the pointer of the
// primitive's "material" (for a missing one).
Material gltf_material(const tinygltf::Model& model, int index, const std::string& from, const std::string& path, TextureTable& textures);

}  // namespace caustica::scene::gltf
