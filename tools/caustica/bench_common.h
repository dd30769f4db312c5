#pragma once
// What the benchmarks of `caustica bench` share. bench.cpp has the help and picks the benchmark;
// bench_frames.cpp has load, refraction and photons; bench_accuracy.cpp and bench_stability.cpp
// the other two.
#include <cstdint>
#include <initializer_list>
#include <set>
#include <string>

#include "cli.h"
#include "graph/executor.h"
#include "vk/context.h"

namespace caustica::cli::bench {

// The benchmarks, `caustica bench NAME` each.
int cmd_bench_load(Args& args);
int cmd_bench_refraction(Args& args);
int cmd_bench_photons(Args& args);
int cmd_bench_accuracy(Args& args);
int cmd_bench_stability(Args& args);

// A file (NAME.json) as given, or a bundled one by name ("bunny_plane", "stability/close_light").
std::string bundled_path(const char* folder, const std::string& name);
std::string scene_path(const std::string& name);
std::string graph_path(const std::string& name);

// The graph's passes whose GPU time a method is charged with.
std::set<std::string> passes_of_types(const graph::GraphDesc& graph, std::initializer_list<const char*> types);

inline constexpr std::initializer_list<const char*> kCausticPassTypes = {"caustic_map", "hierarchical_caustic_map", "adaptive_caustic_map"};

struct Timings {
  double method_ms = 0, frame_ms = 0;
  graph::FrameResult last;
};

// One warm-up frame (pipelines compile on first use), then the median of `frames`.
Timings time_frames(graph::Executor& executor, uint32_t frames, const std::set<std::string>& method_passes);

// Whether the graph runs on this device: a graph that traces with ray queries needs them. The
// benchmarks skip, and say so, what a device cannot run rather than fail the whole run.
bool runs_on(const vk::Context& vk, const graph::GraphDesc& g);

}  // namespace caustica::cli::bench
