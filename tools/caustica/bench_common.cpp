// What the benchmarks share; bench_common.h says what each does.
#include "bench_common.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>

#include "builtin_passes.h"
#include "core/paths.h"

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

bool ComparisonOptions::take(const std::string& flag, Args& args) {
  if (flag == "--caustic-size")
    caustic_size = static_cast<uint32_t>(parse_uint(flag, args.value(flag), 16, 8192));
  else if (flag == "--size")
    parse_size(args.value(flag), width, height);
  else if (flag == "--reference-photons")
    reference_photons = parse_uint(flag, args.value(flag), 1000, 100'000'000'000ull);
  else if (flag == "--blur")
    blur = parse_number(flag, args.value(flag), 0, 64);
  else if (flag == "--out")
    out_dir = args.value(flag);
  else if (flag == "--device")
    device = args.value(flag);
  else
    return false;
  return true;
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

}  // namespace caustica::cli::bench
