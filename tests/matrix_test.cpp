// Every bundled graph on every bundled scene (the stability suite's included, a textured pane and
// the opaque surfaces' extensions), on lavapipe with validation and synchronization validation: each
// must render without a validation message, without NaN or Inf in its output, and with its first
// output written. Small frames, photon grids and light-space maps keep it quick: the shapes of the
// work (passes, barriers, aliasing, batches) are the same as at full size, and the adaptive
// traversal still refines once at 128^2 photons. (With the graphs' 1024^2 maps the Release run took
// 45 s here, 16 s with 256^2, when it had fewer graphs and scenes; 51 s with 256^2 and 17 s with
// 128^2 on 30 November 2026, shader cache warm: the kernels' device work was most of it.) The Release run renders every graph on each scene
// whose plan values are new and each other scene with one graph in turn; under the sanitizers (CAUSTICA_SMALL_LOOPS) each graph and each
// scene renders once, paired in turn.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <set>
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

// The scene's values that shape a plan: every expression value but the two lengths that scale the
// scene's numbers (its diagonal and the ray offset that follows from it).
[[maybe_unused]] std::map<std::string, double> plan_values(const scene::Scene& scene) {
  auto values = scene.expression_values();
  values.erase("scene.diagonal");
  values.erase("scene.ray_epsilon");
  return values;
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
  // Each scene loaded once: for its values (Release) and for its renders, then let go.
  std::vector<std::shared_ptr<const scene::Scene>> scene_cache(scenes.size());
  auto scene_at = [&](size_t i) {
    if (!scene_cache[i]) scene_cache[i] = std::make_shared<const scene::Scene>(scene::load_scene_file(scenes[i].string()));
    return scene_cache[i];
  };
  std::vector<std::pair<size_t, size_t>> pairs;  // (scene, graph)
#ifdef CAUSTICA_SMALL_LOOPS
  for (size_t i = 0; i < std::max(scenes.size(), graphs.size()); ++i) pairs.emplace_back(i % scenes.size(), i % graphs.size());
#else
  // A graph's plan, and every pipeline define in it, is a function of the graph and the scene's
  // expression values (graph::compile_graph; the passes' setup reads nothing else of the scene). So
  // every graph renders on the first scene of each set of values; a scene whose values an earlier
  // one already has (the stability cases, the bunny beside the ball: the same passes, other numbers)
  // meets the graphs in turn, one each, and the stability suite renders every caustic method on each
  // of its cases with validation.
  std::set<std::map<std::string, double>> planned;
  size_t next_graph = 0;
  for (size_t s = 0; s < scenes.size(); ++s) {
    if (planned.insert(plan_values(*scene_at(s))).second) {
      for (size_t g = 0; g < graphs.size(); ++g) pairs.emplace_back(s, g);
    } else {
      pairs.emplace_back(s, next_graph++ % graphs.size());
    }
  }
  std::printf("%zu scenes with values of their own\n", planned.size());
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
      executor->set_scene(scene_at(scene_index));
      scene_cache[scene_index].reset();  // the executor holds it while its graphs render
      loaded = scene_index;
    }
    graph::GraphDesc graph = graph::load_graph_file(graph_file.string());
    for (const char* small : {"grid=128", "shadow_size=128", "light_size=128", "caustic_size=64"}) {
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
