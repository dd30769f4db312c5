// caustica bench: refraction (deferred against forward), photons (the paper's table) and accuracy
// (speed against accuracy against the ground truth). Run by hand; results go into docs/.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <set>
#include <stdexcept>

#include <unistd.h>

#include "builtin_passes.h"
#include "cli.h"
#include "core/paths.h"
#include "core/suggest.h"
#include "graph/executor.h"
#include "io/image_io.h"
#include "reference/image_metrics.h"
#include "reference/photon_reference.h"
#include "reference/refraction_reference.h"
#include "scene/gpu_scene.h"
#include "scene/scene.h"

namespace caustica::cli {

namespace {

// A file (NAME.json) as given, or a bundled one by name ("bunny_plane", "stability/close_light").
std::string bundled_path(const char* folder, const std::string& name) {
  return std::filesystem::path(name).extension() == ".json" ? name : (data_dir() / folder / (name + ".json")).string();
}

std::string scene_path(const std::string& name) {
  return bundled_path("scenes", name);
}
std::string graph_path(const std::string& name) {
  return bundled_path("graphs", name);
}

// `s` as one word of a POSIX shell command line, whatever it holds (a folder named "it's", say).
std::string shell_word(const std::string& s) {
  std::string word = "'";
  for (char c : s) word += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return word + "'";
}

// The interpreter that draws the accuracy chart: CAUSTICA_PYTHON, else Debian's, where
// python3-matplotlib installs, even when another python3 comes first on PATH.
std::string chart_python() {
  if (const char* env = std::getenv("CAUSTICA_PYTHON"); env && *env) return env;
  return std::filesystem::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
}

}  // namespace

// Loading a model or scene: the host's part (parsing, decoding the textures materials use, normals,
// d_N) and the device's (buffers, texture upload with their mip chains), median over runs.
int cmd_bench_load(Args& args) {
  std::string file, device;
  uint32_t runs = 5;
  while (!args.done()) {
    std::string a = args.take();
    if (a == "--scene")
      file = args.value(a);
    else if (a == "--runs")
      runs = static_cast<uint32_t>(parse_uint(a, args.value(a), 1, 100));
    else if (a == "--device")
      device = args.value(a);
    else
      unknown_option(a, {"--scene", "--runs", "--device"});
  }
  if (file.empty()) throw UsageError("bench load needs --scene FILE (a scene or a model file)");
  vk::Context vk(device_options(device, false));
  std::vector<double> host_ms, device_ms;
  std::shared_ptr<const scene::Scene> scene;
  uint64_t texture_bytes = 0;
  for (uint32_t run = 0; run < runs; ++run) {
    const auto start = std::chrono::steady_clock::now();
    scene = std::make_shared<const scene::Scene>(scene::load_scene_file(file));
    const auto loaded = std::chrono::steady_clock::now();
    {
      scene::GpuScene on_device(vk, scene);
      texture_bytes = on_device.texture_bytes();
    }
    const auto uploaded = std::chrono::steady_clock::now();
    host_ms.push_back(std::chrono::duration<double, std::milli>(loaded - start).count());
    device_ms.push_back(std::chrono::duration<double, std::milli>(uploaded - loaded).count());
    vk.wait_idle();
  }
  auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
  };
  std::printf("%s: %zu triangles, %zu of %zu images decoded (%.1f MiB of textures on the device with their mips)\n", file.c_str(),
              scene->triangle_count(), scene->textures.size(), scene->file_images, static_cast<double>(texture_bytes) / (1 << 20));
  std::printf("median of %u runs: host %.0f ms (parse, decode, normals, d_N), device %.0f ms (upload), total %.0f ms\n", runs,
              median(host_ms), median(device_ms), median(host_ms) + median(device_ms));
  return 0;
}

// Deferred against forward refraction: the same scene through both graphs, frames interleaved so
// that machine noise hits both alike, median GPU time of the refraction passes and of the frame.
int cmd_bench_refraction(Args& args) {
  std::vector<std::string> scenes;
  uint32_t width = 1280, height = 720, frames = 7;
  std::vector<uint32_t> sphere_details;
  std::string device, csv;
  while (!args.done()) {
    std::string a = args.take();
    if (a == "--scene")
      scenes.push_back(args.value(a));
    else if (a == "--size")
      parse_size(args.value(a), width, height);
    else if (a == "--frames")
      frames = static_cast<uint32_t>(parse_uint(a, args.value(a), 1, 1000));
    else if (a == "--sphere-detail")
      sphere_details.push_back(static_cast<uint32_t>(parse_uint(a, args.value(a), 3, 1024)));
    else if (a == "--device")
      device = args.value(a);
    else if (a == "--csv")
      csv = args.value(a);
    else
      unknown_option(a, {"--scene", "--size", "--frames", "--sphere-detail", "--device", "--csv"});
  }
  if (!csv.empty()) io::check_output_file(csv);
  struct Case {
    std::string label;
    std::shared_ptr<const scene::Scene> scene;
  };
  std::vector<Case> cases;
  for (const auto& file : scenes) {
    auto s = std::make_shared<const scene::Scene>(scene::load_scene_file(file));
    cases.push_back({s->name, s});
  }
  for (uint32_t detail : sphere_details) {
    // The ball-lens scene with its sphere tessellated more or less finely: triangle count alone varies.
    scene::Scene s = scene::load_scene_file((data_dir() / "scenes/sphere_plane.json").string());
    for (auto& o : s.objects) {
      if (!o.material.refractor) continue;
      const glm::vec3 centre = o.center();
      const float radius = 0.5f * (o.bounds_max.y - o.bounds_min.y);
      o.mesh = scene::make_sphere(radius, static_cast<int>(detail), static_cast<int>(std::max(2u, detail / 2)));
      for (auto& p : o.mesh.positions) p += centre;
      o.mesh.normal_distance = scene::normal_distances(o.mesh);
    }
    cases.push_back({"sphere, detail " + std::to_string(detail), std::make_shared<const scene::Scene>(std::move(s))});
  }
  if (cases.empty()) {  // the bundled ball lens and bunny
    for (const char* name : {"sphere_plane", "bunny_plane"}) {
      auto s = std::make_shared<const scene::Scene>(scene::load_scene_file(scene_path(name)));
      cases.push_back({s->name, s});
    }
  }

  vk::Context vk(device_options(device, false));
  shader::ShaderCompiler shaders(data_dir() / "shaders");
  const char* graphs[2] = {"refraction_forward", "refraction_deferred"};
  std::string table =
      "| scene | refractor triangles | forward: refraction passes | deferred: refraction passes | deferred / forward | forward frame | "
      "deferred frame |\n|---|---|---|---|---|---|---|\n";
  std::string rows_csv = "scene,refractor_triangles,forward_refraction_ms,deferred_refraction_ms,forward_frame_ms,deferred_frame_ms\n";
  for (const auto& c : cases) {
    std::unique_ptr<graph::Executor> executors[2];
    for (int g = 0; g < 2; ++g) {
      executors[g] = std::make_unique<graph::Executor>(vk, shaders, passes::builtin_registry());
      executors[g]->set_scene(c.scene);
      executors[g]->configure(graph::load_graph_file((data_dir() / "graphs" / (std::string(graphs[g]) + ".json")).string()), width, height);
    }
    std::vector<double> refraction[2], frame[2];
    ProgressLine progress(c.label + ": frames", frames + 2);
    for (uint32_t f = 0; f < frames + 2; ++f) {
      for (int g = 0; g < 2; ++g) {
        auto result = executors[g]->run_frame(false);
        if (f < 2) continue;  // pipelines compile on first use on lavapipe
        double ms = 0;
        for (const auto& p : result.passes) {
          if (p.name == "refractors" || p.name == "refraction") ms += p.gpu_ms;
        }
        refraction[g].push_back(ms);
        frame[g].push_back(result.gpu_ms);
      }
      progress.update(f + 1);
    }
    size_t triangles = 0;
    for (const auto& o : c.scene->objects) triangles += o.material.refractor ? o.mesh.indices.size() / 3 : 0;
    const double fw = median(refraction[0]), df = median(refraction[1]);
    char row[512];
    std::snprintf(row, sizeof(row), "| %s | %zu | %.2f ms | %.2f ms | %.2f | %.2f ms | %.2f ms |\n", c.label.c_str(), triangles, fw, df,
                  df / fw, median(frame[0]), median(frame[1]));
    table += row;
    std::snprintf(row, sizeof(row), "%s,%zu,%.4f,%.4f,%.4f,%.4f\n", c.label.c_str(), triangles, fw, df, median(frame[0]), median(frame[1]));
    rows_csv += row;
  }
  std::cout << "device: " << vk.device_name() << ", " << width << "x" << height << ", median of " << frames << " frames after 2 warm-up\n\n"
            << table;
  if (!csv.empty()) io::write_text_atomically(csv, rows_csv);
  return 0;
}

// The paper's table: photons processed per method and effective grid on one scene, with the GPU
// time of the caustic pass, one run.
int cmd_bench_photons(Args& args) {
  std::string scene_file = (data_dir() / kBenchScene).string(), out_dir, device;
  std::vector<uint32_t> grids{256, 512, 1024, 2048, 4096, 8192, 16384};
  uint32_t frames = 3, regular_max = 16384;
  while (!args.done()) {
    std::string a = args.take();
    if (a == "--scene")
      scene_file = args.value(a);
    else if (a == "--out")
      out_dir = args.value(a);
    else if (a == "--device")
      device = args.value(a);
    else if (a == "--frames")
      frames = static_cast<uint32_t>(parse_uint(a, args.value(a), 1, 100));
    else if (a == "--regular-max")
      regular_max = static_cast<uint32_t>(parse_uint(a, args.value(a), 64, 65536));
    else if (a == "--grids") {
      grids = parse_powers_of_two(a, args.value(a), 64, 65536);
    } else {
      unknown_option(a, {"--scene", "--grids", "--frames", "--regular-max", "--out", "--device"});
    }
  }
  auto scene = std::make_shared<const scene::Scene>(scene::load_scene_file(scene_file));
  vk::Context vk(device_options(device, false));
  shader::ShaderCompiler shaders(data_dir() / "shaders");
  struct Method {
    const char* name;
    const char* graph;
    const char* set;  // a parameter override, or ""
  };
  const Method methods[] = {{"regular", "caustics_regular", ""},
                            {"hierarchical", "caustics_hierarchical", ""},
                            {"adaptive_max_level", "caustics_adaptive_maxlevel", ""},
                            {"adaptive_max_error", "caustics_adaptive_maxerror", ""},
                            {"adaptive_max_error_same_texel", "caustics_adaptive_maxerror", "converge_test=same_texel"},
                            {"adaptive_hybrid", "caustics_adaptive", ""}};
  std::string csv = "grid,method,processed,gpu_ms\n";
  const bool terminal = ::isatty(STDERR_FILENO) != 0;
  const std::string header =
      "| photon grid | regular | hierarchical | adaptive, max level | adaptive, max error | adaptive, max error with the paper's "
      "same-texel "
      "test | adaptive, hybrid "
      "|\n|---|---|---|---|---|---|---|\n";
  std::string table = header, times = header;
  for (uint32_t grid : grids) {
    std::string row = "| " + std::to_string(grid) + "^2 |", time_row = row;
    for (const auto& m : methods) {
      if (std::string(m.name) == "regular" && grid > regular_max) {
        row += " n/a |";
        time_row += " n/a |";
        continue;
      }
      graph::Executor executor(vk, shaders, passes::builtin_registry());
      executor.set_scene(scene);
      auto g = graph::load_graph_file((data_dir() / "graphs" / (std::string(m.graph) + ".json")).string());
      std::vector<std::string> sets{"grid=" + std::to_string(grid)};
      if (*m.set) sets.emplace_back(m.set);
      graph::apply_overrides(g, sets);
      executor.configure(g, 640, 360);
      executor.run_frame(false);  // pipelines compile on first use
      std::vector<double> ms;
      double processed = 0;
      for (uint32_t f = 0; f < frames; ++f) {
        auto result = executor.run_frame(false);
        for (const auto& p : result.passes) {
          if (p.name == "caustics") ms.push_back(p.gpu_ms);
        }
        processed = result.counters.count("photons.processed") ? result.counters.at("photons.processed") : 0;
      }
      char cell[128];
      std::snprintf(cell, sizeof(cell), " %.0f |", processed);
      row += cell;
      std::snprintf(cell, sizeof(cell), " %.2f ms |", median(ms));
      time_row += cell;
      std::snprintf(cell, sizeof(cell), "%u,%s,%.0f,%.4f\n", grid, m.name, processed, median(ms));
      csv += cell;
      // On a terminal each grid's line is rewritten in place; in a log every method gets its own.
      std::fprintf(stderr, "%s%u^2 %s: %.0f photons, %.2f ms%s", terminal ? "\r" : "", grid, m.name, processed, median(ms),
                   terminal ? "          " : "\n");
    }
    if (terminal) std::fprintf(stderr, "\n");
    table += row + "\n";
    times += time_row + "\n";
  }
  std::cout << "scene " << scene->name << ", device " << vk.device_name() << ", median of " << frames
            << " frames after one warm-up; GPU time of the caustic pass only\n\nphotons processed:\n\n"
            << table << "\ncaustic pass GPU time:\n\n"
            << times;
  if (!out_dir.empty()) {
    std::filesystem::create_directories(out_dir);
    io::write_text_atomically((std::filesystem::path(out_dir) / "photons.csv").string(), csv);
  }
  return 0;
}

namespace {

bool is_one_of(const std::string& type, std::initializer_list<const char*> types) {
  return std::any_of(types.begin(), types.end(), [&](const char* t) { return type == t; });
}

// The graph's passes whose GPU time a method is charged with.
std::set<std::string> passes_of_types(const graph::GraphDesc& graph, std::initializer_list<const char*> types) {
  std::set<std::string> names;
  for (const auto& p : graph.passes) {
    if (is_one_of(p.type, types)) names.insert(p.name);
  }
  return names;
}

struct Timings {
  double method_ms = 0, frame_ms = 0;
  graph::FrameResult last;
};

// One warm-up frame (pipelines compile on first use), then the median of `frames`.
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

constexpr std::initializer_list<const char*> kCausticPassTypes = {"caustic_map", "hierarchical_caustic_map", "adaptive_caustic_map"};
constexpr std::initializer_list<const char*> kRefractionPassTypes = {"refractor_buffers", "deferred_refraction", "forward_refraction",
                                                                     "refraction_layers"};

// Whether the graph runs on this device: a graph that traces with ray queries needs them. The
// benchmarks skip, and say so, what a device cannot run rather than fail the whole run.
bool runs_on(const vk::Context& vk, const graph::GraphDesc& g) {
  if (vk.ray_queries().available) return true;
  graph::CompileOptions options;
  options.scene_values = graph::typical_scene_values();
  return graph::compile_graph(g, passes::builtin_registry(), options).ray_query_passes.empty();
}

}  // namespace

// Speed against accuracy: every scene x caustic graph x effective photon grid against the photon
// reference, and every refraction graph x distance estimate against the ray-traced reference.
int cmd_bench_accuracy(Args& args) {
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
  uint32_t frames = 3, regular_max = 4096, caustic_size = 512, width = 640, height = 360;
  uint64_t reference_photons = 100'000'000;
  double blur = 1.5;
  std::string out_dir, device;
  while (!args.done()) {
    std::string a = args.take();
    if (a == "--scenes")
      scenes = parse_names(a, args.value(a));
    else if (a == "--graphs")
      graphs = parse_names(a, args.value(a));
    else if (a == "--grids")
      grids = parse_powers_of_two(a, args.value(a), 64, 65536);
    else if (a == "--frames")
      frames = static_cast<uint32_t>(parse_uint(a, args.value(a), 1, 100));
    else if (a == "--regular-max")
      regular_max = static_cast<uint32_t>(parse_uint(a, args.value(a), 64, 65536));
    else if (a == "--caustic-size")
      caustic_size = static_cast<uint32_t>(parse_uint(a, args.value(a), 16, 8192));
    else if (a == "--size")
      parse_size(args.value(a), width, height);
    else if (a == "--reference-photons")
      reference_photons = parse_uint(a, args.value(a), 1000, 100'000'000'000ull);
    else if (a == "--blur")
      blur = parse_number(a, args.value(a), 0, 64);
    else if (a == "--out")
      out_dir = args.value(a);
    else if (a == "--device")
      device = args.value(a);
    else
      unknown_option(a, {"--scenes", "--graphs", "--grids", "--frames", "--regular-max", "--caustic-size", "--size", "--reference-photons",
                         "--blur", "--out", "--device"});
  }
  if (out_dir.empty()) throw UsageError("bench accuracy needs --out DIR");
  // Everything is loaded and checked before the first long step.
  std::vector<std::shared_ptr<const scene::Scene>> loaded;
  for (const auto& name : scenes) loaded.push_back(std::make_shared<const scene::Scene>(scene::load_scene_file(scene_path(name))));
  // A graph is NAME or NAME:PARAM=VALUE[:PARAM=VALUE...], its method label the name and overrides.
  std::vector<graph::GraphDesc> graph_descs;
  std::vector<std::string> labels;
  for (const auto& entry : graphs) {
    std::vector<std::string> sets;
    for (size_t at = entry.find(':'); at != std::string::npos;) {
      const size_t next = entry.find(':', at + 1);
      sets.push_back(entry.substr(at + 1, next == std::string::npos ? std::string::npos : next - at - 1));
      at = next;
    }
    const std::string name = entry.substr(0, entry.find(':'));
    graph_descs.push_back(graph::load_graph_file(graph_path(name)));
    auto& g = graph_descs.back();
    graph::apply_overrides(g, sets);
    std::string label = g.name;
    for (const auto& set : sets) label += " " + set;
    labels.push_back(label);
    if (passes_of_types(g, kCausticPassTypes).empty() &&
        passes_of_types(g, {"deferred_refraction", "forward_refraction", "refraction_layers"}).empty()) {
      throw InputError(graph_path(name) + ": bench accuracy needs a graph with a caustic or a refraction pass");
    }
  }
  const std::filesystem::path plot_script = data_dir() / "tools" / "plot_accuracy.py";
  if (!std::filesystem::is_regular_file(plot_script)) throw InputError(plot_script.string() + ": the chart script is missing");
  // The chart is drawn last, after what can be an hour on lavapipe: a missing matplotlib is found now.
  const std::string python = chart_python();
  if (std::system((shell_word(python) + " -c 'import matplotlib' > /dev/null 2>&1").c_str()) != 0) {
    throw std::runtime_error("the chart needs matplotlib, which " + python +
                             " cannot import (Debian: python3-matplotlib; CAUSTICA_PYTHON names another interpreter)");
  }
  std::filesystem::create_directories(out_dir);
  const std::filesystem::path dir(out_dir);

  vk::Context vk(device_options(device, false));
  shader::ShaderCompiler shaders(data_dir() / "shaders");
  std::string csv = "scene,kind,method,grid,photons_processed,method_ms,frame_ms,relative_l1,energy_ratio,shape_l1,psnr,nonfinite\n";
  std::string table =
      "| scene | method | grid | photons processed | method GPU ms | frame GPU ms | relative L1 | energy ratio | shape L1 "
      "|\n|---|---|---|---|---|---|---|---|---|\n";
  const auto start = std::chrono::steady_clock::now();
  auto add_row = [&](const std::string& scene, const char* kind, const std::string& method, uint32_t grid, double processed,
                     const Timings& t, const reference::ImageComparison& c) {
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
  };

  for (size_t si = 0; si < loaded.size(); ++si) {
    const auto& scene = loaded[si];
    bool wants_caustics = false, wants_refraction = false;
    for (const auto& g : graph_descs) {
      wants_caustics = wants_caustics || !passes_of_types(g, kCausticPassTypes).empty();
      wants_refraction = wants_refraction || passes_of_types(g, kCausticPassTypes).empty();
    }
    reference::PhotonReference photons;
    if (wants_caustics) {
      reference::PhotonOptions options;
      options.photons = reference_photons;
      options.map_size = caustic_size;
      ProgressLine progress(scene->name + ": reference photons", reference_photons);
      options.progress = [&](uint64_t done, uint64_t) { progress.update(done); };
      photons = reference::trace_photon_reference(*scene, options);
      io::write_image((dir / (scene->name + "_reference_caustics.exr")).string(), photons.caustic_map);
    }
    reference::RefractionImage refraction;
    if (wants_refraction) refraction = reference::render_refraction_reference(*scene, width, height);

    for (size_t gi = 0; gi < graph_descs.size(); ++gi) {
      const auto& desc = graph_descs[gi];
      const auto caustic_passes = passes_of_types(desc, kCausticPassTypes);
      graph::Executor executor(vk, shaders, passes::builtin_registry());
      executor.set_scene(scene);
      if (!caustic_passes.empty()) {
        for (uint32_t grid : grids) {
          if (grid > regular_max && !passes_of_types(desc, {"caustic_map"}).empty()) continue;
          graph::GraphDesc g = desc;
          graph::apply_overrides(g, {"grid=" + std::to_string(grid), "caustic_size=" + std::to_string(caustic_size)});
          if (!runs_on(vk, g)) {
            std::fprintf(stderr, "%s: skipped on %s, which lacks %s (ray queries)\n", labels[gi].c_str(), vk.device_name().c_str(),
                         vk.ray_queries().missing.c_str());
            break;
          }
          executor.configure(g, width, height, {"caustics"});
          const Timings t = time_frames(executor, frames, caustic_passes);
          const double processed = t.last.counters.count("photons.processed") ? t.last.counters.at("photons.processed") : 0.0;
          add_row(scene->name, "caustics", labels[gi], grid, processed, t,
                  reference::compare_images(executor.read_image("caustics"), photons.caustic_map, blur));
        }
      } else {
        // An image-space graph runs every image-space rung; one that traces exact paths by default
        // (refraction_raytraced, refraction_hybrid) runs as it is.
        const graph::GraphParameter* distance_param = desc.find_parameter("distance");
        const std::string own = distance_param ? distance_param->value.get<std::string>() : "dv_dn";
        const bool exact = own == "ray_query" || own == "hybrid";
        if (!runs_on(vk, desc)) {
          std::fprintf(stderr, "%s: skipped on %s, which lacks %s (ray queries)\n", labels[gi].c_str(), vk.device_name().c_str(),
                       vk.ray_queries().missing.c_str());
          continue;
        }
        for (const std::string& distance : exact ? std::vector<std::string>{own} : std::vector<std::string>{"dv", "dv_dn", "search"}) {
          graph::GraphDesc g = desc;
          graph::apply_overrides(g, {"distance=" + distance});
          executor.configure(g, width, height, {"refracted"});
          const Timings t = time_frames(executor, frames, passes_of_types(desc, kRefractionPassTypes));
          reference::ImageComparison c;
          c.relative_l1 = reference::refraction_relative_l1(executor.read_image("refracted"), refraction);
          c.energy_ratio = c.shape_l1 = c.psnr = std::nan("");
          add_row(scene->name, "refraction", labels[gi] + " " + distance, 0, 0.0, t, c);
        }
      }
    }
  }

  io::write_text_atomically((dir / "results.csv").string(), csv);
  char config[1024];
  std::snprintf(config, sizeof(config),
                "Device %s. Frames %ux%u; median GPU time of %u frames after one warm-up. Caustic maps %u^2, compared with %llu "
                "reference photons (caustica reference --photons, Fresnel on) after a Gaussian blur of sigma %.3g texels; "
                "refraction compared with the ray-traced reference over the refractor's pixels (no blur).",
                vk.device_name().c_str(), width, height, frames, caustic_size, static_cast<unsigned long long>(reference_photons), blur);
  io::write_text_atomically((dir / "README.md").string(),
                            "# caustica bench accuracy\n\n" + std::string(config) +
                                "\n\nColumns as in results.csv: `method GPU ms` is the caustic pass (photon work only; the light-space "
                                "inputs are the same for every method) or, for refraction, refractor_buffers plus the refraction pass. "
                                "`relative L1` and `energy ratio` are defined in docs/accuracy.md. The chart is speed_accuracy.png.\n\n" +
                                table);
  const std::filesystem::path partial = dir / ".speed_accuracy.partial.png";
  const std::string command = shell_word(python) + " " + shell_word(plot_script.string()) + " " +
                              shell_word((dir / "results.csv").string()) + " " + shell_word(partial.string());
  if (std::system(command.c_str()) != 0) {
    std::filesystem::remove(partial);
    throw std::runtime_error("drawing the chart failed: " + command + " (Debian: python3-matplotlib)");
  }
  std::filesystem::rename(partial, dir / "speed_accuracy.png");
  std::cout << config << "\n\n" << table;
  std::fprintf(stderr, "bench accuracy: %s/results.csv, README.md, speed_accuracy.png\n", out_dir.c_str());
  return 0;
}

namespace {

struct StabilityCase {
  const char* label;
  const char* scene;          // its last path component names the case for --cases
  bool moving_light = false;  // also measure flicker along a light path
  std::string name() const { return std::filesystem::path(scene).filename().string(); }
};

const StabilityCase kStabilityCases[] = {
    {"ball lens", "sphere_plane"},
    {"bunny with the light moving", "bunny_plane", true},
    {"high index (n = 2.4)", "stability/high_index"},
    {"grazing light", "stability/grazing_light"},
    {"torus (four interfaces)", "torus"},
    {"stacked refractors", "three_refractors"},
    {"tiny refractor", "stability/tiny_refractor"},
    {"refractor filling the view", "stability/filling_refractor"},
    {"light close to the refractor", "stability/close_light"},
    {"n = 1", "stability/index_one"},
    {"no refractor", "no_refractor"},
};

std::shared_ptr<const scene::Scene> with_light_moved(const scene::Scene& scene, glm::vec3 offset) {
  auto moved = std::make_shared<scene::Scene>(scene);
  moved->lights.front().view.position += offset;
  return moved;
}

}  // namespace

// Where each caustic method breaks: every case of kStabilityCases x every method, against the
// photon reference; docs/stability.md reports a run.
int cmd_bench_stability(Args& args) {
  uint32_t grid = 2048, caustic_size = 512, frames = 3, width = 320, height = 180;
  uint64_t reference_photons = 20'000'000;
  double blur = 1.5;
  bool validate = false;
  std::string out_dir, device;
  std::vector<StabilityCase> cases(std::begin(kStabilityCases), std::end(kStabilityCases));
  while (!args.done()) {
    std::string a = args.take();
    if (a == "--cases") {
      std::vector<std::string> known;
      for (const auto& c : kStabilityCases) known.push_back(c.name());
      cases.clear();
      for (const auto& name : parse_names(a, args.value(a))) {
        const auto found = std::find(known.begin(), known.end(), name);
        if (found == known.end()) throw UsageError("--cases: no case '" + name + "'" + did_you_mean(name, known) + "; see --help");
        cases.push_back(kStabilityCases[found - known.begin()]);
      }
    } else if (a == "--grid")
      grid = parse_powers_of_two(a, args.value(a), 64, 65536).front();
    else if (a == "--caustic-size")
      caustic_size = static_cast<uint32_t>(parse_uint(a, args.value(a), 16, 8192));
    else if (a == "--frames")
      frames = static_cast<uint32_t>(parse_uint(a, args.value(a), 1, 100));
    else if (a == "--reference-photons")
      reference_photons = parse_uint(a, args.value(a), 1000, 100'000'000'000ull);
    else if (a == "--out")
      out_dir = args.value(a);
    else if (a == "--device")
      device = args.value(a);
    else if (a == "--validate")
      validate = true;
    else
      unknown_option(a, {"--cases", "--grid", "--caustic-size", "--frames", "--reference-photons", "--out", "--device", "--validate"});
  }
  struct Method {
    const char* label;
    const char* graph;
    const char* extra;  // a --set beyond grid and caustic_size, or null
  };
  const Method methods[] = {{"regular", "caustics_regular", nullptr},
                            {"hierarchical", "caustics_hierarchical", nullptr},
                            {"adaptive max-level", "caustics_adaptive_maxlevel", nullptr},
                            {"adaptive max-error", "caustics_adaptive_maxerror", nullptr},
                            {"adaptive hybrid", "caustics_adaptive", nullptr},
                            {"adaptive hybrid unseeded (the paper)", "caustics_adaptive", "coverage_seeding=false"},
                            {"adaptive hybrid with search", "caustics_adaptive_hybrid", "distance=search"},
                            {"adaptive hybrid with exact re-trace", "caustics_adaptive_hybrid", nullptr},
                            {"ray query", "caustics_raytraced", nullptr}};
  if (!out_dir.empty()) std::filesystem::create_directories(out_dir);
  vk::Context vk(device_options(device, validate));
  shader::ShaderCompiler shaders(data_dir() / "shaders");
  std::string csv =
      "case,method,relative_l1,energy_ratio,shape_l1,nonfinite,photons_processed,caustic_ms,shift_l1,shift_energy,flicker,reference_"
      "flicker,reference_landed_photons,reference_shift_l1\n";
  std::string table =
      "| case | method | relative L1 | energy ratio | shape L1 | NaN/Inf | photons | caustic ms | 1e-4 shift: L1 (reference) | flicker "
      "(reference) |\n"
      "|---|---|---|---|---|---|---|---|---|---|\n";
  const glm::vec3 shift(1e-4f, 0.0f, 0.0f);
  constexpr int kPathSteps = 6;
  const glm::vec3 step(0.02f, 0.0f, 0.0f);
  for (const auto& c : cases) {
    const auto scene = std::make_shared<const scene::Scene>(scene::load_scene_file(scene_path(c.scene)));
    reference::PhotonOptions options;
    options.photons = reference_photons;
    options.map_size = caustic_size;
    auto reference_map = [&](const scene::Scene& s) { return reference::trace_photon_reference(s, options).caustic_map; };
    const auto traced = reference::trace_photon_reference(*scene, options);
    const io::ImageData& reference = traced.caustic_map;
    // The exact answer's own sensitivity to the tiny move, sampled like the reference: where paths
    // bounce many times (n = 2.4) it is large, and a method that follows them can be no calmer.
    const double reference_shift = reference::compare_images(reference_map(*with_light_moved(*scene, shift)), reference, blur).relative_l1;
    std::vector<io::ImageData> reference_path;
    double reference_flicker = 0;
    if (c.moving_light) {
      for (int i = 0; i < kPathSteps; ++i) reference_path.push_back(reference_map(*with_light_moved(*scene, step * float(i))));
      for (int i = 1; i < kPathSteps; ++i)
        reference_flicker += reference::compare_images(reference_path[i], reference_path[i - 1], blur).relative_l1 / (kPathSteps - 1);
    }
    for (const auto& m : methods) {
      graph::GraphDesc g = graph::load_graph_file(graph_path(m.graph));
      std::vector<std::string> sets{"grid=" + std::to_string(grid), "caustic_size=" + std::to_string(caustic_size)};
      if (m.extra) sets.emplace_back(m.extra);
      graph::apply_overrides(g, sets);
      if (!runs_on(vk, g)) {
        std::fprintf(stderr, "%s: skipped on %s, which lacks %s (ray queries)\n", m.label, vk.device_name().c_str(),
                     vk.ray_queries().missing.c_str());
        continue;
      }
      graph::Executor executor(vk, shaders, passes::builtin_registry());
      auto prepare = [&](std::shared_ptr<const scene::Scene> s) {
        executor.set_scene(std::move(s));
        executor.configure(g, width, height, {"caustics"});
      };
      auto render = [&](std::shared_ptr<const scene::Scene> s) {
        prepare(std::move(s));
        return time_frames(executor, frames, passes_of_types(g, kCausticPassTypes));
      };
      // The moved lights' maps are compared, not timed: one frame each, without the warm-up.
      auto render_untimed = [&](std::shared_ptr<const scene::Scene> s) {
        prepare(std::move(s));
        executor.run_frame(true);
      };
      // Without a refractor the caustic pass is culled ("enabled": "scene.refractors") and its map
      // never exists: an empty map, which is the right answer.
      auto caustic_map = [&] {
        const int index = executor.plan().find_resource("caustics");
        if (index >= 0 && executor.plan().resources[static_cast<size_t>(index)].used()) return executor.read_image("caustics");
        io::ImageData empty;
        empty.width = empty.height = caustic_size;
        empty.rgba.assign(size_t{caustic_size} * caustic_size * 4, 0.0f);
        return empty;
      };
      const Timings t = render(scene);
      const io::ImageData map = caustic_map();
      const io::ImageData frame = executor.read_image(executor.plan().resources[executor.plan().outputs.front()].name);
      uint64_t nonfinite = 0;
      for (const auto* image : {&map, &frame}) {
        for (float v : image->rgba) nonfinite += std::isfinite(v) ? 0 : 1;
      }
      for (const auto& [name, value] : t.last.counters) nonfinite += std::isfinite(value) ? 0 : 1;
      const auto accuracy = reference::compare_images(map, reference, blur);
      render_untimed(with_light_moved(*scene, shift));
      const auto shifted = reference::compare_images(caustic_map(), map, blur);
      double flicker = 0;
      if (c.moving_light) {
        io::ImageData previous = map;
        for (int i = 1; i < kPathSteps; ++i) {
          render_untimed(with_light_moved(*scene, step * float(i)));
          io::ImageData current = caustic_map();
          flicker += reference::compare_images(current, previous, blur).relative_l1 / (kPathSteps - 1);
          previous = std::move(current);
        }
      }
      const double processed = t.last.counters.count("photons.processed") ? t.last.counters.at("photons.processed") : 0.0;
      char line[768];
      std::snprintf(line, sizeof(line), "%s,%s,%.6f,%.6f,%.6f,%llu,%.0f,%.4f,%.6f,%.6f,%.6f,%.6f,%llu,%.6f\n", c.label, m.label,
                    accuracy.relative_l1, accuracy.energy_ratio, accuracy.shape_l1, static_cast<unsigned long long>(nonfinite), processed,
                    t.method_ms, shifted.relative_l1, shifted.energy_ratio, flicker, reference_flicker,
                    static_cast<unsigned long long>(traced.totals.landed_photons), reference_shift);
      csv += line;
      char flicker_cell[64] = "-";
      if (c.moving_light) std::snprintf(flicker_cell, sizeof(flicker_cell), "%.4f (%.4f)", flicker, reference_flicker);
      std::snprintf(line, sizeof(line), "| %s | %s | %.4f | %.4f | %.4f | %llu | %.0f | %.2f | %.5f (%.5f) | %s |\n", c.label, m.label,
                    accuracy.relative_l1, accuracy.energy_ratio, accuracy.shape_l1, static_cast<unsigned long long>(nonfinite), processed,
                    t.method_ms, shifted.relative_l1, reference_shift, flicker_cell);
      table += line;
      std::fprintf(stderr, "%s, %s: relative L1 %.4f, energy %.4f, %llu NaN/Inf\n", c.label, m.label, accuracy.relative_l1,
                   accuracy.energy_ratio, static_cast<unsigned long long>(nonfinite));
    }
  }
  char config[512];
  std::snprintf(
      config, sizeof(config),
      "Device %s; photon grid %u^2, caustic map %u^2, frames %ux%u, median of %u frames after one warm-up; reference %llu photons "
      "(Fresnel on); metrics after a Gaussian blur of sigma %.3g texels (docs/accuracy.md). Light path: %d positions 0.02 apart.",
      vk.device_name().c_str(), grid, caustic_size, width, height, frames, static_cast<unsigned long long>(reference_photons), blur,
      kPathSteps);
  std::cout << config << "\n\n" << table;
  if (!out_dir.empty()) {
    const std::filesystem::path dir(out_dir);
    io::write_text_atomically((dir / "stability.csv").string(), csv);
    io::write_text_atomically((dir / "README.md").string(), "# caustica bench stability\n\n" + std::string(config) + "\n\n" + table);
  }
  if (vk.validation_messages() > 0) {
    std::fprintf(stderr, "caustica: %u validation messages (see above)\n", vk.validation_messages());
    return 3;
  }
  return 0;
}

int cmd_bench(Args& args) {
  const char* help =
      "usage: caustica bench refraction [--scene FILE]... [--sphere-detail N]... [--size WxH] [--frames N] [--csv FILE]\n"
      "       caustica bench photons [--scene FILE] [--grids 256,512,...] [--frames N] [--regular-max G] [--out DIR]\n"
      "       caustica bench stability [--grid G] [--out DIR] ...\n"
      "       caustica bench load --scene FILE [--runs N]\n"
      "       caustica bench accuracy --out DIR [--scenes A,B] [--graphs G,H,...] [--grids 256,512,...] [--frames N]\n"
      "                               [--regular-max G] [--caustic-size N] [--size WxH] [--reference-photons N] [--blur SIGMA]\n\n"
      "accuracy: speed against accuracy. For every scene (bundled names or files; default sphere_plane,bunny_plane) x\n"
      "caustic graph x effective photon grid (default 256..4096; the regular map only up to --regular-max, 4096): the\n"
      "median GPU time of the caustic pass and of the frame, and the error of the caustic map against the photon\n"
      "reference (--reference-photons, default 1e8) after a matched blur; and for every refraction graph x distance\n"
      "(dv, dv_dn, search; a graph that traces exact paths by default, with its own): the refraction passes' time and\n"
      "error against the ray-traced reference. Writes DIR/results.csv, DIR/speed_accuracy.png (error against time,\n"
      "log-log, python3-matplotlib), DIR/README.md and each scene's reference map. Default graphs: the five caustic\n"
      "graphs, the max-error one also with converge_test=same_texel (the paper's test), the default one also with\n"
      "distance=dv_dn (the paper's estimate), the adaptive hybrid with distance=search and as\n"
      "it is, caustics_raytraced, refraction_forward, refraction_deferred, refraction_raytraced, refraction_hybrid (graphs\n"
      "that need ray queries are skipped, with a note, on a device without them). A graph is NAME or\n"
      "NAME:PARAM=VALUE[:PARAM=VALUE...]. The chart is drawn with matplotlib by /usr/bin/python3 (python3 on PATH where\n"
      "there is none), or by the interpreter that CAUSTICA_PYTHON names; one that cannot import matplotlib stops the\n"
      "benchmark before it starts.\n\n"
      "       caustica bench stability [--cases A,B] [--grid G] [--caustic-size N] [--frames N] [--reference-photons N] [--out DIR]\n"
      "                                [--validate]\n\n"
      "stability: where each caustic method breaks. Every case (ball lens; bunny with the light moving; n = 2.4; grazing\n"
      "light; torus; stacked refractors; a refractor smaller than the start grid's spacing; one filling the light's view;\n"
      "the light close to it; n = 1; no refractor) x every method (the hybrid also without coverage seeding, and the\n"
      "exact-path ladder: the adaptive hybrid graph with the search and with exact re-traces, and the ray-query tracer,\n"
      "skipped on a device without ray queries) at one grid\n"
      "(default 2048): error, energy ratio and shape error against the photon reference (default 2e7), NaN/Inf count,\n"
      "photons, caustic-pass time, the change after moving the light by 1e-4 (and the reference's own change), and the\n"
      "flicker along a light path against the reference's own. DIR/stability.csv and DIR/README.md. --cases runs some of\n"
      "the cases, named by their scenes: sphere_plane, bunny_plane, high_index, grazing_light, torus, three_refractors,\n"
      "tiny_refractor, filling_refractor, close_light, index_one, no_refractor.\n\n"
      "photons: the paper's table on a scene (default the bunny): photons processed by the regular, hierarchical and\n"
      "adaptive (max level, max error, hybrid) caustic maps for each effective grid, and the caustic pass's GPU time;\n"
      "DIR/photons.csv has columns grid, method, processed, gpu_ms. --regular-max skips the regular map above a grid.\n\n"
      "refraction: deferred against forward refraction on the same scenes (default: the bundled ball lens and bunny),\n"
      "one run, frames interleaved, after two warm-up frames: median GPU time of the refraction passes\n"
      "(refractor_buffers + the refraction pass) and of the whole frame. --sphere-detail renders the ball-lens scene\n"
      "with its sphere tessellated into N slices (triangle count alone varies).\n\n"
      "load: loading a scene or model file, median over --runs (default 5): the host's part (parsing, decoding the\n"
      "textures its materials use, normals, d_N) and the device's (buffers, textures with their mip chains), and how\n"
      "many of the file's images were decoded. tools/make_load_asset.py writes a textured 100k-triangle test model.\n";
  if (args.wants_help()) {
    std::cout << help;
    return 0;
  }
  if (args.done())
    throw UsageError("bench needs a benchmark name: refraction, photons, accuracy, stability or load; see caustica bench --help");
  std::string what = args.take();
  if (what == "refraction") return cmd_bench_refraction(args);
  if (what == "photons") return cmd_bench_photons(args);
  if (what == "accuracy") return cmd_bench_accuracy(args);
  if (what == "stability") return cmd_bench_stability(args);
  if (what == "load") return cmd_bench_load(args);
  throw UsageError("bench " + what + ": unknown benchmark" +
                   did_you_mean(what, {"refraction", "photons", "accuracy", "stability", "load"}));
}

}  // namespace caustica::cli
