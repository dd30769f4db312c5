// libFuzzer target: any bytes as a scene file (with the meshes it names), loaded. Every input must
// end in a scene or an InputError.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "scene/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace caustica;
  try {
    scene::load_scene(JsonDocument::parse(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz/scene.json"));
  } catch (const InputError&) {
  }
  return 0;
}
