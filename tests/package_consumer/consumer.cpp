// Loads, validates and runs a bundled graph through the installed headers and libraries only, the
// way another project's tests would. Exit 0 only if the graph compiles, a frame runs on the device
// with validation on, and the validation layers said nothing.
#include <cstdio>
#include <exception>

#include "builtin_passes.h"
#include "core/error.h"
#include "core/paths.h"
#include "graph/executor.h"

int main() {
  using namespace caustica;
  try {
    graph::GraphDesc graph = graph::load_graph_file((data_dir() / "graphs" / "core_demo.json").string());
    vk::Context vk({"", true, false});
    shader::ShaderCompiler shaders(data_dir() / "shaders");
    graph::Executor executor(vk, shaders, passes::builtin_registry());
    executor.configure(graph, 64, 32);
    graph::FrameResult frame = executor.run_frame(true);
    const io::ImageData image = executor.read_image(executor.plan().resources.at(executor.plan().outputs.at(0)).name);
    std::printf("data %s: %zu passes, %.3f ms GPU, output %ux%u, %u validation messages\n", data_dir().c_str(), frame.passes.size(),
                frame.gpu_ms, image.width, image.height, vk.validation_messages());
    return image.width == 64 && image.height == 32 && vk.validation_messages() == 0 ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "consumer: %s\n", e.what());
    return 1;
  }
}
