// caustica bench accuracy: speed against accuracy against the ground truth (docs/accuracy.md).
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <stdexcept>

#include "bench_common.h"
#include "builtin_passes.h"
#include "core/paths.h"
#include "io/image_io.h"
#include "reference/image_metrics.h"
#include "reference/photon_reference.h"
#include "reference/refraction_reference.h"
#include "scene/scene.h"

namespace caustica::cli::bench {

namespace {

constexpr std::initializer_list<const char*> kRefractionPassTypes = {"refractor_buffers", "deferred_refraction", "forward_refraction",
                                                                     "refraction_layers"};

// What bench accuracy is told (caustica bench --help).
struct AccuracyOptions : ComparisonOptions {
  std::vector<std::string> scenes{"sphere_plane", "bunny_plane"};
  std::vector<std::string> graphs{"caustics_regular",
                                  "caustics_hierarchical",
                                  "caustics_adaptive_maxlevel",
                                  "caustics_adaptive_maxerror",
                                  "caustics_adaptive_maxerror:converge_test=same_texel",
                                  "caustics_adaptive",
                                  "caustics_adaptive:distance=dv_dn",
                                  "caustics_adaptive_hybrid:distance=search",
                                  "caustics_adaptive_hybrid",
                                  "caustics_raytraced",
                                  "refraction_forward",
                                  "refraction_deferred",
                                  "refraction_raytraced",
                                  "refraction_hybrid"};
  std::vector<uint32_t> grids{256, 512, 1024, 2048, 4096};
  uint32_t frames = 3, regular_max = 4096;
  CellOptions cells;
};

AccuracyOptions parse_accuracy_options(Args& args) {
  AccuracyOptions o;
  while (!args.done()) {
    std::string a = args.take();
    if (a == "--scenes")
      o.scenes = parse_names(a, args.value(a));
    else if (a == "--graphs")
      o.graphs = parse_names(a, args.value(a));
    else if (a == "--grids")
      o.grids = parse_powers_of_two(a, args.value(a), 64, 65536);
    else if (a == "--frames")
      o.frames = static_cast<uint32_t>(parse_uint(a, args.value(a), 1, 100));
    else if (a == "--regular-max")
      o.regular_max = static_cast<uint32_t>(parse_uint(a, args.value(a), 64, 65536));
    else if (!o.take(a, args) && !o.cells.take(a, args)) {
      std::vector<std::string> known{"--scenes", "--graphs", "--grids", "--frames", "--regular-max"};
      known.insert(known.end(), ComparisonOptions::kFlags.begin(), ComparisonOptions::kFlags.end());
      known.insert(known.end(), CellOptions::kFlags.begin(), CellOptions::kFlags.end());
      unknown_option(a, known);
    }
  }
  if (o.out_dir.empty() && !o.cells.list) throw UsageError("bench accuracy needs --out DIR");
  return o;
}

// The graphs to measure, each with its method label.
struct AccuracyGraphs {
  std::vector<graph::GraphDesc> descs;
  std::vector<std::string> labels;
};

// A graph is NAME or NAME:PARAM=VALUE[:PARAM=VALUE...], its method label the name and overrides.
AccuracyGraphs load_accuracy_graphs(const std::vector<std::string>& graphs) {
  AccuracyGraphs loaded;
  for (const auto& entry : graphs) {
    std::vector<std::string> sets;
    for (size_t at = entry.find(':'); at != std::string::npos;) {
      const size_t next = entry.find(':', at + 1);
      sets.push_back(entry.substr(at + 1, next == std::string::npos ? std::string::npos : next - at - 1));
      at = next;
    }
    const std::string name = entry.substr(0, entry.find(':'));
    loaded.descs.push_back(graph::load_graph_file(graph_path(name)));
    auto& g = loaded.descs.back();
    graph::apply_overrides(g, sets);
    std::string label = g.name;
    for (const auto& set : sets) label += " " + set;
    loaded.labels.push_back(label);
    if (caustic_passes(g).empty() && passes_of_types(g, {"deferred_refraction", "forward_refraction", "refraction_layers"}).empty()) {
      throw InputError(graph_path(name) + ": bench accuracy needs a graph with a caustic or a refraction pass");
    }
  }
  return loaded;
}

// An image-space refraction graph runs every image-space rung; one that traces exact paths by
// default (refraction_raytraced, refraction_hybrid) runs as it is.
std::vector<std::string> refraction_distances(const graph::GraphDesc& desc) {
  const graph::GraphParameter* distance_param = desc.find_parameter("distance");
  const std::string own = distance_param ? distance_param->value.get<std::string>() : "dv_dn";
  if (own == "ray_query" || own == "hybrid") return {own};
  return {"dv", "dv_dn", "search"};
}

// One cell of the sweep: a caustic graph on a scene at one grid, or a refraction graph on a scene
// at each of its distances (grid 0). The cells run in this order, one process's rows' order.
struct AccuracyCell {
  size_t scene = 0, graph = 0;
  uint32_t grid = 0;
};

std::vector<AccuracyCell> accuracy_cells(const AccuracyOptions& o, const AccuracyGraphs& graphs) {
  std::vector<AccuracyCell> cells;
  for (size_t s = 0; s < o.scenes.size(); ++s) {
    for (size_t g = 0; g < graphs.descs.size(); ++g) {
      const auto& desc = graphs.descs[g];
      if (caustic_passes(desc).empty()) {
        cells.push_back({s, g, 0});
        continue;
      }
      for (uint32_t grid : o.grids) {
        if (grid <= o.regular_max || passes_of_types(desc, {"caustic_map"}).empty()) cells.push_back({s, g, grid});
      }
    }
  }
  return cells;
}

constexpr const char* kAccuracyCsvHeader =
    "scene,kind,method,grid,photons_processed,method_ms,frame_ms,relative_l1,energy_ratio,shape_l1,psnr,nonfinite\n";

// One run of the benchmark, of the whole sweep or of one cell: what it was told, where it writes,
// the device, the references traced so far and the rows measured so far (results.csv and the table).
struct AccuracyRun {
  const AccuracyOptions& o;
  const std::filesystem::path& dir;
  vk::Context& vk;
  shader::ShaderCompiler& shaders;
  std::string csv, table;
  // The references of the scene whose cells run now (a scene's cells come together), kept no longer.
  size_t reference_scene = SIZE_MAX;
  std::optional<reference::PhotonReference> scene_photons;
  std::optional<reference::RefractionImage> scene_refraction;
  const std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();

  // A row of results.csv and of the table, and a line on stderr with the time since the start.
  void add_row(const std::string& scene, const char* kind, const std::string& method, uint32_t grid, double processed, const Timings& t,
               const reference::ImageComparison& c) {
    char line[512];
    std::snprintf(line, sizeof(line), "%s,%s,%s,%u,%.0f,%.4f,%.4f,%.6f,%.6f,%.6f,%.3f,%llu\n", scene.c_str(), kind, method.c_str(), grid,
                  processed, t.method_ms, t.frame_ms, c.relative_l1, c.energy_ratio, c.shape_l1, c.psnr,
                  static_cast<unsigned long long>(c.nonfinite_a));
    csv += line;
    std::snprintf(line, sizeof(line), "| %s | %s | %s | %.0f | %.2f | %.2f | %.4f | %s | %s |\n", scene.c_str(), method.c_str(),
                  grid ? (std::to_string(grid) + "^2").c_str() : "-", processed, t.method_ms, t.frame_ms, c.relative_l1,
                  std::isnan(c.energy_ratio) ? "-" : std::to_string(c.energy_ratio).substr(0, 6).c_str(),
                  std::isnan(c.shape_l1) ? "-" : std::to_string(c.shape_l1).substr(0, 6).c_str());
    table += line;
    std::fprintf(stderr, "%s %s%s: %.2f ms, relative L1 %.4f, energy %.4f  (%.0f s)\n", scene.c_str(), method.c_str(),
                 grid ? (" " + std::to_string(grid) + "^2").c_str() : "", t.method_ms, c.relative_l1, c.energy_ratio,
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }

  // One cell, on the executor that has its scene, against the references that it needs: traced (or
  // read from --reference-cache) the first time a cell of the scene asks; one process also writes
  // the photon reference's map to DIR.
  void measure_cell(const AccuracyCell& cell, const std::shared_ptr<const scene::Scene>& scene, const AccuracyGraphs& graphs,
                    graph::Executor& executor) {
    if (cell.scene != reference_scene) {
      reference_scene = cell.scene;
      scene_photons.reset();
      scene_refraction.reset();
    }
    const auto& desc = graphs.descs[cell.graph];
    const auto method_passes = caustic_passes(desc);
    if (method_passes.empty()) {
      if (!scene_refraction) scene_refraction = reference::render_refraction_reference(*scene, o.width, o.height);
      measure_refraction(executor, scene->name, desc, graphs.labels[cell.graph], *scene_refraction);
      return;
    }
    if (!scene_photons) {
      reference::PhotonOptions options;
      options.photons = o.reference_photons;
      options.map_size = o.caustic_size;
      ProgressLine progress(scene->name + ": reference photons", o.reference_photons);
      options.progress = [&](uint64_t done, uint64_t) { progress.update(done); };
      scene_photons = photon_reference(*scene, options, o.cells.reference_cache);
      if (o.cells.cell.empty()) io::write_image((dir / (scene->name + "_reference_caustics.exr")).string(), scene_photons->caustic_map);
    }
    measure_caustics(executor, scene->name, desc, graphs.labels[cell.graph], cell.grid, method_passes, *scene_photons);
  }

  // A caustic graph at one effective grid, its caustic map against the photon reference.
  void measure_caustics(graph::Executor& executor, const std::string& scene, const graph::GraphDesc& desc, const std::string& label,
                        uint32_t grid, const std::set<std::string>& method_passes, const reference::PhotonReference& traced) {
    graph::GraphDesc g = desc;
    graph::apply_overrides(g, {"grid=" + std::to_string(grid), "caustic_size=" + std::to_string(o.caustic_size)});
    if (!runs_on(vk, g)) {
      std::fprintf(stderr, "%s: skipped on %s, which lacks %s (ray queries)\n", label.c_str(), vk.device_name().c_str(),
                   vk.ray_queries().missing.c_str());
      return;
    }
    executor.configure(g, o.width, o.height, {.retained = {"caustics"}});
    const Timings t = time_frames(executor, o.frames, method_passes);
    const double processed = t.last.counters.count("photons.processed") ? t.last.counters.at("photons.processed") : 0.0;
    add_row(scene, "caustics", label, grid, processed, t,
            reference::compare_images(executor.read_image("caustics"), traced.caustic_map, o.blur));
  }

  // A refraction graph at every distance estimate, against the ray-traced reference.
  void measure_refraction(graph::Executor& executor, const std::string& scene, const graph::GraphDesc& desc, const std::string& label,
                          const reference::RefractionImage& refraction) {
    if (!runs_on(vk, desc)) {
      std::fprintf(stderr, "%s: skipped on %s, which lacks %s (ray queries)\n", label.c_str(), vk.device_name().c_str(),
                   vk.ray_queries().missing.c_str());
      return;
    }
    for (const std::string& distance : refraction_distances(desc)) {
      graph::GraphDesc g = desc;
      graph::apply_overrides(g, {"distance=" + distance});
      executor.configure(g, o.width, o.height, {.retained = {"refracted"}});
      const Timings t = time_frames(executor, o.frames, passes_of_types(desc, kRefractionPassTypes));
      reference::ImageComparison c;
      c.relative_l1 = reference::refraction_relative_l1(executor.read_image("refracted"), refraction);
      c.energy_ratio = c.shape_l1 = c.psnr = std::nan("");
      add_row(scene, "refraction", label + " " + distance, 0, 0.0, t, c);
    }
  }
};

// DIR/results.csv, DIR/README.md (the configuration and the table) and DIR/speed_accuracy.png, from
// the rows of one process or of its cells joined; the configuration and the table on stdout.
void write_results(const AccuracyOptions& o, const std::string& device, const std::string& csv, const std::string& table,
                   const Chart& chart) {
  const std::filesystem::path dir(o.out_dir);
  io::write_text_atomically((dir / "results.csv").string(), kAccuracyCsvHeader + csv);
  char config[1024];
  std::snprintf(config, sizeof(config),
                "Device %s. Frames %ux%u; median GPU time of %u frames after one warm-up. Caustic maps %u^2, compared with %llu "
                "reference photons (caustica reference --photons, Fresnel on) after a Gaussian blur of sigma %.3g texels; "
                "refraction compared with the ray-traced reference over the refractor's pixels (no blur).",
                device.c_str(), o.width, o.height, o.frames, o.caustic_size, static_cast<unsigned long long>(o.reference_photons), o.blur);
  const std::string header =
      "| scene | method | grid | photons processed | method GPU ms | frame GPU ms | relative L1 | energy ratio | shape L1 "
      "|\n|---|---|---|---|---|---|---|---|---|\n";
  io::write_text_atomically((dir / "README.md").string(),
                            "# caustica bench accuracy\n\n" + std::string(config) +
                                "\n\nColumns as in results.csv: `method GPU ms` is the caustic pass (photon work only; the light-space "
                                "inputs are the same for every method) or, for refraction, refractor_buffers plus the refraction pass. "
                                "`relative L1` and `energy ratio` are defined in docs/accuracy.md. The chart is speed_accuracy.png.\n\n" +
                                header + table);
  chart.draw(speed_accuracy_inputs(dir), dir / "speed_accuracy.png");
  std::cout << config << "\n\n" << header << table;
  std::fprintf(stderr, "bench accuracy: %s/results.csv, README.md, speed_accuracy.png\n", o.out_dir.c_str());
}

}  // namespace

// Speed against accuracy: every scene x caustic graph x effective photon grid against the photon
// reference, and every refraction graph x distance estimate against the ray-traced reference; or
// one cell of that sweep (--cell), or the list of its cells.
int cmd_bench_accuracy(Args& args) {
  const std::vector<std::string> sweep = sweep_arguments(args);
  const AccuracyOptions o = parse_accuracy_options(args);
  const AccuracyGraphs graphs = load_accuracy_graphs(o.graphs);
  const std::vector<AccuracyCell> cells = accuracy_cells(o, graphs);
  if (o.cells.list) {
    for (size_t k = 0; k < cells.size(); ++k) {
      const AccuracyCell& c = cells[k];
      std::string distances;
      for (const auto& d : refraction_distances(graphs.descs[c.graph])) distances += (distances.empty() ? "" : ",") + d;
      std::printf("%zu %s %s %s\n", k, o.scenes[c.scene].c_str(), o.graphs[c.graph].c_str(),
                  c.grid ? ("grid=" + std::to_string(c.grid)).c_str() : ("distance=" + distances).c_str());
    }
    return 0;
  }
  const bool one_cell = !o.cells.cell.empty();
  const size_t first = one_cell ? cell_index(o.cells.cell, cells.size()) : 0, end = one_cell ? first + 1 : cells.size();
  // Everything is loaded and checked before the first long step.
  std::vector<std::shared_ptr<const scene::Scene>> loaded(o.scenes.size());
  for (size_t k = first; k < end; ++k) {
    auto& scene = loaded[cells[k].scene];
    if (!scene) scene = std::make_shared<const scene::Scene>(scene::load_scene_file(scene_path(o.scenes[cells[k].scene])));
  }
  const Chart chart = one_cell ? Chart{} : find_chart();
  std::filesystem::create_directories(o.out_dir);
  const std::filesystem::path dir(o.out_dir);

  vk::Context vk(device_options(o.device, false));
  shader::ShaderCompiler shaders(data_dir() / "shaders");
  AccuracyRun run{o, dir, vk, shaders};
  // A graph's cells on a scene share its executor, as its grids did before the sweep had cells.
  std::unique_ptr<graph::Executor> executor;
  for (size_t k = first; k < end; ++k) {
    if (!executor || cells[k].scene != cells[k - 1].scene || cells[k].graph != cells[k - 1].graph) {
      executor = std::make_unique<graph::Executor>(vk, shaders, passes::builtin_registry());
      executor->set_scene(loaded[cells[k].scene]);
    }
    run.measure_cell(cells[k], loaded[cells[k].scene], graphs, *executor);
  }
  if (one_cell)
    write_cell(dir, first, cells.size(), kAccuracyCsvHeader, {"accuracy", sweep, vk.device_name(), run.csv, run.table});
  else
    write_results(o, vk.device_name(), run.csv, run.table, chart);
  return 0;
}

void write_merged_accuracy(const CellRows& rows, const std::string& out_dir) {
  Args args = sweep_args(rows.sweep, out_dir);
  const AccuracyOptions o = parse_accuracy_options(args);
  const Chart chart = find_chart();
  std::filesystem::create_directories(out_dir);
  write_results(o, rows.device, rows.csv, rows.table, chart);
}

}  // namespace caustica::cli::bench
