// Benchmarks for the frame-graph core, run by hand; results go to docs/benchmarks.md.
//   bench_core compile      compile time of synthetic chains of 10, 100 and 1000 passes (CPU only)
//   bench_core overhead     executor CPU time per frame against the same passes recorded by hand
//   bench_core memory       transient memory with and without aliasing for every bundled graph
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "builtin_passes.h"
#include "core/paths.h"
#include "graph/executor.h"

using namespace caustica;
using Clock = std::chrono::steady_clock;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

graph::GraphDesc chain(int passes) {
  nlohmann::json resources = nlohmann::json::object(), list = nlohmann::json::array();
  resources["r0"] = {{"type", "image"}, {"format", "rgba16f"}};
  list.push_back({{"name", "p0"}, {"type", "pattern"}, {"outputs", {{"color", "r0"}}}});
  for (int i = 1; i < passes - 1; ++i) {
    std::string in = "r" + std::to_string(i - 1), out = "r" + std::to_string(i);
    resources[out] = {{"type", "image"}, {"format", "rgba16f"}};
    list.push_back({{"name", "p" + std::to_string(i)}, {"type", "box_blur"}, {"inputs", {{"source", in}}}, {"outputs", {{"target", out}}}});
  }
  resources["out"] = {{"type", "image"}, {"format", "rgba8"}};
  list.push_back({{"name", "tonemap"}, {"type", "tonemap"}, {"inputs", {{"source", "r" + std::to_string(passes - 2)}}}, {"outputs", {{"target", "out"}}}});
  nlohmann::json g = {{"name", "chain"}, {"resources", resources}, {"passes", list}, {"outputs", {"out"}}};
  return graph::load_graph(JsonDocument::parse(g.dump(), "chain" + std::to_string(passes) + ".json"));
}

void bench_compile() {
  std::printf("| passes | compile (median of 9) | per pass |\n|---|---|---|\n");
  for (int n : {10, 100, 1000}) {
    graph::GraphDesc g = chain(n);
    graph::CompileOptions options;
    options.output_width = 1280;
    options.output_height = 720;
    options.memory_limit_bytes = ~0ull;
    std::vector<double> ms;
    for (int i = 0; i < 9; ++i) {
      auto t = Clock::now();
      graph::Plan plan = graph::compile_graph(g, passes::builtin_registry(), options);
      ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t).count());
      if (plan.passes.size() != static_cast<size_t>(n)) std::abort();
    }
    std::printf("| %d | %.3f ms | %.2f us |\n", n, median(ms), median(ms) * 1000.0 / n);
  }
}

void bench_overhead() {
  // Tiny images keep the GPU work negligible, so the comparison is of CPU recording cost: the
  // executor's frame (barriers from the plan, labels, timestamps, pass dispatch through the
  // registry) against recording the same pass objects' commands directly with no graph around them.
  vk::Context vk({"", false, false});
  shader::ShaderCompiler shaders(data_dir() / "shaders");
  graph::Executor executor(vk, shaders, passes::builtin_registry());
  graph::GraphDesc g = chain(100);
  executor.configure(g, 8, 8, {}, ~0ull);
  for (int i = 0; i < 5; ++i) executor.run_frame(false);
  std::vector<double> graph_ms, pass_ms;
  for (int i = 0; i < 51; ++i) {
    auto frame = executor.run_frame(false);
    double passes_only = 0;
    for (const auto& p : frame.passes) passes_only += p.cpu_ms;
    graph_ms.push_back(frame.cpu_ms);
    pass_ms.push_back(passes_only);
  }
  double total = median(graph_ms), recording = median(pass_ms);
  std::printf("| graph | frame CPU (record+submit) | of which in passes (barriers+execute) | executor overhead |\n|---|---|---|---|\n");
  std::printf("| chain of 100 passes at 8x8 | %.3f ms | %.3f ms | %.3f ms (%.1f%%) |\n", total, recording, total - recording,
              100.0 * (total - recording) / total);
}

void bench_memory() {
  std::printf("| graph | transient, unaliased | transient, aliased | saved |\n|---|---|---|---|\n");
  for (const auto& entry : std::filesystem::directory_iterator(data_dir() / "graphs")) {
    if (entry.path().extension() != ".json" || entry.path().filename() == "schema.json") continue;
    graph::GraphDesc g = graph::load_graph_file(entry.path().string());
    graph::CompileOptions options;
    options.output_width = 1280;
    options.output_height = 720;
    graph::Plan plan = graph::compile_graph(g, passes::builtin_registry(), options);
    double a = static_cast<double>(plan.transient_bytes_aliased) / 1048576.0, u = static_cast<double>(plan.transient_bytes_unaliased) / 1048576.0;
    std::printf("| %s (1280x720) | %.1f MiB | %.1f MiB | %.0f%% |\n", entry.path().filename().c_str(), u, a, u > 0 ? 100.0 * (u - a) / u : 0.0);
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::string what = argc > 1 ? argv[1] : "";
  if (what == "compile") bench_compile();
  else if (what == "overhead") bench_overhead();
  else if (what == "memory") bench_memory();
  else {
    std::fprintf(stderr, "usage: bench_core compile|overhead|memory\n");
    return 2;
  }
  return 0;
}
