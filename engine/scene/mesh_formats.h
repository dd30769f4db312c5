#pragma once
// The mesh file formats behind load_model_file (mesh_io.cpp). Each parser reports bad input as an
// InputError that names the file and, where the format has lines, the line.
#include <cstddef>
#include <string>

#include "scene/scene.h"

namespace caustica::scene::formats {

inline constexpr size_t kMaxMeshFileBytes = 512u << 20;

// Throws InputError "path:line: message" (no line where it is 0).
[[noreturn]] void fail(const std::string& path, size_t line, const std::string& message);

Mesh load_obj(const std::string& path, const std::string& text);  // Wavefront OBJ: v and f records
Mesh load_off(const std::string& path, const std::string& text);  // OFF, as the Stanford models come
ModelFile load_gltf(const std::string& path);                     // glTF 2.0, .gltf or .glb, through tinygltf

}  // namespace caustica::scene::formats
