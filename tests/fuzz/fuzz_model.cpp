// libFuzzer target: any bytes as a model file (binary glTF when they start with the GLB magic,
// else glTF JSON), opened as a scene of its own. Every input must end in a scene or an InputError.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.h"
#include "scene/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace caustica;
  static const std::filesystem::path folder = [] {
    auto dir = std::filesystem::temp_directory_path() / ("caustica_fuzz_model_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    return dir;
  }();
  const bool binary = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
  const std::filesystem::path path = folder / (binary ? "model.glb" : "model.gltf");
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    scene::load_model_scene(path.string());
  } catch (const InputError&) {
  }
  return 0;
}
