#pragma once
// What the caustica command's subcommands share: argument reading, number parsing with messages
// that name the flag, device options, progress lines and medians.
#include <chrono>
#include <cstdint>
#include <functional>
#include <set>
#include <string>
#include <vector>

#include "core/error.h"
#include "graph/graph_desc.h"
#include "scene/scene.h"
#include "vk/context.h"

namespace caustica::cli {

inline constexpr const char* kDefaultGraph = "graphs/caustics_adaptive.json";
inline constexpr const char* kDefaultScene = "scenes/glass_bunny.json";
// The scene the benchmarks default to (the paper's table, docs/caustics.md): the bunny lit from above.
inline constexpr const char* kBenchScene = "scenes/bunny_plane.json";

// What render, trace and view are told.
struct RenderOptions {
  std::string graph;
  std::string scene;
  bool scene_given = false;
  bool stage = true;  // a model file opened as a scene gets a floor (--no-stage: none)
  // --out: the picture (8-bit, .png and the like) and/or the linear result (.exr), at most one of each.
  std::vector<std::string> outs;
  std::string stats;
  std::string trace;
  uint32_t width = 1280;
  uint32_t height = 720;
  uint32_t frames = 1;
  bool accumulate = false;  // --accumulate: the frames are for the graph's accumulate passes
  uint64_t seconds = 0;     // --seconds: run frames until this long has passed instead
  std::vector<std::string> sets;
  bool moving = false;  // --moving: the graph's parameters as declared, not their while_still values
  std::vector<std::pair<std::string, std::string>> dumps;
  std::string device;
  bool validate = false;
  uint64_t memory_limit_mib = 1536;
  // --orbit: turn the camera by this much each frame and reuse the passes it does not touch, as the
  // viewer does: the interactive loop's frame times without a window (a GPU server has no display).
  float orbit_degrees = 0.0f;
  double frame_timeout_s = 0;  // --frame-timeout; 0: graph::Executor's defaults
};

class Args {
 public:
  Args(int argc, char** argv, int first) {
    for (int i = first; i < argc; ++i) items_.emplace_back(argv[i]);
  }
  bool done() const { return next_ >= items_.size(); }
  std::string take() { return items_[next_++]; }
  std::string value(const std::string& flag) {
    if (done()) throw UsageError(flag + " needs a value");
    return take();
  }
  bool wants_help() const {
    for (const auto& a : items_) {
      if (a == "--help" || a == "-h") return true;
    }
    return false;
  }

 private:
  std::vector<std::string> items_;
  size_t next_ = 0;
};

// Each throws UsageError naming the flag and the accepted range.
uint64_t parse_uint(const std::string& flag, const std::string& text, uint64_t min, uint64_t max);
double parse_number(const std::string& flag, const std::string& text, double min, double max);
void parse_size(const std::string& v, uint32_t& width, uint32_t& height);
// A comma-separated list of powers of two within [min, max], e.g. --grids 256,512,1024.
std::vector<uint32_t> parse_powers_of_two(const std::string& flag, const std::string& list, uint32_t min, uint32_t max);
// A comma-separated list of names, none empty.
std::vector<std::string> parse_names(const std::string& flag, const std::string& list);
[[noreturn]] void unknown_option(const std::string& arg, const std::vector<std::string>& known);
// Records `flag` as given; a flag that takes one value, given again, would silently replace the
// first, and is refused (callers leave out the repeatable ones, --set and --dump).
void given_once(std::set<std::string>& given, const std::string& flag);

// CAUSTICA_FAULT=device_lost|out_of_memory makes the device fail on purpose, so tests can check
// that such failures end the run with exit code 3 and no output (README, "Testing error paths").
vk::ContextOptions device_options(const std::string& device, bool validate);

// Progress of a long step on stderr, "LABEL done/total (p%)  elapsed, left": on a terminal one line
// rewritten in place; into a file or a pipe one line per tenth, so logs stay readable.
class ProgressLine {
 public:
  ProgressLine(std::string label, uint64_t total);
  void update(uint64_t done);

 private:
  std::string label_;
  uint64_t total_;
  std::chrono::steady_clock::time_point start_;
  bool terminal_;
  int printed_tenths_ = -1;
};

double median(std::vector<double> v);

// A scene file or a model opened as one (scene::load_scene_file), its warnings (what its files say
// and the engine does not draw) printed to stderr.
scene::Scene load_scene_and_warn(const std::string& path, bool stage);

// A headless command's graph at rest, as the viewer's once nothing moves: each parameter's first
// while_still value, except those that `sets` (--set NAME=VALUE) sets. Returns "NAME=VALUE" of each
// one applied.
std::vector<std::string> apply_at_rest(graph::GraphDesc& graph, const std::vector<std::string>& sets);
// Calls `configure` with `graph` (its `still` values applied); where that graph is refused
// (InputError: the device lacks what the still values need, e.g. ray queries), with `declared`
// instead, which `graph` becomes, and a note on stderr naming `file`. Any other error is the
// declared graph's own and stands.
void configure_at_rest(const std::string& file, graph::GraphDesc& graph, const graph::GraphDesc& declared,
                       const std::vector<std::string>& still, const std::function<void(const graph::GraphDesc&)>& configure);

// render's and trace's flags; graph plan and graph dot take them too.
RenderOptions parse_render(Args& args, bool trace);

int cmd_render(Args& args);
int cmd_trace(Args& args);
int cmd_validate(Args& args);
int cmd_graph(Args& args);
int cmd_reference(Args& args);
int cmd_merge(Args& args);
int cmd_compare(Args& args);
int cmd_bench(Args& args);
int cmd_view(Args& args);
int cmd_edit(Args& args);

}  // namespace caustica::cli
