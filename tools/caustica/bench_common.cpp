// What the benchmarks share; bench_common.h says what each does.
#include "bench_common.h"

#include <algorithm>
#include <filesystem>

#include "builtin_passes.h"
#include "core/paths.h"

namespace caustica::cli::bench {

std::string bundled_path(const char* folder, const std::string& name) {
  return std::filesystem::path(name).extension() == ".json" ? name : (data_dir() / folder / (name + ".json")).string();
}

std::string scene_path(const std::string& name) {
  return bundled_path("scenes", name);
}
std::string graph_path(const std::string& name) {
  return bundled_path("graphs", name);
}

namespace {

bool is_one_of(const std::string& type, std::initializer_list<const char*> types) {
  return std::any_of(types.begin(), types.end(), [&](const char* t) { return type == t; });
}

}  // namespace

std::set<std::string> passes_of_types(const graph::GraphDesc& graph, std::initializer_list<const char*> types) {
  std::set<std::string> names;
  for (const auto& p : graph.passes) {
    if (is_one_of(p.type, types)) names.insert(p.name);
  }
  return names;
}

Timings time_frames(graph::Executor& executor, uint32_t frames, const std::set<std::string>& method_passes) {
  executor.run_frame(false);
  std::vector<double> method, frame;
  Timings t;
  for (uint32_t f = 0; f < frames; ++f) {
    t.last = executor.run_frame(f + 1 == frames);
    double ms = 0;
    for (const auto& p : t.last.passes) ms += method_passes.count(p.name) ? p.gpu_ms : 0.0;
    method.push_back(ms);
    frame.push_back(t.last.gpu_ms);
  }
  t.method_ms = median(method);
  t.frame_ms = median(frame);
  return t;
}

bool runs_on(const vk::Context& vk, const graph::GraphDesc& g) {
  if (vk.ray_queries().available) return true;
  graph::CompileOptions options;
  options.scene_values = graph::typical_scene_values();
  return graph::compile_graph(g, passes::builtin_registry(), options).ray_query_passes.empty();
}

}  // namespace caustica::cli::bench
