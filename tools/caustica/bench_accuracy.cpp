// caustica bench accuracy: speed against accuracy against the ground truth (docs/accuracy.md).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
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
    else if (!o.take(a, args)) {
      std::vector<std::string> known{"--scenes", "--graphs", "--grids", "--frames", "--regular-max"};
      known.insert(known.end(), ComparisonOptions::kFlags.begin(), ComparisonOptions::kFlags.end());
      unknown_option(a, known);
    }
  }
  if (o.out_dir.empty()) throw UsageError("bench accuracy needs --out DIR");
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
    if (passes_of_types(g, kCausticPassTypes).empty() &&
        passes_of_types(g, {"deferred_refraction", "forward_refraction", "refraction_layers"}).empty()) {
      throw InputError(graph_path(name) + ": bench accuracy needs a graph with a caustic or a refraction pass");
    }
  }
  return loaded;
}

// One run of the benchmark: what it was told, where it writes, the device, and the rows measured
// so far (results.csv and the table).
struct AccuracyRun {
  const AccuracyOptions& o;
  const std::filesystem::path& dir;
  vk::Context& vk;
  shader::ShaderCompiler& shaders;
  std::string csv = "scene,kind,method,grid,photons_processed,method_ms,frame_ms,relative_l1,energy_ratio,shape_l1,psnr,nonfinite\n";
  std::string table =
      "| scene | method | grid | photons processed | method GPU ms | frame GPU ms | relative L1 | energy ratio | shape L1 "
      "|\n|---|---|---|---|---|---|---|---|---|\n";
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

  // Every graph on one scene, against the references that its graphs need (the photon reference's
  // map is written to DIR).
  void measure_scene(const std::shared_ptr<const scene::Scene>& scene, const AccuracyGraphs& graphs) {
    bool wants_caustics = false, wants_refraction = false;
    for (const auto& g : graphs.descs) {
      wants_caustics = wants_caustics || !passes_of_types(g, kCausticPassTypes).empty();
      wants_refraction = wants_refraction || passes_of_types(g, kCausticPassTypes).empty();
    }
    reference::PhotonReference photons;
    if (wants_caustics) {
      reference::PhotonOptions options;
      options.photons = o.reference_photons;
      options.map_size = o.caustic_size;
      ProgressLine progress(scene->name + ": reference photons", o.reference_photons);
      options.progress = [&](uint64_t done, uint64_t) { progress.update(done); };
      photons = reference::trace_photon_reference(*scene, options);
      io::write_image((dir / (scene->name + "_reference_caustics.exr")).string(), photons.caustic_map);
    }
    reference::RefractionImage refraction;
    if (wants_refraction) refraction = reference::render_refraction_reference(*scene, o.width, o.height);

    for (size_t gi = 0; gi < graphs.descs.size(); ++gi) {
      const auto& desc = graphs.descs[gi];
      const auto caustic_passes = passes_of_types(desc, kCausticPassTypes);
      graph::Executor executor(vk, shaders, passes::builtin_registry());
      executor.set_scene(scene);
      if (!caustic_passes.empty())
        measure_caustics(executor, scene->name, desc, graphs.labels[gi], caustic_passes, photons);
      else
        measure_refraction(executor, scene->name, desc, graphs.labels[gi], refraction);
    }
  }

  // A caustic graph at every effective grid (the regular map up to --regular-max), its caustic map
  // against the photon reference.
  void measure_caustics(graph::Executor& executor, const std::string& scene, const graph::GraphDesc& desc, const std::string& label,
                        const std::set<std::string>& caustic_passes, const reference::PhotonReference& photons) {
    for (uint32_t grid : o.grids) {
      if (grid > o.regular_max && !passes_of_types(desc, {"caustic_map"}).empty()) continue;
      graph::GraphDesc g = desc;
      graph::apply_overrides(g, {"grid=" + std::to_string(grid), "caustic_size=" + std::to_string(o.caustic_size)});
      if (!runs_on(vk, g)) {
        std::fprintf(stderr, "%s: skipped on %s, which lacks %s (ray queries)\n", label.c_str(), vk.device_name().c_str(),
                     vk.ray_queries().missing.c_str());
        break;
      }
      executor.configure(g, o.width, o.height, {"caustics"});
      const Timings t = time_frames(executor, o.frames, caustic_passes);
      const double processed = t.last.counters.count("photons.processed") ? t.last.counters.at("photons.processed") : 0.0;
      add_row(scene, "caustics", label, grid, processed, t,
              reference::compare_images(executor.read_image("caustics"), photons.caustic_map, o.blur));
    }
  }

  // A refraction graph at every distance estimate, against the ray-traced reference.
  void measure_refraction(graph::Executor& executor, const std::string& scene, const graph::GraphDesc& desc, const std::string& label,
                          const reference::RefractionImage& refraction) {
    // An image-space graph runs every image-space rung; one that traces exact paths by default
    // (refraction_raytraced, refraction_hybrid) runs as it is.
    const graph::GraphParameter* distance_param = desc.find_parameter("distance");
    const std::string own = distance_param ? distance_param->value.get<std::string>() : "dv_dn";
    const bool exact = own == "ray_query" || own == "hybrid";
    if (!runs_on(vk, desc)) {
      std::fprintf(stderr, "%s: skipped on %s, which lacks %s (ray queries)\n", label.c_str(), vk.device_name().c_str(),
                   vk.ray_queries().missing.c_str());
      return;
    }
    for (const std::string& distance : exact ? std::vector<std::string>{own} : std::vector<std::string>{"dv", "dv_dn", "search"}) {
      graph::GraphDesc g = desc;
      graph::apply_overrides(g, {"distance=" + distance});
      executor.configure(g, o.width, o.height, {"refracted"});
      const Timings t = time_frames(executor, o.frames, passes_of_types(desc, kRefractionPassTypes));
      reference::ImageComparison c;
      c.relative_l1 = reference::refraction_relative_l1(executor.read_image("refracted"), refraction);
      c.energy_ratio = c.shape_l1 = c.psnr = std::nan("");
      add_row(scene, "refraction", label + " " + distance, 0, 0.0, t, c);
    }
  }

  // DIR/results.csv, DIR/README.md (the configuration and the table) and DIR/speed_accuracy.png;
  // the configuration and the table on stdout.
  void write_results(const Chart& chart) const {
    io::write_text_atomically((dir / "results.csv").string(), csv);
    char config[1024];
    std::snprintf(config, sizeof(config),
                  "Device %s. Frames %ux%u; median GPU time of %u frames after one warm-up. Caustic maps %u^2, compared with %llu "
                  "reference photons (caustica reference --photons, Fresnel on) after a Gaussian blur of sigma %.3g texels; "
                  "refraction compared with the ray-traced reference over the refractor's pixels (no blur).",
                  vk.device_name().c_str(), o.width, o.height, o.frames, o.caustic_size,
                  static_cast<unsigned long long>(o.reference_photons), o.blur);
    io::write_text_atomically((dir / "README.md").string(),
                              "# caustica bench accuracy\n\n" + std::string(config) +
                                  "\n\nColumns as in results.csv: `method GPU ms` is the caustic pass (photon work only; the light-space "
                                  "inputs are the same for every method) or, for refraction, refractor_buffers plus the refraction pass. "
                                  "`relative L1` and `energy ratio` are defined in docs/accuracy.md. The chart is speed_accuracy.png.\n\n" +
                                  table);
    chart.draw(speed_accuracy_inputs(dir), dir / "speed_accuracy.png");
    std::cout << config << "\n\n" << table;
    std::fprintf(stderr, "bench accuracy: %s/results.csv, README.md, speed_accuracy.png\n", o.out_dir.c_str());
  }
};

}  // namespace

// Speed against accuracy: every scene x caustic graph x effective photon grid against the photon
// reference, and every refraction graph x distance estimate against the ray-traced reference.
int cmd_bench_accuracy(Args& args) {
  const AccuracyOptions o = parse_accuracy_options(args);
  // Everything is loaded and checked before the first long step.
  std::vector<std::shared_ptr<const scene::Scene>> loaded;
  for (const auto& name : o.scenes) loaded.push_back(std::make_shared<const scene::Scene>(scene::load_scene_file(scene_path(name))));
  const AccuracyGraphs graphs = load_accuracy_graphs(o.graphs);
  const Chart chart = find_chart();
  std::filesystem::create_directories(o.out_dir);
  const std::filesystem::path dir(o.out_dir);

  vk::Context vk(device_options(o.device, false));
  shader::ShaderCompiler shaders(data_dir() / "shaders");
  AccuracyRun run{o, dir, vk, shaders};
  for (const auto& scene : loaded) run.measure_scene(scene, graphs);
  run.write_results(chart);
  return 0;
}

}  // namespace caustica::cli::bench
