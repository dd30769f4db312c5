#pragma once
// What the benchmarks of `caustica bench` share. bench.cpp has the help and picks the benchmark;
// bench_frames.cpp has load, refraction and photons; bench_accuracy.cpp, bench_stability.cpp and
// bench_convergence.cpp the other three.
#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "cli.h"
#include "flags.h"
#include "graph/executor.h"
#include "reference/photon_reference.h"
#include "vk/context.h"

namespace caustica::cli::bench {

// The benchmarks, `caustica bench NAME` each.
int cmd_bench_load(Args& args);
int cmd_bench_refraction(Args& args);
int cmd_bench_compare(Args& args);
int cmd_bench_photons(Args& args);
int cmd_bench_accuracy(Args& args);
int cmd_bench_stability(Args& args);
int cmd_bench_convergence(Args& args);
int cmd_bench_merge(Args& args);
// Each benchmark's flags as `caustica bench --help` lists them; frames_flags_help takes load,
// refraction, compare or photons.
std::string frames_flags_help(const std::string& benchmark);
std::string accuracy_flags_help();
std::string stability_flags_help();
std::string convergence_flags_help();
std::string merge_flags_help();

// A file as given, or a bundled one by name ("bunny_plane", "stability/close_light"): find_data_file.
std::string scene_path(const std::string& name);
std::string graph_path(const std::string& name);

// The graph's passes whose GPU time a method is charged with.
std::set<std::string> passes_of_types(const graph::GraphDesc& graph, std::initializer_list<const char*> types);

inline constexpr std::initializer_list<const char*> kCausticPassTypes = {"caustic_map", "hierarchical_caustic_map", "adaptive_caustic_map"};
// A caustic method's passes: those of kCausticPassTypes, and the user passes (compute, fullscreen)
// that write the "caustics" image, which is the map the benchmarks compare.
std::set<std::string> caustic_passes(const graph::GraphDesc& graph);

struct Timings {
  double method_ms = 0, frame_ms = 0;
  graph::FrameResult last;
};

// One warm-up frame (pipelines compile on first use), then the median of `frames`.
Timings time_frames(graph::Executor& executor, uint32_t frames, const std::set<std::string>& method_passes);
// The GPU time of the frame's passes that are `passes` or a light's instance of one.
double passes_ms(const graph::FrameResult& frame, const std::set<std::string>& passes);

// Several executors' frames interleaved, so that machine noise hits each alike: `warmup` frames of
// each first (pipelines compile on first use on lavapipe), then the median of `frames` of each.
// `label` names the progress line.
std::vector<Timings> time_interleaved(const std::vector<graph::Executor*>& executors, uint32_t frames, uint32_t warmup,
                                      const std::vector<std::set<std::string>>& method_passes, const std::string& label);

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
  // Declares these flags in a benchmark's table.
  void add_flags(FlagTable& table);
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

// A sweep split into cells (docs/cluster.md, "Sweeps by cell"), so that a job array runs one cell
// a task and `bench merge` joins their rows into what one process writes.
struct CellOptions {
  bool list = false;            // --list-cells: print the cells, run nothing
  std::string cell;             // --cell K or auto; empty: the whole sweep in this process
  std::string reference_cache;  // --reference-cache DIR: photon references by key, shared by cells
  // Declares these flags in a benchmark's table.
  void add_flags(FlagTable& table);
};

// The arguments that select the sweep, as given: all but where it writes, the device, validation
// and the cell flags. A cell file's header keeps them; bench merge compares and parses them again.
std::vector<std::string> sweep_arguments(Args args);
// The arguments of a sweep again, with --out OUT_DIR: what bench merge parses its options from.
Args sweep_args(std::vector<std::string> sweep, const std::string& out_dir);

// The index a scheduler gives this process: SLURM_ARRAY_TASK_ID (a Slurm job array) or else
// JOB_COMPLETION_INDEX (a Kubernetes Indexed Job), and the variable's name; both empty when neither is set.
std::pair<std::string, std::string> scheduler_index();

// --cell K, or auto for the scheduler's index, within the sweep's `cells`; UsageError otherwise.
size_t cell_index(const std::string& text, size_t cells);

// The rows one cell measured, or those of every cell joined (bench merge): CSV rows and Markdown
// table rows, without their headers, and the devices that measured them.
struct CellRows {
  std::string benchmark;  // accuracy or stability
  std::vector<std::string> sweep;
  std::string device;
  std::string csv, table;
};

// DIR/cell_K.csv: a header (the benchmark, the cell's index and count, the sweep, the device), the
// CSV header and rows, then the table rows; written under a temporary name and renamed.
void write_cell(const std::filesystem::path& dir, size_t index, size_t cells, const std::string& csv_header, const CellRows& rows);

// The writers of one process's results, which bench merge calls with the cells' rows joined.
void write_merged_accuracy(const CellRows& rows, const std::string& out_dir);
void write_merged_stability(const CellRows& rows, const std::string& out_dir);

// The photon reference that `options` asks for; with a cache folder, the shards in
// CACHE/IDENTITY-pPHOTONS-mSIZE-sSEED.shards (where `submit.sh --out CACHE/KEY.exr` puts a sharded reference), or
// else traced here as one shard and left there for the next cell that needs it.
reference::PhotonReference photon_reference(const scene::Scene& scene, const reference::PhotonOptions& options, const std::string& cache);

}  // namespace caustica::cli::bench
