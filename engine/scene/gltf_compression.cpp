#include "scene/gltf_compression.h"

#include <draco/compression/decode.h>
#include <meshoptimizer.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>

#include "core/error.h"

#include <tiny_gltf.h>

namespace caustica::scene::gltf {
namespace {

// Decoded views and meshes are refused beyond this (the fuzzer's "huge counts"); 1 GiB is far more
// than a model caustica can trace interactively.
constexpr uint64_t kMaxDecodedBytes = uint64_t{1} << 30;

[[noreturn]] void fail(const std::string& path, const std::string& message) {
  throw InputError(path + ": " + message);
}

uint32_t read_u32(const unsigned char* p) {
  uint32_t v = 0;
  std::memcpy(&v, p, 4);
  return v;
}
void append_u32(std::vector<unsigned char>& out, uint32_t v) {
  const auto* p = reinterpret_cast<const unsigned char*>(&v);
  out.insert(out.end(), p, p + 4);
}

// A GLB's JSON chunk and its BIN chunk (empty when it has none).
struct GlbChunks {
  std::string json;
  std::vector<unsigned char> bin;
  bool has_bin = false;
};

// The chunks of a well-formed GLB; nothing for anything else (tinygltf then says what is wrong).
std::optional<GlbChunks> split_glb(const std::vector<unsigned char>& bytes) {
  if (bytes.size() < 20 || std::memcmp(bytes.data(), "glTF", 4) != 0 || read_u32(bytes.data() + 8) > bytes.size()) return std::nullopt;
  GlbChunks chunks;
  size_t at = 12;
  const size_t end = read_u32(bytes.data() + 8);
  for (int chunk = 0; at + 8 <= end && chunk < 2; ++chunk) {
    const size_t length = read_u32(bytes.data() + at);
    const uint32_t type = read_u32(bytes.data() + at + 4);
    if (length > end - at - 8) return std::nullopt;
    const auto* data = bytes.data() + at + 8;
    if (chunk == 0) {
      if (type != 0x4E4F534Au) return std::nullopt;
      chunks.json.assign(reinterpret_cast<const char*>(data), length);
    } else if (type == 0x004E4942u) {
      chunks.bin.assign(data, data + length);
      chunks.has_bin = true;
    }
    at += 8 + length;
  }
  if (chunks.json.empty()) return std::nullopt;
  return chunks;
}

std::vector<unsigned char> join_glb(std::string json, const GlbChunks& chunks) {
  while (json.size() % 4) json += ' ';
  std::vector<unsigned char> out;
  const size_t bin_padded = (chunks.bin.size() + 3) / 4 * 4;
  const size_t total = 12 + 8 + json.size() + (chunks.has_bin ? 8 + bin_padded : 0);
  out.reserve(total);
  append_u32(out, 0x46546C67u);  // "glTF"
  append_u32(out, 2);
  append_u32(out, static_cast<uint32_t>(total));
  append_u32(out, static_cast<uint32_t>(json.size()));
  append_u32(out, 0x4E4F534Au);
  out.insert(out.end(), json.begin(), json.end());
  if (chunks.has_bin) {
    append_u32(out, static_cast<uint32_t>(bin_padded));
    append_u32(out, 0x004E4942u);
    out.insert(out.end(), chunks.bin.begin(), chunks.bin.end());
    out.resize(total, 0);
  }
  return out;
}

// An integer member of an extension object, checked against [lo, hi].
uint64_t integer(const tinygltf::Value& object, const char* key, const std::string& pointer, uint64_t lo, uint64_t hi,
                 const std::string& path, std::optional<uint64_t> fallback = std::nullopt) {
  const std::string at = pointer + "/" + key;
  if (!object.Has(key)) {
    if (fallback) return *fallback;
    fail(path, at + ": is required");
  }
  const auto& v = object.Get(key);
  const double d = v.IsNumber() ? v.GetNumberAsDouble() : std::nan("");
  if (!(d >= static_cast<double>(lo) && d <= static_cast<double>(hi)) || std::floor(d) != d) {
    fail(path, at + ": must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  }
  return static_cast<uint64_t>(d);
}

std::string string_member(const tinygltf::Value& object, const char* key, const std::string& pointer, const std::string& fallback,
                          const std::string& path) {
  if (!object.Has(key)) return fallback;
  if (!object.Get(key).IsString()) fail(path, pointer + "/" + key + ": must be a string");
  return object.Get(key).Get<std::string>();
}

}  // namespace

PreparedFile prepare(std::vector<unsigned char> bytes, bool binary) {
  PreparedFile prepared;
  GlbChunks chunks;
  std::string text;
  if (binary) {
    const auto split = split_glb(bytes);
    if (!split) {
      prepared.bytes = std::move(bytes);
      return prepared;
    }
    chunks = *split;
    text = chunks.json;
  } else {
    text.assign(bytes.begin(), bytes.end());
  }
  auto doc = nlohmann::json::parse(text, nullptr, false);
  bool changed = false;
  if (doc.is_object()) {
    if (auto buffers = doc.find("buffers"); buffers != doc.end() && buffers->is_array()) {
      for (size_t i = 0; i < buffers->size(); ++i) {
        auto& buffer = (*buffers)[i];
        if (!buffer.is_object() || buffer.contains("uri")) continue;
        const auto ext = buffer.find("extensions");
        if (ext == buffer.end() || !ext->is_object() || !ext->contains("EXT_meshopt_compression")) continue;
        const auto& meshopt = (*ext)["EXT_meshopt_compression"];
        if (!meshopt.is_object() || meshopt.value("fallback", false) != true) continue;
        const auto length = buffer.find("byteLength");
        if (length == buffer.end() || !length->is_number_unsigned()) continue;  // tinygltf names the error
        prepared.fallback_bytes[i] = length->get<uint64_t>();
        buffer["uri"] = "data:application/octet-stream;base64,AA==";  // one byte: tinygltf refuses an empty data URI
        buffer["byteLength"] = 1;
        changed = true;
      }
    }
    if (auto meshes = doc.find("meshes"); meshes != doc.end() && meshes->is_array()) {
      for (size_t m = 0; m < meshes->size(); ++m) {
        auto primitives = (*meshes)[m].find("primitives");
        if (!(*meshes)[m].is_object() || primitives == (*meshes)[m].end() || !primitives->is_array()) continue;
        for (size_t p = 0; p < primitives->size(); ++p) {
          auto& primitive = (*primitives)[p];
          if (!primitive.is_object() || !primitive.contains("indices")) continue;
          const auto ext = primitive.find("extensions");
          if (ext == primitive.end() || !ext->is_object() || !ext->contains("KHR_draco_mesh_compression")) continue;
          if (!primitive["indices"].is_number_integer()) continue;  // tinygltf names the error
          prepared.draco_indices[{m, p}] = primitive["indices"].get<int>();
          primitive.erase("indices");
          changed = true;
        }
      }
    }
  }
  if (!changed) {
    prepared.bytes = std::move(bytes);
  } else if (binary) {
    prepared.bytes = join_glb(doc.dump(), chunks);
  } else {
    const std::string json = doc.dump();
    prepared.bytes.assign(json.begin(), json.end());
  }
  return prepared;
}

void decode_meshopt(tinygltf::Model& model, const PreparedFile& prepared, const std::string& path) {
  for (size_t v = 0; v < model.bufferViews.size(); ++v) {
    auto& view = model.bufferViews[v];
    const auto ext = view.extensions.find("EXT_meshopt_compression");
    if (ext == view.extensions.end()) continue;
    const std::string at = "/bufferViews/" + std::to_string(v) + "/extensions/EXT_meshopt_compression";
    const tinygltf::Value& m = ext->second;
    if (!m.IsObject()) fail(path, at + ": must be an object");
    if (model.buffers.empty()) fail(path, at + "/buffer: the file has no buffers");
    const uint64_t buffer = integer(m, "buffer", at, 0, model.buffers.size() - 1, path);
    const uint64_t offset = integer(m, "byteOffset", at, 0, UINT32_MAX, path, 0);
    const uint64_t length = integer(m, "byteLength", at, 1, UINT32_MAX, path);
    const uint64_t stride = integer(m, "byteStride", at, 1, 256, path);
    const uint64_t count = integer(m, "count", at, 1, UINT32_MAX, path);
    const std::string mode = string_member(m, "mode", at, "", path);
    const std::string filter = string_member(m, "filter", at, "NONE", path);
    const auto& source = model.buffers[buffer].data;
    if (offset + length > source.size()) fail(path, at + ": byteOffset + byteLength run past the end of buffer " + std::to_string(buffer));
    if (count * stride > kMaxDecodedBytes) fail(path, at + ": decodes to " + std::to_string(count * stride) + " bytes, more than 1 GiB");
    if (count * stride != view.byteLength) {
      fail(path, at + ": count x byteStride (" + std::to_string(count * stride) + ") differs from the buffer view's byteLength (" +
                     std::to_string(view.byteLength) + ")");
    }
    // The view's place in its own (fallback or ordinary) buffer must still be valid.
    const auto fallback = prepared.fallback_bytes.find(static_cast<size_t>(view.buffer));
    const uint64_t own = fallback != prepared.fallback_bytes.end() ? fallback->second
                         : view.buffer >= 0 && static_cast<size_t>(view.buffer) < model.buffers.size()
                             ? model.buffers[static_cast<size_t>(view.buffer)].data.size()
                             : 0;
    if (view.byteOffset + view.byteLength > own) fail(path, "/bufferViews/" + std::to_string(v) + ": runs past the end of its buffer");
    std::vector<unsigned char> decoded(count * stride);
    const unsigned char* data = source.data() + offset;
    int status = -1;
    if (mode == "ATTRIBUTES") {
      if (stride % 4 != 0) fail(path, at + "/byteStride: must be a multiple of 4 for ATTRIBUTES");
      status = meshopt_decodeVertexBuffer(decoded.data(), count, stride, data, length);
    } else if (mode == "TRIANGLES" || mode == "INDICES") {
      if (stride != 2 && stride != 4) fail(path, at + "/byteStride: must be 2 or 4 for " + mode);
      if (mode == "TRIANGLES" && count % 3 != 0) fail(path, at + "/count: must be a multiple of 3 for TRIANGLES");
      status = mode == "TRIANGLES" ? meshopt_decodeIndexBuffer(decoded.data(), count, stride, data, length)
                                   : meshopt_decodeIndexSequence(decoded.data(), count, stride, data, length);
    } else {
      fail(path, at + "/mode: '" + mode + "' is not ATTRIBUTES, TRIANGLES or INDICES");
    }
    if (status != 0) fail(path, at + ": the compressed data is malformed (meshoptimizer error " + std::to_string(status) + ")");
    if (filter == "OCTAHEDRAL") {
      if (mode != "ATTRIBUTES" || (stride != 4 && stride != 8))
        fail(path, at + "/filter: OCTAHEDRAL needs ATTRIBUTES with byteStride 4 or 8");
      meshopt_decodeFilterOct(decoded.data(), count, stride);
    } else if (filter == "QUATERNION") {
      if (mode != "ATTRIBUTES" || stride != 8) fail(path, at + "/filter: QUATERNION needs ATTRIBUTES with byteStride 8");
      meshopt_decodeFilterQuat(decoded.data(), count, stride);
    } else if (filter == "EXPONENTIAL") {
      if (mode != "ATTRIBUTES") fail(path, at + "/filter: EXPONENTIAL needs ATTRIBUTES");
      meshopt_decodeFilterExp(decoded.data(), count, stride);
    } else if (filter != "NONE") {
      fail(path, at + "/filter: '" + filter + "' is not NONE, OCTAHEDRAL, QUATERNION or EXPONENTIAL");
    }
    tinygltf::Buffer out;
    out.data = std::move(decoded);
    model.buffers.push_back(std::move(out));
    view.buffer = static_cast<int>(model.buffers.size() - 1);
    view.byteOffset = 0;
  }
}

DracoGeometry decode_draco(const tinygltf::Model& model, const tinygltf::Primitive& primitive, int indices, const std::string& pointer,
                           const std::string& path) {
  const std::string at = pointer + "/extensions/KHR_draco_mesh_compression";
  const tinygltf::Value& ext = primitive.extensions.at("KHR_draco_mesh_compression");
  if (!ext.IsObject()) fail(path, at + ": must be an object");
  if (model.bufferViews.empty()) fail(path, at + "/bufferView: the file has no buffer views");
  const auto& view = model.bufferViews[integer(ext, "bufferView", at, 0, model.bufferViews.size() - 1, path)];
  if (view.buffer < 0 || static_cast<size_t>(view.buffer) >= model.buffers.size())
    fail(path, at + ": its buffer view names a missing buffer");
  const auto& buffer = model.buffers[static_cast<size_t>(view.buffer)].data;
  if (view.byteOffset + view.byteLength > buffer.size()) fail(path, at + ": its buffer view is longer than its buffer");
  if (!ext.Has("attributes") || !ext.Get("attributes").IsObject()) fail(path, at + "/attributes: must be an object");
  const tinygltf::Value& ids = ext.Get("attributes");

  draco::DecoderBuffer data;
  data.Init(reinterpret_cast<const char*>(buffer.data() + view.byteOffset), view.byteLength);
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&data);
  if (!decoded.ok()) fail(path, at + ": the Draco data cannot be decoded (" + decoded.status().error_msg_string() + ")");
  const std::unique_ptr<draco::Mesh> mesh = std::move(decoded).value();
  const uint64_t points = mesh->num_points();
  if (points * 24 + uint64_t{mesh->num_faces()} * 12 > kMaxDecodedBytes) fail(path, at + ": the Draco mesh is larger than 1 GiB decoded");

  // The accessors the extension replaces must describe what it decodes to.
  auto check_count = [&](int accessor, uint64_t decoded_count, const std::string& what) {
    if (accessor < 0 || static_cast<size_t>(accessor) >= model.accessors.size())
      fail(path, what + ": accessor " + std::to_string(accessor) + " does not exist");
    const uint64_t declared = model.accessors[static_cast<size_t>(accessor)].count;
    if (declared != decoded_count) {
      fail(path, what + ": accessor " + std::to_string(accessor) + " has count " + std::to_string(declared) +
                     ", but the Draco data decodes to " + std::to_string(decoded_count));
    }
  };
  auto read = [&](const char* name, int components) {
    const auto width = static_cast<size_t>(components);
    std::vector<float> values;
    if (!ids.Has(name)) return values;
    const auto attribute = primitive.attributes.find(name);
    if (attribute == primitive.attributes.end()) fail(path, at + "/attributes/" + name + ": the primitive has no " + name + " attribute");
    check_count(attribute->second, points, pointer + "/attributes/" + name);
    const auto id = integer(ids, name, at + "/attributes", 0, UINT32_MAX, path);
    const draco::PointAttribute* source = mesh->GetAttributeByUniqueId(static_cast<uint32_t>(id));
    if (!source || source->num_components() < components) {
      fail(path, at + "/attributes/" + name + ": the Draco data has no attribute " + std::to_string(id) + " of " +
                     std::to_string(components) + " components");
    }
    values.resize(points * width);
    for (draco::PointIndex i(0); i < mesh->num_points(); ++i) {
      float v[4] = {};
      source->ConvertValue<float>(source->mapped_index(i), std::min<int8_t>(source->num_components(), 4), v);
      for (int c = 0; c < components; ++c) {
        if (!std::isfinite(v[c])) fail(path, at + "/attributes/" + name + ": holds a value that is not a finite number");
        values[i.value() * width + static_cast<size_t>(c)] = v[c];
      }
    }
    return values;
  };
  DracoGeometry out;
  out.positions = read("POSITION", 3);
  if (out.positions.empty()) fail(path, at + "/attributes: has no POSITION");
  out.normals = read("NORMAL", 3);
  out.texcoords[0] = read("TEXCOORD_0", 2);
  out.texcoords[1] = read("TEXCOORD_1", 2);
  out.tangents = read("TANGENT", 4);
  out.indices.reserve(uint64_t{mesh->num_faces()} * 3);
  for (draco::FaceIndex f(0); f < mesh->num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) out.indices.push_back(mesh->face(f)[k].value());
  }
  if (indices >= 0) check_count(indices, out.indices.size(), pointer + "/indices");
  return out;
}

}  // namespace caustica::scene::gltf
