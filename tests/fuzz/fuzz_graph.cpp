// libFuzzer target: any bytes as a graph file, loaded and compiled against the test registry.
// Every input must end in a plan or an InputError; anything else (a crash, a sanitizer report, an
// uncaught exception, a hang) is a bug.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "graph/compiler.h"
#include "test_registry.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace caustica;
  static const graph::PassRegistry registry = test::make_test_registry();
  try {
    graph::GraphDesc graph = graph::load_graph(JsonDocument::parse(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.json"));
    graph::CompileOptions options;
    options.scene_values = graph::typical_scene_values();
    graph::compile_graph(graph, registry, options);
  } catch (const InputError&) {
  }
  return 0;
}
