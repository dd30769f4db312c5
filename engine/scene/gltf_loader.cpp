// glTF 2.0 through tinygltf: the scene's nodes, meshes, cameras and lights, with the ratified
// extensions docs/gltf.md lists; each primitive's material through gltf_material.h.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <map>
#include <optional>
#include <sstream>
#include <type_traits>

#include "core/error.h"
#include "io/json_reader.h"
#include "scene/gltf_compression.h"
#include "scene/gltf_material.h"
#include "scene/mesh_formats.h"
#include "scene/scene.h"

#include <tiny_gltf.h>  // the implementation is Debian's libtinygltf

namespace caustica::scene::formats {
namespace {

glm::mat4 node_matrix(const tinygltf::Node& node) {
  if (node.matrix.size() == 16) return glm::make_mat4(std::vector<float>(node.matrix.begin(), node.matrix.end()).data());
  glm::mat4 m(1.0f);
  if (node.translation.size() == 3) m = glm::translate(m, glm::vec3(node.translation[0], node.translation[1], node.translation[2]));
  if (node.rotation.size() == 4) {
    m *= glm::mat4_cast(glm::quat(static_cast<float>(node.rotation[3]), static_cast<float>(node.rotation[0]),
                                  static_cast<float>(node.rotation[1]), static_cast<float>(node.rotation[2])));
  }
  if (node.scale.size() == 3) m = glm::scale(m, glm::vec3(node.scale[0], node.scale[1], node.scale[2]));
  return m;
}

// One component as a number. Normalized integers map to [0, 1] or [-1, 1] as the specification
// says (KHR_mesh_quantization stores positions and normals this way); others keep their value.
double read_component(const unsigned char* q, int type, bool normalized) {
  auto load = [q](auto v) {
    std::memcpy(&v, q, sizeof v);
    return v;
  };
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return static_cast<double>(load(0.0f));
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return load(uint32_t{0});
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return normalized ? load(uint16_t{0}) / 65535.0 : load(uint16_t{0});
    case TINYGLTF_COMPONENT_TYPE_SHORT: return normalized ? std::max(load(int16_t{0}) / 32767.0, -1.0) : load(int16_t{0});
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return normalized ? load(uint8_t{0}) / 255.0 : load(uint8_t{0});
    case TINYGLTF_COMPONENT_TYPE_BYTE: return normalized ? std::max(load(int8_t{0}) / 127.0, -1.0) : load(int8_t{0});
    default: return std::nan("");
  }
}

// Where `count` elements of `element` bytes, `stride` apart, lie in a buffer view; checked.
const unsigned char* view_data(const tinygltf::Model& model, int view_index, size_t offset, size_t count, size_t element, size_t stride,
                               const std::string& what, const std::string& path) {
  if (view_index < 0 || static_cast<size_t>(view_index) >= model.bufferViews.size()) fail(path, 0, what + " has no valid buffer view");
  const auto& view = model.bufferViews[static_cast<size_t>(view_index)];
  if (view.buffer < 0 || static_cast<size_t>(view.buffer) >= model.buffers.size()) fail(path, 0, "a buffer view names a missing buffer");
  const auto& buffer = model.buffers[static_cast<size_t>(view.buffer)].data;
  if (view.byteOffset + view.byteLength > buffer.size()) fail(path, 0, what + ": its buffer view is longer than its buffer");
  if (count > 0 && (offset + (count - 1) * stride + element > view.byteLength)) fail(path, 0, what + " reads past the end of its buffer");
  return buffer.data() + view.byteOffset + offset;
}

// Reads accessor `index` as `components` numbers per element: any component type, normalized or
// not, from a buffer view or (none given) zeros, with its sparse substitutions applied.
template <typename T>
std::vector<T> read_accessor(const tinygltf::Model& model, int index, int components, const std::string& path) {
  if (index < 0 || static_cast<size_t>(index) >= model.accessors.size())
    fail(path, 0, "accessor " + std::to_string(index) + " does not exist");
  const auto& accessor = model.accessors[static_cast<size_t>(index)];
  const std::string what = "accessor " + std::to_string(index);
  if (tinygltf::GetNumComponentsInType(static_cast<uint32_t>(accessor.type)) != components) fail(path, 0, what + " has the wrong type");
  const int component_size = tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(accessor.componentType));
  if (component_size <= 0) fail(path, 0, what + " has an unknown component type");
  if (accessor.count > (size_t{1} << 28)) fail(path, 0, what + " has " + std::to_string(accessor.count) + " elements, more than 2^28");
  const size_t element = static_cast<size_t>(component_size) * static_cast<size_t>(components);
  std::vector<double> values(accessor.count * static_cast<size_t>(components), 0.0);
  auto read_elements = [&](const unsigned char* data, size_t stride, size_t count, auto&& target) {
    for (size_t i = 0; i < count; ++i) {
      for (int c = 0; c < components; ++c) {
        target(i, c,
               read_component(data + i * stride + static_cast<size_t>(c * component_size), accessor.componentType, accessor.normalized));
      }
    }
  };
  if (accessor.bufferView >= 0) {
    if (static_cast<size_t>(accessor.bufferView) >= model.bufferViews.size()) fail(path, 0, what + " has no valid buffer view");
    const int stride = accessor.ByteStride(model.bufferViews[static_cast<size_t>(accessor.bufferView)]);
    if (stride <= 0 || static_cast<size_t>(stride) < element)
      fail(path, 0, what + ": its buffer view's byteStride does not fit its elements");
    const auto step = static_cast<size_t>(stride);
    const unsigned char* data = view_data(model, accessor.bufferView, accessor.byteOffset, accessor.count, element, step, what, path);
    read_elements(data, step, accessor.count,
                  [&](size_t i, int c, double v) { values[i * static_cast<size_t>(components) + static_cast<size_t>(c)] = v; });
  }
  if (accessor.sparse.isSparse) {
    const auto count = static_cast<size_t>(std::max(accessor.sparse.count, 0));
    const int index_size = tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(accessor.sparse.indices.componentType));
    if (index_size <= 0 || count > accessor.count) fail(path, 0, what + " has invalid sparse indices");
    const unsigned char* indices =
        view_data(model, accessor.sparse.indices.bufferView, static_cast<size_t>(accessor.sparse.indices.byteOffset), count,
                  static_cast<size_t>(index_size), static_cast<size_t>(index_size), what + "'s sparse indices", path);
    const unsigned char* data = view_data(model, accessor.sparse.values.bufferView, static_cast<size_t>(accessor.sparse.values.byteOffset),
                                          count, element, element, what + "'s sparse values", path);
    for (size_t k = 0; k < count; ++k) {
      const double target = read_component(indices + k * static_cast<size_t>(index_size), accessor.sparse.indices.componentType, false);
      if (!(target >= 0 && target < static_cast<double>(accessor.count))) fail(path, 0, what + " has a sparse index out of range");
      for (int c = 0; c < components; ++c) {
        values[static_cast<size_t>(target) * static_cast<size_t>(components) + static_cast<size_t>(c)] =
            read_component(data + k * element + static_cast<size_t>(c * component_size), accessor.componentType, accessor.normalized);
      }
    }
  }
  std::vector<T> out;
  out.reserve(values.size());
  for (double v : values) {
    if (!std::isfinite(v) || (std::is_unsigned_v<T> && v < 0))
      fail(path, 0, what + " holds a value that is not a finite number" + (std::is_unsigned_v<T> ? " of 0 or more" : ""));
    out.push_back(static_cast<T>(v));
  }
  return out;
}

// The extensions whose content caustica reads: a file that requires any other is refused, and one
// that uses any other is read with a warning (unread_content).
const std::vector<std::string> kReadExtensions = {"KHR_materials_transmission",
                                                  "KHR_materials_ior",
                                                  "KHR_materials_volume",
                                                  "KHR_materials_dispersion",
                                                  "KHR_materials_specular",
                                                  "KHR_materials_clearcoat",
                                                  "KHR_materials_iridescence",
                                                  "KHR_materials_emissive_strength",
                                                  "KHR_materials_sheen",
                                                  "KHR_materials_anisotropy",
                                                  "KHR_materials_diffuse_transmission",
                                                  "KHR_lights_punctual",
                                                  "KHR_mesh_quantization",
                                                  "EXT_meshopt_compression",
                                                  "KHR_draco_mesh_compression",
                                                  "KHR_texture_transform"};

// What the picture loses where a file uses an extension caustica does not read.
std::string what_is_ignored(const std::string& extension) {
  static const std::map<std::string, std::string> kIgnored = {
      {"KHR_materials_unlit", "unlit shading (lit as the metallic-roughness model)"},
      {"KHR_materials_variants", "the material variants (each primitive's own material is drawn)"},
      {"EXT_mesh_gpu_instancing", "the instances (each mesh is drawn once, at its node)"},
      {"KHR_xmp_json_ld", "the metadata (which does not change the picture)"},
      {"KHR_xmp", "the metadata (which does not change the picture)"}};
  const auto it = kIgnored.find(extension);
  return it == kIgnored.end() ? "its content" : it->second;
}

// Warnings for what the file says and caustica does not draw: each extension it uses and caustica
// does not read (with the materials that use it), and an opaque surface's layer on a transmissive
// material.
std::vector<std::string> unread_content(const tinygltf::Model& model, const std::string& path) {
  std::vector<std::string> warnings;
  for (const auto& used : model.extensionsUsed) {
    if (std::find(kReadExtensions.begin(), kReadExtensions.end(), used) != kReadExtensions.end()) continue;
    std::string where;
    for (size_t i = 0; i < model.materials.size(); ++i) {
      if (model.materials[i].extensions.count(used) != 0) where += (where.empty() ? " (" : ", ") + ("/materials/" + std::to_string(i));
    }
    warnings.push_back(path + ": uses " + used + ", which caustica does not read: " + what_is_ignored(used) + " is ignored" +
                       (where.empty() ? "" : where + ")"));
  }
  for (size_t i = 0; i < model.materials.size(); ++i) {
    const auto& extensions = model.materials[i].extensions;
    const auto transmission = extensions.find("KHR_materials_transmission");
    const bool transmits = transmission != extensions.end() && transmission->second.Has("transmissionFactor") &&
                           transmission->second.Get("transmissionFactor").IsNumber() &&
                           transmission->second.Get("transmissionFactor").GetNumberAsDouble() > 0.0;
    // The lighting pass shades opaque surfaces; a refractor's surface is its interface.
    for (const char* layer : {"KHR_materials_sheen", "KHR_materials_anisotropy", "KHR_materials_diffuse_transmission"}) {
      if (transmits && extensions.count(layer) != 0) {
        warnings.push_back(path + ": /materials/" + std::to_string(i) + " uses " + layer +
                           ", which caustica draws on opaque surfaces only: on this transmissive one it is ignored");
      }
    }
  }
  return warnings;
}

// TEXCOORD_0 and TEXCOORD_1, when the primitive has either, into mesh.texcoords.
void read_texcoords(const tinygltf::Model& model, const tinygltf::Primitive& prim, const std::optional<gltf::DracoGeometry>& draco,
                    Mesh& mesh, const std::string& pointer, const std::string& path) {
  for (int set = 0; set < 2; ++set) {
    const std::string name = "TEXCOORD_" + std::to_string(set);
    const auto attribute = prim.attributes.find(name);
    if (attribute == prim.attributes.end()) continue;
    const auto uv =
        draco && !draco->texcoords[set].empty() ? draco->texcoords[set] : read_accessor<float>(model, attribute->second, 2, path);
    if (uv.size() / 2 != mesh.positions.size())
      fail(path, 0,
           pointer + "/attributes/" + name + ": " + std::to_string(uv.size() / 2) + " coordinates for " +
               std::to_string(mesh.positions.size()) + " positions");
    mesh.texcoords.resize(mesh.positions.size(), glm::vec4(0.0f));
    for (size_t i = 0; i < mesh.positions.size(); ++i) {
      mesh.texcoords[i][2 * set] = uv[2 * i];
      mesh.texcoords[i][2 * set + 1] = uv[2 * i + 1];
    }
  }
}

// TANGENT, when the primitive has it, into mesh.tangents, carried by the node's transform `world`.
void read_tangents(const tinygltf::Model& model, const tinygltf::Primitive& prim, const std::optional<gltf::DracoGeometry>& draco,
                   const glm::mat4& world, Mesh& mesh, const std::string& pointer, const std::string& path) {
  const auto attribute = prim.attributes.find("TANGENT");
  if (attribute == prim.attributes.end()) return;
  const auto t = draco && !draco->tangents.empty() ? draco->tangents : read_accessor<float>(model, attribute->second, 4, path);
  if (t.size() / 4 != mesh.positions.size())
    fail(path, 0,
         pointer + "/attributes/TANGENT: " + std::to_string(t.size() / 4) + " tangents for " + std::to_string(mesh.positions.size()) +
             " positions");
  mesh.tangents.reserve(mesh.positions.size());
  for (size_t i = 0; i + 3 < t.size(); i += 4) mesh.tangents.push_back(carry_tangent(world, glm::vec4(t[i], t[i + 1], t[i + 2], t[i + 3])));
}

// Images are kept as their encoded bytes: TextureTable decodes the ones a material uses.
bool keep_encoded_image(tinygltf::Image* image, const int, std::string*, std::string*, int, int, const unsigned char* bytes, int size,
                        void*) {
  image->image.assign(bytes, bytes + std::max(size, 0));
  image->as_is = true;
  return true;
}

}  // namespace

namespace {

std::vector<unsigned char> read_model_bytes(const std::string& path, bool binary) {
  std::vector<unsigned char> bytes;
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, 0, "cannot open the file");
  in.seekg(0, std::ios::end);
  const auto size = static_cast<size_t>(std::max<std::streamoff>(in.tellg(), 0));
  if (size > kMaxMeshFileBytes) fail(path, 0, "the file is larger than " + std::to_string(kMaxMeshFileBytes >> 20) + " MiB");
  in.seekg(0);
  bytes.resize(size);
  if (!in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(size))) fail(path, 0, "cannot read the file");
  // tinygltf reads the GLB container without looking at its version; version 1 was a different format.
  if (binary && bytes.size() >= 8 && std::memcmp(bytes.data(), "glTF", 4) == 0) {
    uint32_t version = 0;
    std::memcpy(&version, bytes.data() + 4, 4);
    if (version != 2) fail(path, 0, "binary glTF version " + std::to_string(version) + ": only version 2 is supported");
  }
  return bytes;
}

// tinygltf's parse of the prepared file, refused where caustica cannot read it as the
// specification says: another version, an extension it requires that caustica does not read.
tinygltf::Model parse_model(const std::string& path, const gltf::PreparedFile& prepared, bool binary) {
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(keep_encoded_image, nullptr);
  tinygltf::Model model;
  std::string error, warning;
  const std::string base_dir = std::filesystem::path(path).parent_path().string();
  const auto& data = prepared.bytes;
  const bool ok = binary
                      ? loader.LoadBinaryFromMemory(&model, &error, &warning, data.data(), static_cast<unsigned int>(data.size()), base_dir)
                      : loader.LoadASCIIFromString(&model, &error, &warning, reinterpret_cast<const char*>(data.data()),
                                                   static_cast<unsigned int>(data.size()), base_dir);
  if (!ok) {
    while (!error.empty() && (error.back() == '\n' || error.back() == ' ')) error.pop_back();
    fail(path, 0, "not a valid glTF file: " + (error.empty() ? std::string("tinygltf gave no reason") : error));
  }
  if (model.asset.version.rfind("2.", 0) != 0) {
    fail(path, 0, "/asset/version: '" + model.asset.version + "' is not a glTF version caustica reads (2.x)");
  }
  for (const auto& required : model.extensionsRequired) {
    if (std::find(kReadExtensions.begin(), kReadExtensions.end(), required) == kReadExtensions.end()) {
      fail(path, 0,
           "requires the extension " + required +
               ", which caustica does not read (it reads KHR_materials_transmission, _ior, _volume, _dispersion, _specular, "
               "_clearcoat, _iridescence, _emissive_strength, KHR_lights_punctual, KHR_mesh_quantization, EXT_meshopt_compression, "
               "KHR_draco_mesh_compression and KHR_texture_transform)");
    }
  }
  return model;
}

// Every image a URI names beside the file exists (a URI's %XX escapes decoded).
void check_image_files(const tinygltf::Model& model, const std::string& path) {
  for (size_t i = 0; i < model.images.size(); ++i) {
    const std::string& uri = model.images[i].uri;
    if (uri.empty() || uri.rfind("data:", 0) == 0) continue;
    std::string decoded;
    for (size_t k = 0; k < uri.size(); ++k) {
      if (uri[k] == '%' && k + 2 < uri.size() && std::isxdigit(static_cast<unsigned char>(uri[k + 1])) &&
          std::isxdigit(static_cast<unsigned char>(uri[k + 2]))) {
        decoded += static_cast<char>(std::stoi(uri.substr(k + 1, 2), nullptr, 16));
        k += 2;
      } else {
        decoded += uri[k];
      }
    }
    const auto file = std::filesystem::path(path).parent_path() / decoded;
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec))
      fail(path, 0, "image " + std::to_string(i) + ": cannot read '" + uri + "' (" + file.string() + ")");
  }
}

// The nodes' contents in world space: the first camera, the punctual lights, the triangle
// primitives with their materials.
class NodeReader {
 public:
  NodeReader(const tinygltf::Model& model, const gltf::PreparedFile& prepared, const std::string& path, gltf::TextureTable& textures,
             ModelFile& out)
      : model_(model), prepared_(prepared), path_(path), textures_(textures), out_(out) {}

  void visit(int node_index, const glm::mat4& parent) {
    if (node_index < 0 || static_cast<size_t>(node_index) >= model_.nodes.size())
      fail(path_, 0, "node " + std::to_string(node_index) + " does not exist");
    if (std::find(visiting_.begin(), visiting_.end(), node_index) != visiting_.end())
      fail(path_, 0, "node " + std::to_string(node_index) + " is its own ancestor");
    visiting_.push_back(node_index);
    const auto& node = model_.nodes[static_cast<size_t>(node_index)];
    const glm::mat4 world = parent * node_matrix(node);
    read_camera(node, world);
    read_light(node, node_index, world);
    if (node.mesh >= 0) {
      if (static_cast<size_t>(node.mesh) >= model_.meshes.size())
        fail(path_, 0, "node " + std::to_string(node_index) + " names a missing mesh");
      const auto& mesh = model_.meshes[static_cast<size_t>(node.mesh)];
      for (const auto& prim : mesh.primitives) {
        if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != -1) continue;  // points and lines do not refract
        out_.parts.push_back(read_primitive(node.mesh, mesh, static_cast<size_t>(&prim - mesh.primitives.data()), world));
      }
    }
    for (int child : node.children) visit(child, world);
    visiting_.pop_back();
  }

 private:
  // Cameras and lights look down their node's -Z.
  static glm::vec3 forward(const glm::mat4& world) { return glm::normalize(glm::vec3(world * glm::vec4(0, 0, -1, 0))); }

  void read_camera(const tinygltf::Node& node, const glm::mat4& world) {
    if (node.camera < 0 || out_.camera || static_cast<size_t>(node.camera) >= model_.cameras.size()) return;
    const auto& camera = model_.cameras[static_cast<size_t>(node.camera)];
    View view;
    view.position = glm::vec3(world[3]);
    view.target = view.position + forward(world);
    if (camera.type == "perspective") {
      view.fov_y_degrees = static_cast<float>(glm::degrees(camera.perspective.yfov));
      if (camera.perspective.znear > 0) view.near_plane = static_cast<float>(camera.perspective.znear);
      if (camera.perspective.zfar > camera.perspective.znear) view.far_plane = static_cast<float>(camera.perspective.zfar);
    }
    out_.camera = view;
    out_.camera_is_orthographic = camera.type == "orthographic";
  }

  void read_light(const tinygltf::Node& node, int node_index, const glm::mat4& world) {
    const auto ext = node.extensions.find("KHR_lights_punctual");
    if (ext == node.extensions.end() || !ext->second.Has("light")) return;
    const int index = ext->second.Get("light").GetNumberAsInt();
    if (index < 0 || static_cast<size_t>(index) >= model_.lights.size())
      fail(path_, 0, "node " + std::to_string(node_index) + " names a missing light");
    const auto& l = model_.lights[static_cast<size_t>(index)];
    ModelLight light;
    light.type = l.type;
    light.position = glm::vec3(world[3]);
    light.direction = forward(world);
    light.intensity = static_cast<float>(l.intensity);
    if (l.color.size() == 3) light.color = glm::vec3(l.color[0], l.color[1], l.color[2]);
    light.cone_degrees = static_cast<float>(glm::degrees(2.0 * l.spot.outerConeAngle));
    out_.lights.push_back(light);
  }

  MeshPart read_primitive(int mesh_index, const tinygltf::Mesh& mesh, size_t primitive_index, const glm::mat4& world) const {
    const tinygltf::Primitive& prim = mesh.primitives[primitive_index];
    auto position = prim.attributes.find("POSITION");
    if (position == prim.attributes.end()) fail(path_, 0, "a primitive of mesh '" + mesh.name + "' has no POSITION");
    MeshPart part;
    part.name = mesh.name;
    const std::string pointer = "/meshes/" + std::to_string(mesh_index) + "/primitives/" + std::to_string(primitive_index);
    std::optional<gltf::DracoGeometry> draco;
    if (prim.extensions.count("KHR_draco_mesh_compression")) {
      const auto indices = prepared_.draco_indices.find({static_cast<size_t>(mesh_index), primitive_index});
      draco = gltf::decode_draco(model_, prim, indices == prepared_.draco_indices.end() ? -1 : indices->second, pointer, path_);
    }
    const auto p = draco ? draco->positions : read_accessor<float>(model_, position->second, 3, path_);
    for (size_t i = 0; i + 2 < p.size(); i += 3)
      part.mesh.positions.push_back(glm::vec3(world * glm::vec4(p[i], p[i + 1], p[i + 2], 1.0f)));
    auto normal = prim.attributes.find("NORMAL");
    if (normal != prim.attributes.end()) {
      const glm::mat3 normal_matrix = glm::transpose(glm::inverse(glm::mat3(world)));
      const auto n = draco && !draco->normals.empty() ? draco->normals : read_accessor<float>(model_, normal->second, 3, path_);
      if (n.size() != p.size()) fail(path_, 0, "NORMAL and POSITION of mesh '" + mesh.name + "' differ in count");
      for (size_t i = 0; i + 2 < n.size(); i += 3) {
        glm::vec3 v = normal_matrix * glm::vec3(n[i], n[i + 1], n[i + 2]);
        float len = glm::length(v);
        part.mesh.normals.push_back(len > 0 && std::isfinite(len) ? v / len : glm::vec3(0, 1, 0));
      }
      // The specification ignores tangents where the normals are computed, so only here.
      read_tangents(model_, prim, draco, world, part.mesh, pointer, path_);
    }
    if (draco) {
      part.mesh.indices = draco->indices;
    } else if (prim.indices >= 0) {
      part.mesh.indices = read_accessor<uint32_t>(model_, prim.indices, 1, path_);
    } else {
      for (uint32_t i = 0; i < part.mesh.positions.size(); ++i) part.mesh.indices.push_back(i);
    }
    part.mesh.indices.resize(part.mesh.indices.size() / 3 * 3);
    part.material = gltf::gltf_material(model_, prim.material, pointer + "/material", path_, textures_);
    read_texcoords(model_, prim, draco, part.mesh, pointer, path_);
    return part;
  }

  const tinygltf::Model& model_;
  const gltf::PreparedFile& prepared_;
  const std::string& path_;
  gltf::TextureTable& textures_;
  ModelFile& out_;
  std::vector<int> visiting_;  // guards against node cycles, which the spec forbids
};

}  // namespace

ModelFile load_gltf(const std::string& path) {
  const bool binary = std::filesystem::path(path).extension() == ".glb";
  const gltf::PreparedFile prepared = gltf::prepare(read_model_bytes(path, binary), binary);
  tinygltf::Model model = parse_model(path, prepared, binary);
  check_image_files(model, path);
  gltf::decode_meshopt(model, prepared, path);
  ModelFile out;
  gltf::TextureTable textures(model, path);
  NodeReader reader(model, prepared, path, textures, out);
  if (model.scenes.empty()) {
    for (size_t n = 0; n < model.nodes.size(); ++n) reader.visit(static_cast<int>(n), glm::mat4(1.0f));
  } else {
    const int scene = model.defaultScene >= 0 ? model.defaultScene : 0;
    if (static_cast<size_t>(scene) >= model.scenes.size()) fail(path, 0, "the default scene does not exist");
    for (int root : model.scenes[static_cast<size_t>(scene)].nodes) reader.visit(root, glm::mat4(1.0f));
  }
  if (out.parts.empty()) fail(path, 0, "the file has no triangle meshes");
  out.textures = textures.take();
  out.images = model.images.size();
  out.warnings = unread_content(model, path);
  return out;
}

}  // namespace caustica::scene::formats
