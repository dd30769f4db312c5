// Every bundled graph on every bundled scene (the stability suite's included, and a textured
// pane), on lavapipe with validation and synchronization validation: each must render without a
// validation message, without NaN or Inf in its output, and with its first output written. Small
// frames, photon grids and light-space maps keep it quick (with the graphs' 1024^2 maps the Release
// run took 45 s here, 16 s with 256^2: clearing and first touching them was most of it); the shapes
// of the work (passes, barriers, aliasing, batches) are the same as at full size. Under the sanitizers (CAUSTICA_SMALL_LOOPS) each graph
// and each scene renders once, paired in turn: the Release run covers every pair of a graph and a bundled scene, and each graph on one of
// the stability cases.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <vector>

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
  // Opaque surfaces with glTF's sheen, anisotropy and diffuse transmission: the G-buffer's material
  // target written and read.
  scenes.push_back(std::filesystem::path(CAUSTICA_SOURCE_DIR) / "tests/data/surfaces/surfaces.json");
  ASSERT_GE(graphs.size(), 9u);
  ASSERT_GE(scenes.size(), 14u);
  std::vector<std::pair<size_t, size_t>> pairs;  // (scene, graph)
#ifdef CAUSTICA_SMALL_LOOPS
  for (size_t i = 0; i < std::max(scenes.size(), graphs.size()); ++i) pairs.emplace_back(i % scenes.size(), i % graphs.size());
#else
  // The stability cases are paired with the graphs in turn (each graph on one of them): they differ
  // from the bundled scenes in their numbers, not in the passes a graph plans for them, and the
  // stability suite renders every caustic method on every one of them with validation.
  const size_t first_case = scenes.size() - stability.size() - 2;  // the tinted pane and the surfaces come after them
  for (size_t s = 0; s < scenes.size(); ++s) {
    const bool is_case = s >= first_case && s < first_case + stability.size();
    for (size_t g = 0; g < graphs.size(); ++g) {
      if (!is_case || g % stability.size() == s - first_case) pairs.emplace_back(s, g);
    }
  }
#endif
  int renders = 0;
  // One executor a scene, so that the scene is uploaded (and its acceleration structures built)
  // once, not for every graph; each graph is a new plan on it, as a graph reloaded in the viewer is.
  std::unique_ptr<graph::Executor> executor;
  size_t loaded = scenes.size();
  for (const auto& [scene_index, graph_index] : pairs) {
    const auto& scene_file = scenes[scene_index];
    const auto& graph_file = graphs[graph_index];
    if (scene_index != loaded) {
      executor = std::make_unique<graph::Executor>(vk, shaders, passes::builtin_registry());
      executor->set_scene(std::make_shared<const scene::Scene>(scene::load_scene_file(scene_file.string())));
      loaded = scene_index;
    }
    graph::GraphDesc graph = graph::load_graph_file(graph_file.string());
    for (const char* small : {"grid=256", "shadow_size=256", "light_size=256", "caustic_size=128"}) {
      const std::string name = std::string(small).substr(0, std::string(small).find('='));
      if (graph.find_parameter(name)) graph::apply_overrides(graph, {small});
    }
    const uint32_t before = vk.validation_messages();
    // A graph this device refuses (one that needs ray queries, on a GPU without them) fails here
    // and the rest still run, so that one run shows every other graph's messages too.
    try {
      executor->configure(graph, 96, 64);
      executor->run_frame(true);
    } catch (const std::exception& e) {
      ADD_FAILURE() << graph_file.filename() << " on " << scene_file.filename() << ": " << e.what();
      continue;
    }
    const io::ImageData out = executor->read_image(executor->plan().resources[executor->plan().outputs.front()].name);
    size_t bad = 0;
    for (float v : out.rgba) bad += std::isfinite(v) ? 0 : 1;
    EXPECT_EQ(vk.validation_messages(), before) << graph_file.filename() << " on " << scene_file.filename();
    EXPECT_EQ(bad, 0u) << graph_file.filename() << " on " << scene_file.filename();
    EXPECT_EQ(out.width, 96u);
    ++renders;
  }
  std::printf("%d graph x scene renders\n", renders);
}
