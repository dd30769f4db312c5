// What the benchmarks share; bench_common.h says what each does.
#include "bench_common.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include "builtin_passes.h"
#include "core/error.h"
#include "core/paths.h"
#include "flags.h"
#include "graph/per_light.h"
#include "io/files.h"
#include "io/json_document.h"
#include "reference/photon_shard.h"

namespace caustica::cli::bench {

std::string scene_path(const std::string& name) {
  return find_data_file(name, "scenes");
}
std::string graph_path(const std::string& name) {
  return find_data_file(name, "graphs");
}

namespace {

bool is_one_of(const std::string& type, std::initializer_list<const char*> types) {
  return std::any_of(types.begin(), types.end(), [&](const char* t) { return type == t; });
}

// `s` as one word of a POSIX shell command line, whatever it holds (a folder named "it's", say).
std::string shell_word(const std::string& s) {
  std::string word = "'";
  for (char c : s) word += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return word + "'";
}

}  // namespace

std::set<std::string> passes_of_types(const graph::GraphDesc& graph, std::initializer_list<const char*> types) {
  std::set<std::string> names;
  for (const auto& p : graph.passes) {
    if (is_one_of(p.type, types)) names.insert(p.name);
  }
  return names;
}

std::set<std::string> caustic_passes(const graph::GraphDesc& graph) {
  std::set<std::string> names = passes_of_types(graph, kCausticPassTypes);
  for (const auto& p : graph.passes) {
    const bool writes_map = std::any_of(p.outputs.begin(), p.outputs.end(), [](const auto& port) { return port.second == "caustics"; });
    if (p.user && writes_map) names.insert(p.name);
  }
  return names;
}

double passes_ms(const graph::FrameResult& frame, const std::set<std::string>& passes) {
  double ms = 0;
  for (const auto& p : frame.passes) ms += passes.count(std::string(graph::instance_of(p.name))) ? p.gpu_ms : 0.0;
  return ms;
}

Timings time_frames(graph::Executor& executor, uint32_t frames, const std::set<std::string>& method_passes) {
  executor.run_frame(false);
  std::vector<double> method, frame;
  Timings t;
  for (uint32_t f = 0; f < frames; ++f) {
    t.last = executor.run_frame(f + 1 == frames);
    method.push_back(passes_ms(t.last, method_passes));
    frame.push_back(t.last.gpu_ms);
  }
  t.method_ms = median(method);
  t.frame_ms = median(frame);
  return t;
}

std::vector<Timings> time_interleaved(const std::vector<graph::Executor*>& executors, uint32_t frames, uint32_t warmup,
                                      const std::vector<std::set<std::string>>& method_passes, const std::string& label) {
  std::vector<std::vector<double>> method(executors.size()), frame(executors.size());
  std::vector<Timings> timings(executors.size());
  ProgressLine progress(label, warmup + frames);
  for (uint32_t f = 0; f < warmup + frames; ++f) {
    for (size_t e = 0; e < executors.size(); ++e) {
      timings[e].last = executors[e]->run_frame(f + 1 == warmup + frames);
      if (f < warmup) continue;
      method[e].push_back(passes_ms(timings[e].last, method_passes[e]));
      frame[e].push_back(timings[e].last.gpu_ms);
    }
    progress.update(f + 1);
  }
  for (size_t e = 0; e < executors.size(); ++e) {
    timings[e].method_ms = median(method[e]);
    timings[e].frame_ms = median(frame[e]);
  }
  return timings;
}

bool runs_on(const vk::Context& vk, const graph::GraphDesc& g) {
  graph::CompileOptions options;
  options.scene_values = graph::typical_scene_values();
  options.ray_queries = vk.ray_queries().available;
  options.tracer = graph::tracer_from_environment();
  try {
    graph::compile_graph(g, passes::builtin_registry(), options);
    return true;
  } catch (const InputError&) {
    return false;  // traces with ray queries (--tracer ray_query) where the device has none
  }
}

// Declared on options that still hold their defaults, which the help texts say.
void ComparisonOptions::add_flags(FlagTable& table) {
  const std::string map = caustic_size ? std::to_string(caustic_size) : "the graph's own";
  table.add(uint32_flag("--caustic-size", "N", "the caustic map's side (default " + map + ")", caustic_size, 16, 8192))
      .add(size_flag(width, height, "the frame size (default " + std::to_string(width) + "x" + std::to_string(height) + ")"))
      .add(uint_flag("--reference-photons", "N", "photons of the reference (default 1e8)", reference_photons, 1000, 100'000'000'000ull))
      .add(blur_flag(blur, "Gaussian sigma in pixels before comparing with the reference (default 1.5)"))
      .add(text_flag("--out", "DIR", "the folder of the results (required)", out_dir))
      .add(device_flag(device))
      .add(tracer_flag());
}

Chart find_chart() {
  const std::filesystem::path plot_script = data_dir() / "tools" / "plot_accuracy.py";
  if (!std::filesystem::is_regular_file(plot_script)) throw InputError(plot_script.string() + ": the chart script is missing");
  std::string python = std::filesystem::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
  if (const char* env = std::getenv("CAUSTICA_PYTHON"); env && *env) python = env;
  if (std::system((shell_word(python) + " -c 'import matplotlib' > /dev/null 2>&1").c_str()) != 0) {
    throw std::runtime_error("the chart needs matplotlib, which " + python +
                             " cannot import (Debian: python3-matplotlib; CAUSTICA_PYTHON names another interpreter)");
  }
  return {plot_script, python};
}

void Chart::draw(const std::vector<std::filesystem::path>& csvs, const std::filesystem::path& out) const {
  const std::filesystem::path partial = out.parent_path() / ("." + out.stem().string() + ".partial.png");
  std::string command = shell_word(python) + " " + shell_word(script.string());
  for (const auto& csv : csvs) command += " " + shell_word(csv.string());
  command += " " + shell_word(partial.string());
  if (std::system(command.c_str()) != 0) {
    std::filesystem::remove(partial);
    throw std::runtime_error("drawing the chart failed: " + command + " (Debian: python3-matplotlib)");
  }
  std::filesystem::rename(partial, out);
}

std::vector<std::filesystem::path> speed_accuracy_inputs(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> csvs{dir / "results.csv"};
  if (std::filesystem::exists(dir / "convergence.csv")) csvs.push_back(dir / "convergence.csv");
  return csvs;
}

void CellOptions::add_flags(FlagTable& table) {
  table.add(switch_flag("--list-cells", "print the sweep's cells, one a line from 0, and run nothing", list))
      .add(text_flag("--cell", "K", "run cell K alone and write DIR/cell_K.csv (auto: K from the scheduler)", cell))
      .add(text_flag("--reference-cache", "DIR", "keep the photon references in DIR, for the cells that need them again", reference_cache));
}

std::vector<std::string> sweep_arguments(Args args) {
  std::vector<std::string> sweep;
  while (!args.done()) {
    const std::string a = args.take();
    if (a == "--out" || a == "--device" || a == "--cell" || a == "--reference-cache") {
      if (!args.done()) args.take();
    } else if (a != "--list-cells" && a != "--validate") {
      sweep.push_back(a);
    }
  }
  return sweep;
}

Args sweep_args(std::vector<std::string> sweep, const std::string& out_dir) {
  sweep.insert(sweep.end(), {"--out", out_dir});
  std::vector<char*> argv;
  for (auto& a : sweep) argv.push_back(a.data());
  return Args(static_cast<int>(argv.size()), argv.data(), 0);
}

std::pair<std::string, std::string> scheduler_index() {
  for (const char* variable : {"SLURM_ARRAY_TASK_ID", "JOB_COMPLETION_INDEX"}) {
    const char* value = std::getenv(variable);
    if (value != nullptr && *value != '\0') return {value, variable};
  }
  return {};
}

size_t cell_index(const std::string& text, size_t cells) {
  std::string index = text, from = "--cell";
  if (text == "auto") {
    std::tie(index, from) = scheduler_index();
    if (from.empty()) {
      throw UsageError("--cell auto: neither SLURM_ARRAY_TASK_ID (a Slurm job array) nor JOB_COMPLETION_INDEX (a Kubernetes Indexed Job) " +
                       std::string("is set; outside a scheduler give the index: --cell K"));
    }
  }
  try {
    return static_cast<size_t>(parse_uint(from, index, 0, cells - 1));
  } catch (const UsageError&) {
    const std::string what = from == "--cell" ? "'" + index + "'" : "the index that " + from + " gives, '" + index + "',";
    throw UsageError("--cell " + text + ": " + what + " is not a cell of this sweep, 0 to " + std::to_string(cells - 1) +
                     " (--list-cells lists them)");
  }
}

void write_cell(const std::filesystem::path& dir, size_t index, size_t cells, const std::string& csv_header, const CellRows& rows) {
  std::filesystem::create_directories(dir);
  io::write_text_atomically((dir / ("cell_" + std::to_string(index) + ".csv")).string(),
                            "# caustica bench " + rows.benchmark + " cell " + std::to_string(index) + " of " + std::to_string(cells) +
                                "\n# sweep: " + nlohmann::json(rows.sweep).dump() + "\n# device: " + rows.device + "\n" + csv_header +
                                rows.csv + rows.table);
  std::fprintf(stderr, "bench %s: cell %zu of %zu -> %s\n", rows.benchmark.c_str(), index, cells,
               (dir / ("cell_" + std::to_string(index) + ".csv")).c_str());
}

namespace {

// One cell file as read back.
struct CellFile {
  std::string path;
  size_t index = 0, cells = 0;
  CellRows rows;
};

CellFile read_cell(const std::filesystem::path& path) {
  CellFile cell{path.string()};
  std::istringstream in(caustica::read_text_file(cell.path, size_t{1} << 30));
  std::string title, sweep, device, header;
  std::getline(in, title);
  std::getline(in, sweep);
  std::getline(in, device);
  std::getline(in, header);
  char benchmark[32] = "";
  unsigned long long index = 0, cells = 0;
  int used = 0;
  if (std::sscanf(title.c_str(), "# caustica bench %31s cell %llu of %llu%n", benchmark, &index, &cells, &used) != 3 ||
      static_cast<size_t>(used) != title.size() || index >= cells || sweep.rfind("# sweep: ", 0) != 0 ||
      device.rfind("# device: ", 0) != 0 || header.empty()) {
    throw InputError(cell.path + ": not a cell of a bench sweep (bench accuracy|stability --cell K writes them)");
  }
  cell.index = index;
  cell.cells = cells;
  cell.rows.benchmark = benchmark;
  const auto arguments = nlohmann::json::parse(sweep.substr(9), nullptr, false);
  if (!arguments.is_array()) throw InputError(cell.path + ": its sweep line is not a list of arguments");
  for (const auto& a : arguments) cell.rows.sweep.push_back(a.is_string() ? a.get<std::string>() : a.dump());
  cell.rows.device = device.substr(10);
  for (std::string line; std::getline(in, line);) (line.rfind('|', 0) == 0 ? cell.rows.table : cell.rows.csv) += line + "\n";
  return cell;
}

std::string sweep_text(const CellRows& rows) {
  std::string text = "bench " + rows.benchmark;
  for (const auto& a : rows.sweep) text += " " + a;
  return text;
}

// bench merge's one flag, --out; the cells' folders come as arguments.
FlagTable merge_flags(std::string& out) {
  return {text_flag("--out", "OUT", "the folder of the joined results (required)", out)};
}

}  // namespace

std::string merge_flags_help() {
  std::string out;
  return merge_flags(out).help();
}

int cmd_bench_merge(Args& args) {
  std::string out;
  const FlagTable flags = merge_flags(out);
  std::vector<std::string> dirs;
  flags.parse(args, [&dirs](const std::string& dir) { dirs.push_back(dir); });
  if (dirs.empty()) throw UsageError("bench merge needs the cells' folders: caustica bench merge DIR... --out OUT");
  if (out.empty()) throw UsageError("bench merge needs --out OUT");

  std::vector<CellFile> cells;
  for (const auto& dir : dirs) {
    if (!std::filesystem::is_directory(dir)) throw InputError(dir + ": not a folder of cells");
    std::vector<std::filesystem::path> paths;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
      const std::string name = entry.path().filename().string();
      if (name.rfind("cell_", 0) == 0 && entry.path().extension() == ".csv") paths.push_back(entry.path());
    }
    std::sort(paths.begin(), paths.end());
    for (const auto& path : paths) cells.push_back(read_cell(path));
  }
  if (cells.empty()) throw InputError("no cell_K.csv in " + dirs.front() + (dirs.size() > 1 ? " or the other folders" : ""));
  const CellFile& first = cells.front();
  std::map<size_t, const CellFile*> by_index;
  std::string problems;
  for (const auto& cell : cells) {
    if (cell.rows.benchmark != first.rows.benchmark || cell.rows.sweep != first.rows.sweep || cell.cells != first.cells) {
      problems += cell.path + ": a cell of another sweep (" + sweep_text(cell.rows) + ", " + std::to_string(cell.cells) +
                  " cells), where " + first.path + " has " + sweep_text(first.rows) + ", " + std::to_string(first.cells) + " cells\n";
    } else if (const auto [at, added] = by_index.emplace(cell.index, &cell); !added) {
      problems += cell.path + " and " + at->second->path + " are both cell " + std::to_string(cell.index) + "\n";
    }
  }
  std::string missing;
  for (size_t k = 0; k < first.cells; ++k) missing += by_index.count(k) ? "" : (missing.empty() ? "" : ",") + std::to_string(k);
  if (!missing.empty()) {
    problems += "cells " + missing + " of " + std::to_string(first.cells) + " are missing: run them (--cell K) or resubmit them (" +
                "tools/slurm/submit.sh --bench ... --resubmit " + missing + ")\n";
  }
  if (!problems.empty()) throw InputError(problems.substr(0, problems.size() - 1));

  CellRows joined{first.rows.benchmark, first.rows.sweep, "", "", ""};
  std::set<std::string> devices;
  for (const auto& [index, cell] : by_index) {
    joined.csv += cell->rows.csv;
    joined.table += cell->rows.table;
    if (devices.insert(cell->rows.device).second) joined.device += (joined.device.empty() ? "" : "; ") + cell->rows.device;
  }
  if (joined.benchmark == "accuracy")
    write_merged_accuracy(joined, out);
  else if (joined.benchmark == "stability")
    write_merged_stability(joined, out);
  else
    throw InputError(first.path + ": cells of bench " + joined.benchmark + ", which bench merge does not join");
  return 0;
}

reference::PhotonReference photon_reference(const scene::Scene& scene, const reference::PhotonOptions& options, const std::string& cache) {
  if (cache.empty()) return reference::trace_photon_reference(scene, options);
  const std::string identity = reference::scene_identity(scene);
  const std::filesystem::path folder =
      std::filesystem::path(cache) /
      (identity + "-p" + std::to_string(options.photons) + "-m" + std::to_string(options.map_size) + "-s" + std::to_string(options.seed) +
       (options.light ? "-v" + std::to_string(options.light) : "") + ".shards");
  std::vector<std::string> shards;
  if (std::filesystem::is_directory(folder)) {
    for (const auto& entry : std::filesystem::directory_iterator(folder)) {
      // A shard still being written is a hidden temporary file; merge_photon_shards names any missing.
      if (entry.path().extension() == ".exr" && entry.path().filename().string().front() != '.') shards.push_back(entry.path().string());
    }
  }
  if (shards.empty()) {
    std::filesystem::create_directories(folder);
    const reference::TracedShard traced = reference::trace_photon_shard(scene, options, 0, 1);
    shards.push_back((folder / "shard_0.exr").string());
    reference::write_photon_shard(shards.back(), traced.shard, traced.map_units);
    std::fprintf(stderr, "reference: %s -> %s\n", scene.name.c_str(), folder.c_str());
  }
  std::sort(shards.begin(), shards.end());
  reference::MergedPhotons merged = reference::merge_photon_shards(shards);
  const reference::PhotonShard& whole = merged.whole;
  if (whole.scene_identity != identity || whole.total != options.photons || whole.map_size != options.map_size ||
      whole.seed != options.seed || whole.fresnel != options.fresnel) {
    throw InputError(folder.string() + ": its shards are of another reference (scene " + whole.scene_name + " " + whole.scene_identity +
                     ", photons " + std::to_string(whole.total) + ", map " + std::to_string(whole.map_size) + ", seed " +
                     std::to_string(whole.seed) + ") than its name says");
  }
  return {std::move(merged.caustic_map), {}, whole.totals};
}

}  // namespace caustica::cli::bench
