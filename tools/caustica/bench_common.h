#pragma once
// What the benchmarks of `caustica bench` share. bench.cpp has the help and picks the benchmark;
// bench_frames.cpp has load, refraction and photons; bench_accuracy.cpp, bench_stability.cpp and
// bench_convergence.cpp the other three.
#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <set>
#include <string>
#include <vector>

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
int cmd_bench_convergence(Args& args);

// A file as given, or a bundled one by name ("bunny_plane", "stability/close_light"): find_data_file.
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

// What bench accuracy and bench convergence are both told: the caustic map's size (bench
// convergence: 0 for the graph's own), the frame size, the photon reference and the blur before
// comparing, the output folder and the device.
struct ComparisonOptions {
  uint32_t caustic_size = 512, width = 640, height = 360;
  uint64_t reference_photons = 100'000'000;
  double blur = 1.5;
  std::string out_dir, device;
  // Takes the value of `flag` when it is one of kFlags; false for any other flag.
  bool take(const std::string& flag, Args& args);
  static inline const std::vector<std::string> kFlags{"--caustic-size", "--size", "--reference-photons", "--blur", "--out", "--device"};
};

// What draws the charts (tools/plot_accuracy.py): the script and the interpreter.
struct Chart {
  std::filesystem::path script;
  std::string python;
  // Draws `out` from the CSV files (results.csv of bench accuracy, convergence.csv of bench
  // convergence: a panel for each kind of row), written whole or not at all.
  void draw(const std::vector<std::filesystem::path>& csvs, const std::filesystem::path& out) const;
};

// The chart script and an interpreter that can import matplotlib: CAUSTICA_PYTHON, else Debian's,
// where python3-matplotlib installs, even when another python3 comes first on PATH. Throws when
// there is none, before a benchmark's long work rather than after it.
Chart find_chart();

// What speed_accuracy.png in `dir` is drawn from: results.csv, and convergence.csv where bench
// convergence wrote one there too (its panel then stands beside the speed-accuracy ones).
std::vector<std::filesystem::path> speed_accuracy_inputs(const std::filesystem::path& dir);

}  // namespace caustica::cli::bench
