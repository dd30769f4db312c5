#pragma once
// Compressed glTF geometry: EXT_meshopt_compression buffer views and KHR_draco_mesh_compression
// primitives, decoded with Debian's libmeshoptimizer and libdraco. Debian's tinygltf (2.7) refuses
// two things these extensions make valid, so the file's JSON is adjusted before tinygltf reads it.
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace tinygltf {
class Model;
struct Primitive;
}  // namespace tinygltf

namespace caustica::scene::gltf {

// A glTF file (text or GLB) as tinygltf 2.7 can read it: a fallback buffer with no data
// (EXT_meshopt_compression) is given a one-byte data URI, and a Draco primitive's "indices", whose
// accessor has no buffer view, is taken out (the indices come from the Draco data). Everything
// else is the file's own.
struct PreparedFile {
  std::vector<unsigned char> bytes;                        // what tinygltf reads: the file itself when nothing changed
  std::map<size_t, uint64_t> fallback_bytes;               // fallback buffer index -> its byteLength in the file
  std::map<std::pair<size_t, size_t>, int> draco_indices;  // (mesh, primitive) -> its "indices" accessor
};
// `bytes` is the whole file; `binary` whether it is a GLB. A malformed file is passed on unchanged,
// for tinygltf to name what is wrong.
PreparedFile prepare(std::vector<unsigned char> bytes, bool binary);

// Replaces every EXT_meshopt_compression buffer view's data with its decoded bytes (a new buffer
// per view). Errors name the buffer view's JSON pointer.
void decode_meshopt(tinygltf::Model& model, const PreparedFile& prepared, const std::string& path);

struct DracoGeometry {
  std::vector<float> positions;  // 3 per point, dequantized
  std::vector<float> normals;    // 3 per point, or empty when the Draco data has no NORMAL
  std::vector<float> texcoords[2];  // TEXCOORD_0 and _1: 2 per point, or empty
  std::vector<float> tangents;      // TANGENT: 4 per point, or empty
  std::vector<uint32_t> indices;
};
// Decodes a KHR_draco_mesh_compression primitive. `pointer` is the primitive's JSON pointer;
// `indices` its "indices" accessor (-1: none), whose count must match the decoded triangles.
DracoGeometry decode_draco(const tinygltf::Model& model, const tinygltf::Primitive& primitive, int indices, const std::string& pointer,
                           const std::string& path);

}  // namespace caustica::scene::gltf
