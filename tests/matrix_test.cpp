// Every bundled graph on every bundled scene (the stability suite's included, and a textured
// pane), on lavapipe with validation and synchronization validation: each must render without a
// validation message, without NaN or Inf in its output, and with its first output written. Small
// frames and small photon grids keep it quick; the shapes of the work (passes, barriers, aliasing,
// batches) are the same as at full size.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "builtin_passes.h"
#include "core/paths.h"
#include "graph/executor.h"

using namespace caustica;

namespace {

std::vector<std::filesystem::path> bundled(const char* folder) {
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(data_dir() / folder)) {
    if (entry.path().extension() == ".json" && entry.path().filename() != "schema.json") files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace

TEST(Matrix, EveryGraphOnEverySceneIsValidationClean) {
  vk::Context vk({"", true, false});
  shader::ShaderCompiler shaders(data_dir() / "shaders");
  const auto graphs = bundled("graphs");
  auto scenes = bundled("scenes");
  const auto stability = bundled("scenes/stability");
  scenes.insert(scenes.end(), stability.begin(), stability.end());
  // A refractor whose tint varies over it: the refractor buffers draw their front_tint too.
  scenes.push_back(std::filesystem::path(CAUSTICA_SOURCE_DIR) / "tests/data/gltf/tinted_pane.gltf");
  ASSERT_GE(graphs.size(), 9u);
  ASSERT_GE(scenes.size(), 14u);
  int renders = 0;
  for (const auto& scene_file : scenes) {
    auto scene = std::make_shared<const scene::Scene>(scene::load_scene_file(scene_file.string()));
    for (const auto& graph_file : graphs) {
      graph::GraphDesc graph = graph::load_graph_file(graph_file.string());
      if (graph.find_parameter("grid")) graph::apply_overrides(graph, {"grid=256"});
      graph::Executor executor(vk, shaders, passes::builtin_registry());
      executor.set_scene(scene);
      const uint32_t before = vk.validation_messages();
      // A graph this device refuses (one that needs ray queries, on a GPU without them) fails here
      // and the rest still run, so that one run shows every other graph's messages too.
      try {
        executor.configure(graph, 96, 64);
        executor.run_frame(true);
      } catch (const std::exception& e) {
        ADD_FAILURE() << graph_file.filename() << " on " << scene_file.filename() << ": " << e.what();
        continue;
      }
      const io::ImageData out = executor.read_image(executor.plan().resources[executor.plan().outputs.front()].name);
      size_t bad = 0;
      for (float v : out.rgba) bad += std::isfinite(v) ? 0 : 1;
      EXPECT_EQ(vk.validation_messages(), before) << graph_file.filename() << " on " << scene_file.filename();
      EXPECT_EQ(bad, 0u) << graph_file.filename() << " on " << scene_file.filename();
      EXPECT_EQ(out.width, 96u);
      ++renders;
    }
  }
  std::printf("%d graph x scene renders\n", renders);
}
