#pragma once
// A lavapipe engine with validation and synchronization validation on that renders bundled graphs
// on scenes, for the device tests; any validation message fails the test that owns it.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "builtin_passes.h"
#include "core/paths.h"
#include "graph/executor.h"

namespace caustica::test {

struct SceneEngine {
  vk::Context vk{{"", true, false}};
  // The process's, with its disk cache: each test is a process of its own, and most of a small
  // test's start would otherwise be compiling the same shaders again.
  shader::ShaderCompiler& shaders = shader::process_shader_compiler();
  graph::Executor executor{vk, shaders, passes::builtin_registry()};
  uint32_t width = 320, height = 180;
  // The viewer's setting: skip passes whose dependencies are unchanged (ConfigureOptions).
  bool reuse = false;
  // What the next configure() hands over with (HandOverOptions), then cleared.
  graph::HandOverOptions next;
  // The tracer the plans take (ConfigureOptions::tracer); unset: the device's choice.
  std::optional<graph::Tracer> tracer;

  bool configure(const graph::GraphDesc& graph, uint32_t w, uint32_t h, std::set<std::string> retained = {}) {
    const bool compiled = executor.configure(
        graph, w, h, {.retained = std::move(retained), .reuse_unchanged_passes = reuse, .hand_over = next, .tracer = tracer});
    next = {};
    return compiled;
  }

  // Runs one frame of graphs/<graph_name>.json on `scene`, reading back the outputs and `retained`.
  graph::FrameResult render(const std::string& graph_name, std::shared_ptr<const scene::Scene> scene, const std::vector<std::string>& sets,
                            const std::set<std::string>& retained) {
    auto graph = graph::load_graph_file((data_dir() / "graphs" / (graph_name + ".json")).string());
    graph::apply_overrides(graph, sets);
    return render(graph, std::move(scene), retained);
  }

  graph::FrameResult render(const graph::GraphDesc& graph, std::shared_ptr<const scene::Scene> scene,
                            const std::set<std::string>& retained) {
    executor.set_scene(std::move(scene));
    executor.configure(graph, width, height, {.retained = retained, .tracer = tracer});
    return executor.run_frame(true);
  }

  ~SceneEngine() { EXPECT_EQ(vk.validation_messages(), 0u); }
};

inline std::shared_ptr<scene::Scene> load_bundled_scene(const std::string& name) {
  return std::make_shared<scene::Scene>(scene::load_scene_file((data_dir() / "scenes" / (name + ".json")).string()));
}

// How far image `a` lies from `b`: the sum of the colour channels' absolute differences over the sum
// of b's absolute colour values (alpha left out: a caustic map's is 1 everywhere). A GPU adds a
// texel's photons in whatever order its atomics land, so two maps of the same photons agree to
// float rounding, not bit for bit (lavapipe's order happens to be fixed).
inline double relative_difference(const io::ImageData& a, const io::ImageData& b) {
  EXPECT_EQ(a.rgba.size(), b.rgba.size());
  double difference = 0, total = 0;
  for (size_t i = 0; i < std::min(a.rgba.size(), b.rgba.size()); ++i) {
    if (i % 4 == 3) continue;
    difference += std::abs(static_cast<double>(a.rgba[i]) - static_cast<double>(b.rgba[i]));
    total += std::abs(static_cast<double>(b.rgba[i]));
  }
  // Two empty maps would agree perfectly: a comparison against nothing is a failure.
  EXPECT_GT(total, 0.0) << "relative_difference: the reference image is empty";
  return total > 0 ? difference / total : difference;
}

// A caustic-map texel's flux as the flux counters count it: the mean of its three channels.
inline double texel_flux(const io::ImageData& map, size_t texel) {
  const float* rgb = &map.rgba[texel * 4];
  return (double(rgb[0]) + double(rgb[1]) + double(rgb[2])) / 3.0;
}

// A caustic map's flux as the counters total it.
inline double map_flux(const io::ImageData& map) {
  double total = 0;
  for (size_t i = 0; i < map.rgba.size() / 4; ++i) total += texel_flux(map, i);
  return total;
}

// The flux of each level of an adaptive caustic map's caustic_levels atlas (level 0 of side `side` at
// the left, each next level half as large to the right of the one before, each texel divided by the
// level-0 texels it covers), as the flux counters total it; `outside` gets the absolute sum of the
// texels in no level.
inline std::vector<double> level_fluxes(const io::ImageData& atlas, uint32_t side, uint32_t levels, double* outside) {
  std::vector<double> flux(levels, 0.0);
  *outside = 0;
  for (uint32_t y = 0; y < atlas.height; ++y) {
    for (uint32_t x = 0; x < atlas.width; ++x) {
      uint32_t left = 0, level = 0;
      while (level < levels && x >= left + (side >> level)) left += side >> level++;
      const double v = texel_flux(atlas, size_t{y} * atlas.width + x);
      if (level < levels && y < (side >> level))
        flux[level] += v * double(1u << (2 * level));
      else
        *outside += std::abs(v);
    }
  }
  return flux;
}

}  // namespace caustica::test
