// caustica bench convergence: the error of an accumulating caustic map against wall time, for each
// distance method of a progressive graph, against the photon reference (docs/interactive.md).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>

#include "bench_common.h"
#include "builtin_passes.h"
#include "core/paths.h"
#include "core/suggest.h"
#include "io/image_io.h"
#include "reference/image_metrics.h"
#include "reference/photon_reference.h"
#include "scene/scene.h"

namespace caustica::cli::bench {

namespace {

// What bench convergence is told (caustica bench --help).
struct ConvergenceOptions : ComparisonOptions {
  ConvergenceOptions() {  // the viewer's size, and the graph's own caustic map
    caustic_size = 0;
    width = 1280;
    height = 720;
  }
  std::string scene = "glass_bunny", graph = "caustics_progressive", reference_file;
  std::vector<std::string> methods{"dv_dn", "search", "hybrid", "ray_query"};
  double seconds = 30;
  uint32_t frames = 0;  // when given, instead of --seconds
  uint32_t grid = 0;    // 0: the graph's own
};

ConvergenceOptions parse_convergence_options(Args& args) {
  ConvergenceOptions o;
  bool seconds_given = false;
  while (!args.done()) {
    std::string a = args.take();
    if (a == "--scene")
      o.scene = args.value(a);
    else if (a == "--graph")
      o.graph = args.value(a);
    else if (a == "--methods")
      o.methods = parse_names(a, args.value(a));
    else if (a == "--seconds") {
      o.seconds = parse_number(a, args.value(a), 0.001, 86400);
      seconds_given = true;
    } else if (a == "--frames")
      o.frames = static_cast<uint32_t>(parse_uint(a, args.value(a), 1, 1'000'000));
    else if (a == "--grid")
      o.grid = static_cast<uint32_t>(parse_uint(a, args.value(a), 16, 16384));
    else if (a == "--reference")
      o.reference_file = args.value(a);
    else if (!o.take(a, args)) {
      std::vector<std::string> known{"--scene", "--graph", "--methods", "--seconds", "--frames", "--grid", "--reference"};
      known.insert(known.end(), ComparisonOptions::kFlags.begin(), ComparisonOptions::kFlags.end());
      unknown_option(a, known);
    }
  }
  if (o.out_dir.empty()) throw UsageError("bench convergence needs --out DIR");
  if (seconds_given && o.frames > 0) throw UsageError("bench convergence: give --seconds or --frames, not both");
  return o;
}

// The graph with one method's distance and the sizes asked for; checked before the long work.
graph::GraphDesc method_graph(const graph::GraphDesc& loaded, const ConvergenceOptions& o, const std::string& method) {
  graph::GraphDesc g = loaded;
  std::vector<std::string> sets{"distance=" + method};
  if (o.grid) sets.push_back("grid=" + std::to_string(o.grid));
  if (o.caustic_size) sets.push_back("caustic_size=" + std::to_string(o.caustic_size));
  graph::apply_overrides(g, sets);
  return g;
}

// The frames after which the mean is compared with the reference: every one of the first eight,
// then about four a doubling, and the last.
bool checkpoint(uint32_t frame) {
  if (frame <= 8) return true;
  const uint32_t step = 1u << (31 - __builtin_clz(frame) - 2);  // a quarter of the power of two below
  return frame % step == 0;
}

struct Row {
  std::string method;
  uint32_t frame = 0;
  double seconds = 0, frame_ms = 0;
  reference::ImageComparison error;
};

// First time a method's error is at most `limit`, as a table cell.
std::string time_to(const std::vector<Row>& rows, const std::string& method, double limit) {
  for (const auto& r : rows) {
    if (r.method == method && r.error.relative_l1 <= limit) {
      char cell[64];
      std::snprintf(cell, sizeof(cell), "%.1f s (frame %u)", r.seconds, r.frame);
      return cell;
    }
  }
  return "not reached";
}

// A method's error at its last checkpoint no later than `seconds`, as a table cell; "-" where the
// run ended well before.
std::string error_at(const std::vector<Row>& rows, const std::string& method, double seconds) {
  const Row* at = nullptr;
  double end = 0;
  for (const auto& r : rows) {
    if (r.method != method) continue;
    if (r.seconds <= seconds) at = &r;
    end = r.seconds;
  }
  if (!at || end < 0.9 * seconds) return "-";
  char cell[32];
  std::snprintf(cell, sizeof(cell), "%.4f", at->error.relative_l1);
  return cell;
}

}  // namespace

// Each method accumulates from a fresh start (after one frame elsewhere that compiles its
// pipelines), and its mean is compared with the reference after frames spaced out over the run;
// the clock stops while a mean is read back and compared, so the times are the viewer's.
int cmd_bench_convergence(Args& args) {
  const ConvergenceOptions o = parse_convergence_options(args);
  // Everything is loaded and checked before the first long step.
  const auto scene = std::make_shared<const scene::Scene>(scene::load_scene_file(scene_path(o.scene)));
  const graph::GraphDesc loaded = graph::load_graph_file(graph_path(o.graph));
  if (!loaded.find_parameter("distance") || !loaded.find_parameter("caustic_size") || passes_of_types(loaded, {"accumulate"}).empty()) {
    throw InputError(graph_path(o.graph) +
                     ": bench convergence needs a graph with an accumulate pass writing `caustics` and the "
                     "parameters `distance` and `caustic_size`, as graphs/caustics_progressive.json has");
  }
  std::vector<graph::GraphDesc> graphs;
  const graph::ParamDecl& distance = loaded.find_parameter("distance")->decl;
  for (const auto& method : o.methods) {
    if (const std::string wrong = graph::check_param_value(distance, method); !wrong.empty())
      throw UsageError("--methods " + method + ": " + loaded.name + "'s distance " + wrong + did_you_mean(method, distance.choices));
    graphs.push_back(method_graph(loaded, o, method));
  }
  const uint32_t caustic_size = static_cast<uint32_t>(graphs.front().find_parameter("caustic_size")->value.get<int64_t>());
  io::ImageData reference_map;
  if (!o.reference_file.empty()) {
    reference_map = io::read_image(o.reference_file);
    if (reference_map.width != caustic_size || reference_map.height != caustic_size) {
      throw InputError(o.reference_file + ": the reference map is " + std::to_string(reference_map.width) + "x" +
                       std::to_string(reference_map.height) + ", the caustic map " + std::to_string(caustic_size) + "x" +
                       std::to_string(caustic_size) + " (--caustic-size)");
    }
  }
  const Chart chart = find_chart();
  const std::filesystem::path dir(o.out_dir);
  std::filesystem::create_directories(dir);

  vk::Context vk(device_options(o.device, false));
  shader::ShaderCompiler shaders(data_dir() / "shaders");
  if (reference_map.rgba.empty()) {
    reference::PhotonOptions options;
    options.photons = o.reference_photons;
    options.map_size = caustic_size;
    ProgressLine progress(scene->name + ": reference photons", o.reference_photons);
    options.progress = [&](uint64_t done, uint64_t) { progress.update(done); };
    reference_map = reference::trace_photon_reference(*scene, options).caustic_map;
    io::write_image((dir / (scene->name + "_reference_caustics.exr")).string(), reference_map);
  }

  using Clock = std::chrono::steady_clock;
  std::vector<Row> rows;
  for (size_t m = 0; m < graphs.size(); ++m) {
    const std::string& method = o.methods[m];
    if (!runs_on(vk, graphs[m])) {
      std::fprintf(stderr, "%s: skipped on %s, which lacks %s (ray queries)\n", method.c_str(), vk.device_name().c_str(),
                   vk.ray_queries().missing.c_str());
      continue;
    }
    {  // the pipelines compile here (vk::Context keeps them), outside the measured run
      graph::Executor warm_up(vk, shaders, passes::builtin_registry());
      warm_up.set_scene(scene);
      warm_up.configure(graphs[m], o.width, o.height);
      warm_up.run_frame(false);
    }
    graph::Executor executor(vk, shaders, passes::builtin_registry());
    executor.set_scene(scene);
    // As the viewer: at rest the camera's and the light's own passes keep their results.
    executor.configure(graphs[m], o.width, o.height, {.retained = {"caustics"}, .reuse_unchanged_passes = true});
    double elapsed = 0, last_ms = 0;
    for (uint32_t frame = 1;; ++frame) {
      // With --seconds, the last frame is the one that would end past the limit, judged by the one before.
      const bool last = o.frames > 0 ? frame == o.frames : elapsed + last_ms / 1000.0 >= o.seconds;
      const bool compare = last || checkpoint(frame);
      const auto start = Clock::now();
      executor.run_frame(compare);
      last_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
      elapsed += last_ms / 1000.0;
      if (compare) {
        rows.push_back(
            {method, frame, elapsed, last_ms, reference::compare_images(executor.read_image("caustics"), reference_map, o.blur)});
        std::fprintf(stderr, "%s %s: frame %u, %.2f s, relative L1 %.4f, energy %.4f\n", scene->name.c_str(), method.c_str(), frame,
                     elapsed, rows.back().error.relative_l1, rows.back().error.energy_ratio);
      }
      if (last) break;
    }
  }

  std::string csv = "scene,method,frame,seconds,frame_ms,relative_l1,energy_ratio,shape_l1\n";
  for (const auto& r : rows) {
    char line[256];
    std::snprintf(line, sizeof(line), "%s,%s,%u,%.4f,%.3f,%.6f,%.6f,%.6f\n", scene->name.c_str(), r.method.c_str(), r.frame, r.seconds,
                  r.frame_ms, r.error.relative_l1, r.error.energy_ratio, r.error.shape_l1);
    csv += line;
  }
  std::string table =
      "| method | relative L1 after 1 s | after 10 s | after 30 s | at the end | to 0.10 | to 0.05 | frames |\n"
      "|---|---|---|---|---|---|---|---|\n";
  for (const auto& method : o.methods) {
    const Row* end = nullptr;
    for (const auto& r : rows) end = r.method == method ? &r : end;
    if (!end) continue;
    char line[512];
    std::snprintf(line, sizeof(line), "| %s | %s | %s | %s | %.4f (%.1f s) | %s | %s | %u |\n", method.c_str(),
                  error_at(rows, method, 1).c_str(), error_at(rows, method, 10).c_str(), error_at(rows, method, 30).c_str(),
                  end->error.relative_l1, end->seconds, time_to(rows, method, 0.10).c_str(), time_to(rows, method, 0.05).c_str(),
                  end->frame);
    table += line;
  }
  char config[1024];
  std::snprintf(config, sizeof(config),
                "Scene %s, graph %s, device %s. Frames %ux%u, each method from a fresh start after one frame that compiles its "
                "pipelines, passes whose inputs did not change keeping their results as in the viewer; wall time of the frames "
                "only (the clock stops while a mean is read back and compared). Caustic maps "
                "%u^2 against %s after a Gaussian blur of sigma %.3g texels.",
                scene->name.c_str(), loaded.name.c_str(), vk.device_name().c_str(), o.width, o.height, caustic_size,
                o.reference_file.empty() ? (std::to_string(o.reference_photons) + " reference photons (Fresnel on)").c_str()
                                         : o.reference_file.c_str(),
                o.blur);
  io::write_text_atomically((dir / "convergence.csv").string(), csv);
  io::write_text_atomically((dir / "convergence.md").string(),
                            "# caustica bench convergence\n\n" + std::string(config) +
                                "\n\nThe rows of convergence.csv, one per compared frame; the chart is convergence.png.\n\n" + table);
  chart.draw({dir / "convergence.csv"}, dir / "convergence.png");
  if (std::filesystem::exists(dir / "results.csv")) chart.draw(speed_accuracy_inputs(dir), dir / "speed_accuracy.png");
  std::cout << config << "\n\n" << table;
  std::fprintf(stderr, "bench convergence: %s/convergence.csv, convergence.md, convergence.png\n", o.out_dir.c_str());
  return 0;
}

}  // namespace caustica::cli::bench
