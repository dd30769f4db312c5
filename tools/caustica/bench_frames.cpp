// caustica bench load, refraction and photons: loading a scene, deferred against forward refraction,
// and the paper's table of photons processed per method.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>

#include <unistd.h>

#include "bench_common.h"
#include "builtin_passes.h"
#include "core/paths.h"
#include "flags.h"
#include "io/image_io.h"
#include "scene/gpu_scene.h"
#include "scene/scene.h"

namespace caustica::cli::bench {

namespace {

struct LoadOptions {
  std::string file, device;
  uint32_t runs = 5;
};

FlagTable load_flags(LoadOptions& o) {
  return {text_flag("--scene", "FILE", "the scene or model file to load (required)", o.file),
          uint32_flag("--runs", "N", "loads to take the median of (default 5)", o.runs, 1, 100), device_flag(o.device), tracer_flag()};
}

struct RefractionOptions {
  std::vector<std::string> scenes;
  uint32_t width = 1280, height = 720, frames = 7;
  std::vector<uint32_t> sphere_details;
  std::string device, csv;
};

FlagTable refraction_flags(RefractionOptions& o) {
  return {
      {"--scene", "FILE", "a scene to measure (repeatable; default the bundled ball lens and bunny)",
       [&o](const std::string& v) { o.scenes.push_back(v); }, true},
      {"--sphere-detail", "N", "the ball-lens scene with its sphere in N slices (repeatable)",
       [&o](const std::string& v) { o.sphere_details.push_back(static_cast<uint32_t>(parse_uint("--sphere-detail", v, 3, 1024))); }, true},
      size_flag(o.width, o.height, "the frame size (default 1280x720)"),
      frames_flag(o.frames, 1000, "frames timed of each (default 7)"),
      device_flag(o.device),
      tracer_flag(),
      text_flag("--csv", "FILE", "also write the table as CSV", o.csv)};
}

struct CompareOptions {
  std::vector<std::string> names;
  std::string scene_file = scene_path("sphere_plane"), device, csv;
  uint32_t width = 1280, height = 720, frames = 15;
  std::vector<std::string> sets;
  bool moving = false;
};

FlagTable compare_flags(CompareOptions& o) {
  return {names_flag("--graphs", "A,B[,...]",
                     "the graphs (names or files), the first the one the others are compared with;\n"
                     "NAME@ray_query or NAME@compute traces with that tracer (one graph, both tracers)",
                     o.names),
          {"--scene", "FILE", "the scene (default sphere_plane)", [&o](const std::string& v) { o.scene_file = scene_path(v); }},
          size_flag(o.width, o.height, "the frame size (default 1280x720)"),
          frames_flag(o.frames, 1000, "frames timed of each (default 15)"),
          set_flag(o.sets, "a graph parameter, in every graph (repeatable)"),
          moving_flag(o.moving),
          device_flag(o.device),
          tracer_flag(),
          text_flag("--csv", "FILE", "also write the table as CSV", o.csv)};
}

struct PhotonsOptions {
  std::string scene_file = (data_dir() / kBenchScene).string(), out_dir, device;
  std::vector<uint32_t> grids{256, 512, 1024, 2048, 4096, 8192, 16384};
  uint32_t frames = 3, regular_max = 16384;
};

FlagTable photons_flags(PhotonsOptions& o) {
  return {text_flag("--scene", "FILE", "the scene (default bunny_plane)", o.scene_file),
          powers_flag("--grids", "256,512,...", "effective photon grids (default 256..16384)", o.grids, 64, 65536),
          frames_flag(o.frames, 100, "frames timed of each (default 3)"),
          uint32_flag("--regular-max", "G", "the regular map only up to this grid (default 16384)", o.regular_max, 64, 65536),
          text_flag("--out", "DIR", "also write DIR/photons.csv", o.out_dir),
          device_flag(o.device),
          tracer_flag()};
}

}  // namespace

// Loading a model or scene: the host's part (parsing, decoding the textures materials use, normals,
// d_N) and the device's (buffers, texture upload with their mip chains), median over runs.
int cmd_bench_load(Args& args) {
  LoadOptions o;
  load_flags(o).parse(args);
  const auto& [file, device, runs] = o;
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
  RefractionOptions options;
  refraction_flags(options).parse(args);
  const auto& [scenes, width, height, frames, sphere_details, device, csv] = options;
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
  shader::ShaderCompiler& shaders = shader::process_shader_compiler();
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
    const std::set<std::string> refraction_passes{"refractors", "refraction"};
    const std::vector<Timings> t =
        time_interleaved({executors[0].get(), executors[1].get()}, frames, 2, {refraction_passes, refraction_passes}, c.label + ": frames");
    size_t triangles = 0;
    for (const auto& o : c.scene->objects) triangles += o.material.refractor ? o.mesh.indices.size() / 3 : 0;
    const double fw = t[0].method_ms, df = t[1].method_ms;
    char row[512];
    std::snprintf(row, sizeof(row), "| %s | %zu | %.2f ms | %.2f ms | %.2f | %.2f ms | %.2f ms |\n", c.label.c_str(), triangles, fw, df,
                  df / fw, t[0].frame_ms, t[1].frame_ms);
    table += row;
    std::snprintf(row, sizeof(row), "%s,%zu,%.4f,%.4f,%.4f,%.4f\n", c.label.c_str(), triangles, fw, df, t[0].frame_ms, t[1].frame_ms);
    rows_csv += row;
  }
  std::cout << "device: " << vk.device_name() << ", " << width << "x" << height << ", median of " << frames << " frames after 2 warm-up\n\n"
            << table;
  if (!csv.empty()) io::write_text_atomically(csv, rows_csv);
  return 0;
}

// Caustic methods side by side in one process, frames interleaved (as bench refraction): the
// median GPU time of each graph's caustic passes (built-in or user passes writing "caustics") and
// of its frame, and each as a ratio to the first graph's. For a user pass against the built-in it
// replaces (docs/shader_passes.md), where separate processes differ by more than the passes do.
int cmd_bench_compare(Args& args) {
  CompareOptions o;
  compare_flags(o).parse(args);
  const auto& [names, scene_file, device, csv, width, height, frames, sets, moving] = o;
  if (names.size() < 2)
    throw UsageError("bench compare needs --graphs A,B[,...]: two graphs or more, the first the one the others are compared with");
  if (!csv.empty()) io::check_output_file(csv);
  std::vector<graph::GraphDesc> graphs, declared;
  std::vector<std::vector<std::string>> still;  // each graph's values at rest, unless --moving
  std::vector<std::set<std::string>> method_passes;
  std::vector<std::optional<graph::Tracer>> tracers;
  for (const auto& named : names) {
    const size_t at = named.rfind('@');
    const std::string name = named.substr(0, at);
    tracers.push_back(std::nullopt);
    if (at != std::string::npos && !(tracers.back() = graph::parse_tracer(named.substr(at + 1))))
      throw UsageError("--graphs " + named + ": after @ comes the tracer, ray_query or compute");
    declared.push_back(graph::load_graph_file(graph_path(name)));
    graph::apply_overrides(declared.back(), sets);
    graphs.push_back(declared.back());
    still.push_back(moving ? std::vector<std::string>{} : apply_at_rest(graphs.back(), sets));
    method_passes.push_back(caustic_passes(graphs.back()));
    if (method_passes.back().empty()) {
      throw InputError(graph_path(name) + ": bench compare times caustic methods, and this graph has no caustic pass (one of type " +
                       "caustic_map, hierarchical_caustic_map or adaptive_caustic_map, or a user pass that writes the image 'caustics')");
    }
  }
  auto scene = std::make_shared<const scene::Scene>(scene::load_scene_file(scene_file));
  vk::Context vk(device_options(device, false));
  shader::ShaderCompiler& shaders = shader::process_shader_compiler();
  std::vector<std::unique_ptr<graph::Executor>> owned;
  std::vector<graph::Executor*> executors;
  for (size_t g = 0; g < graphs.size(); ++g) {
    owned.push_back(std::make_unique<graph::Executor>(vk, shaders, passes::builtin_registry()));
    owned.back()->set_scene(scene);
    configure_at_rest(
        graph_path(names[g].substr(0, names[g].rfind('@'))), graphs[g], declared[g], still[g],
        [&, w = width, h = height](const graph::GraphDesc& desc) { owned.back()->configure(desc, w, h, {.tracer = tracers[g]}); });
    executors.push_back(owned.back().get());
  }
  const std::vector<Timings> t = time_interleaved(executors, frames, 2, method_passes, scene->name + ": frames");
  std::printf("device: %s, %ux%u, scene %s, median GPU time of %u frames of each graph after 2 warm-up, frames interleaved\n\n",
              vk.device_name().c_str(), width, height, scene->name.c_str(), frames);
  std::printf("| graph | caustic passes | caustic time | frame | caustic / first's | frame / first's |\n|---|---|---|---|---|---|\n");
  std::string rows_csv = "graph,caustic_ms,frame_ms,caustic_ratio,frame_ratio\n";
  for (size_t g = 0; g < graphs.size(); ++g) {
    std::string passes;
    for (const auto& p : method_passes[g]) passes += (passes.empty() ? "" : ", ") + p;
    const double caustic_ratio = t[g].method_ms / t[0].method_ms, frame_ratio = t[g].frame_ms / t[0].frame_ms;
    std::printf("| %s | %s | %.2f ms | %.2f ms | %.3f | %.3f |\n", names[g].c_str(), passes.c_str(), t[g].method_ms, t[g].frame_ms,
                caustic_ratio, frame_ratio);
    char row[1024];
    std::snprintf(row, sizeof(row), "%s,%.4f,%.4f,%.4f,%.4f\n", names[g].c_str(), t[g].method_ms, t[g].frame_ms, caustic_ratio,
                  frame_ratio);
    rows_csv += row;
  }
  if (!csv.empty()) io::write_text_atomically(csv, rows_csv);
  return 0;
}

// The paper's table: photons processed per method and effective grid on one scene, with the GPU
// time of the caustic pass, one run.
int cmd_bench_photons(Args& args) {
  PhotonsOptions o;
  photons_flags(o).parse(args);
  const auto& [scene_file, out_dir, device, grids, frames, regular_max] = o;
  auto scene = std::make_shared<const scene::Scene>(scene::load_scene_file(scene_file));
  vk::Context vk(device_options(device, false));
  shader::ShaderCompiler& shaders = shader::process_shader_compiler();
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
        ms.push_back(passes_ms(result, {"caustics"}));  // every light's instance of the pass
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

std::string frames_flags_help(const std::string& benchmark) {
  if (benchmark == "load") {
    LoadOptions o;
    return load_flags(o).help();
  }
  if (benchmark == "refraction") {
    RefractionOptions o;
    return refraction_flags(o).help();
  }
  if (benchmark == "compare") {
    CompareOptions o;
    return compare_flags(o).help();
  }
  PhotonsOptions o;
  return photons_flags(o).help();
}

}  // namespace caustica::cli::bench
