// caustica bench stability: where each caustic method breaks (docs/stability.md).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <set>

#include "bench_common.h"
#include "builtin_passes.h"
#include "core/paths.h"
#include "core/suggest.h"
#include "graph/per_light.h"
#include "io/image_io.h"
#include "reference/image_metrics.h"
#include "reference/photon_reference.h"
#include "scene/scene.h"

namespace caustica::cli::bench {

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
    {"point light close to the refractor", "stability/close_point_light"},
    {"light inside a glass shade", "glass_lamp"},
    {"caustics overlapping", "overlapping_caustics"},
    {"thin film at grazing light", "stability/grazing_film"},
    {"clear coat over a rough base", "stability/coat_over_rough"},
    {"n = 1", "stability/index_one"},
    {"no refractor", "no_refractor"},
};

std::shared_ptr<const scene::Scene> with_light_moved(const scene::Scene& scene, glm::vec3 offset) {
  auto moved = std::make_shared<scene::Scene>(scene);
  // Its caustic view moves with it, as the engine's does: the photon reference projects its photons
  // through that view, and one left behind measured the moved light's map in the unmoved light's frame.
  scene::move_light(*moved, 0, offset);
  return moved;
}

struct StabilityOptions {
  uint32_t grid = 2048, caustic_size = 512, frames = 3, width = 320, height = 180;
  uint64_t reference_photons = 20'000'000;
  double blur = 1.5;
  bool validate = false;
  std::string out_dir, device;
  std::vector<StabilityCase> cases{std::begin(kStabilityCases), std::end(kStabilityCases)};
  CellOptions cells;
};

FlagTable stability_flags(StabilityOptions& o) {
  FlagTable table{
      {"--cases", "A,B", "some of the cases, by their scenes' names (default every one)",
       [&o](const std::string& v) {
         std::vector<std::string> known;
         for (const auto& c : kStabilityCases) known.push_back(c.name());
         o.cases.clear();
         for (const auto& name : parse_names("--cases", v)) {
           const auto found = std::find(known.begin(), known.end(), name);
           if (found == known.end()) throw UsageError("--cases: no case '" + name + "'" + did_you_mean(name, known) + "; see --help");
           o.cases.push_back(kStabilityCases[found - known.begin()]);
         }
       }},
      {"--grid", "G", "the effective photon grid, a power of two (default 2048)",
       [&o](const std::string& v) { o.grid = parse_powers_of_two("--grid", v, 64, 65536).front(); }},
      uint32_flag("--caustic-size", "N", "the caustic map's side (default 512)", o.caustic_size, 16, 8192),
      uint32_flag("--frames", "N", "frames timed of each method (default 3; 0: one untimed frame)", o.frames, 0, 100),
      uint_flag("--reference-photons", "N", "photons of the reference (default 2e7)", o.reference_photons, 1000, 100'000'000'000ull),
      text_flag("--out", "DIR", "the folder of stability.csv and README.md", o.out_dir),
      device_flag(o.device),
      tracer_flag(),
      validate_flag(o.validate)};
  o.cells.add_flags(table);
  return table;
}

StabilityOptions parse_stability_options(Args& args) {
  StabilityOptions o;
  stability_flags(o).parse(args);
  if (!o.cells.cell.empty() && o.out_dir.empty()) throw UsageError("bench stability --cell needs --out DIR");
  return o;
}

struct Method {
  const char* label;
  const char* graph;
  const char* extra;  // a --set beyond grid and caustic_size, or null
};
const Method kStabilityMethods[] = {{"regular", "caustics_regular", nullptr},
                                    {"hierarchical", "caustics_hierarchical", nullptr},
                                    {"adaptive max-level", "caustics_adaptive_maxlevel", nullptr},
                                    {"adaptive max-error", "caustics_adaptive_maxerror", nullptr},
                                    {"adaptive hybrid", "caustics_adaptive", nullptr},
                                    {"adaptive hybrid unseeded (the paper)", "caustics_adaptive", "coverage_seeding=false"},
                                    {"adaptive hybrid with search", "caustics_adaptive_hybrid", "distance=search"},
                                    {"adaptive hybrid with exact re-trace", "caustics_adaptive_hybrid", nullptr},
                                    {"ray query", "caustics_raytraced", nullptr}};

const glm::vec3 kShift(1e-4f, 0.0f, 0.0f);  // the tiny light move
constexpr int kPathSteps = 6;               // the moving light's positions, kStep apart
const glm::vec3 kStep(0.02f, 0.0f, 0.0f);

io::ImageData empty_map(uint32_t side) {
  io::ImageData empty;
  empty.width = empty.height = side;
  empty.rgba.assign(size_t{side} * side * 4, 0.0f);
  return empty;
}

// Every caustic view's map (scene::caustic_views: a light's, or a point light's cube faces) one
// above another, a gap of empty rows between, so that one comparison weighs every view's light
// and a blur does not carry one view's into another's. One view: its map as it is.
io::ImageData stacked(const std::vector<io::ImageData>& maps) {
  constexpr uint32_t kGap = 8;
  if (maps.size() == 1) return maps.front();
  io::ImageData out;
  out.width = maps.front().width;
  out.height = static_cast<uint32_t>(maps.size()) * (maps.front().height + kGap) - kGap;
  out.rgba.assign(size_t{out.width} * out.height * 4, 0.0f);
  for (size_t k = 0; k < maps.size(); ++k)
    std::copy(maps[k].rgba.begin(), maps[k].rgba.end(),
              out.rgba.begin() + static_cast<std::ptrdiff_t>(k * (maps[k].height + kGap) * out.width * 4));
  return out;
}

uint32_t caustic_view_count(const scene::Scene& scene) {
  return static_cast<uint32_t>(std::max<size_t>(1, scene::caustic_views(scene.lights).size()));
}

// A case's exact answer: every caustic view's map (stacked), each traced with its share of the
// photons, its sensitivity to the tiny move and, for a moving light, the mean change between
// neighbouring positions of its path.
struct CaseReference {
  io::ImageData map;
  uint64_t landed_photons = 0;
  double shift = 0, flicker = 0;
};

io::ImageData reference_maps(const scene::Scene& scene, const StabilityOptions& o, uint64_t* landed = nullptr) {
  const std::vector<uint64_t> shares = reference::photons_per_view(scene, o.reference_photons);
  std::vector<io::ImageData> maps;
  for (uint32_t k = 0; k < caustic_view_count(scene); ++k) {
    reference::PhotonOptions options;
    options.light = k;
    options.photons = k < shares.size() ? shares[k] : o.reference_photons;
    options.map_size = o.caustic_size;
    if (options.photons == 0) {
      maps.push_back(empty_map(o.caustic_size));
      continue;
    }
    reference::PhotonReference traced = photon_reference(scene, options, o.cells.reference_cache);
    if (landed) *landed += traced.totals.landed_photons;
    maps.push_back(std::move(traced.caustic_map));
  }
  return stacked(maps);
}

CaseReference trace_case_reference(const StabilityCase& c, const scene::Scene& scene, const StabilityOptions& o) {
  CaseReference r;
  r.map = reference_maps(scene, o, &r.landed_photons);
  // The exact answer's own sensitivity to the tiny move, sampled like the reference: where paths
  // bounce many times (n = 2.4) it is large, and a method that follows them can be no calmer.
  r.shift = reference::compare_images(reference_maps(*with_light_moved(scene, kShift), o), r.map, o.blur).relative_l1;
  if (c.moving_light) {
    std::vector<io::ImageData> path{r.map};  // the path's first position is the light's own
    for (int i = 1; i < kPathSteps; ++i) path.push_back(reference_maps(*with_light_moved(scene, kStep * float(i)), o));
    for (int i = 1; i < kPathSteps; ++i)
      r.flicker += reference::compare_images(path[i], path[i - 1], o.blur).relative_l1 / (kPathSteps - 1);
  }
  return r;
}

// One method on one case: its map against the reference, its change under the tiny move and
// along the moving light's path.
struct MethodResult {
  Timings timings;
  reference::ImageComparison accuracy, shifted;
  uint64_t nonfinite = 0;
  double flicker = 0, processed = 0;
};

MethodResult measure_method(graph::Executor& executor, const graph::GraphDesc& g, const StabilityCase& c,
                            const std::shared_ptr<const scene::Scene>& scene, const io::ImageData& reference, const StabilityOptions& o) {
  // The case's geometry is on the device already (cmd_bench_stability): only the light moves
  // between renders, so the geometry and its acceleration structures stay (set_view). Uploading
  // the bunny again for each method and each of its path's positions was most of this bench's time
  // under the sanitizers.
  const uint32_t views = caustic_view_count(*scene);
  std::set<std::string> retained;
  for (uint32_t k = 0; k < views; ++k) retained.insert(graph::light_instance("caustics", k));
  auto prepare = [&](std::shared_ptr<const scene::Scene> s) {
    executor.set_view(s->camera, s->lights);
    executor.configure(g, o.width, o.height, {.retained = retained});
  };
  // --frames 0: one frame, untimed, where only the maps are wanted (the suite's run).
  auto render = [&](std::shared_ptr<const scene::Scene> s) {
    prepare(std::move(s));
    if (o.frames > 0) return time_frames(executor, o.frames, caustic_passes(g));
    Timings untimed;
    untimed.method_ms = untimed.frame_ms = std::nan("");
    untimed.last = executor.run_frame(true);
    return untimed;
  };
  // The moved lights' maps are compared, not timed: one frame each, without the warm-up.
  auto render_untimed = [&](std::shared_ptr<const scene::Scene> s) {
    prepare(std::move(s));
    executor.run_frame(true);
  };
  // Every view's map, stacked as the reference's. Without a refractor the caustic pass is culled
  // ("enabled": "light.view * light.refractors") and its map never exists: an empty map, which is
  // the right answer.
  auto caustic_map = [&] {
    std::vector<io::ImageData> maps;
    for (uint32_t k = 0; k < views; ++k) {
      const std::string name = executor.plan().resolve(graph::light_instance("caustics", k));
      const int index = executor.plan().find_resource(name);
      const bool drawn = index >= 0 && executor.plan().resources[static_cast<size_t>(index)].used();
      maps.push_back(drawn ? executor.read_image(name) : empty_map(o.caustic_size));
    }
    return stacked(maps);
  };
  MethodResult r;
  r.timings = render(scene);
  const io::ImageData map = caustic_map();
  const io::ImageData frame = executor.read_image(executor.plan().resources[executor.plan().outputs.front()].name);
  for (const auto* image : {&map, &frame}) {
    for (float v : image->rgba) r.nonfinite += std::isfinite(v) ? 0 : 1;
  }
  for (const auto& [name, value] : r.timings.last.counters) r.nonfinite += std::isfinite(value) ? 0 : 1;
  r.accuracy = reference::compare_images(map, reference, o.blur);
  render_untimed(with_light_moved(*scene, kShift));
  r.shifted = reference::compare_images(caustic_map(), map, o.blur);
  if (c.moving_light) {
    io::ImageData previous = map;
    for (int i = 1; i < kPathSteps; ++i) {
      render_untimed(with_light_moved(*scene, kStep * float(i)));
      io::ImageData current = caustic_map();
      r.flicker += reference::compare_images(current, previous, o.blur).relative_l1 / (kPathSteps - 1);
      previous = std::move(current);
    }
  }
  r.processed = r.timings.last.counters.count("photons.processed") ? r.timings.last.counters.at("photons.processed") : 0.0;
  return r;
}

// The method's row of the CSV and of the Markdown table, and its progress line.
void add_rows(const StabilityCase& c, const Method& m, const MethodResult& r, const CaseReference& reference, const StabilityOptions& o,
              std::string& csv, std::string& table) {
  char line[768];
  std::snprintf(line, sizeof(line), "%s,%s,%.6f,%.6f,%.6f,%llu,%.0f,%.4f,%.6f,%.6f,%.6f,%.6f,%llu,%.6f\n", c.label, m.label,
                r.accuracy.relative_l1, r.accuracy.energy_ratio, r.accuracy.shape_l1, static_cast<unsigned long long>(r.nonfinite),
                r.processed, r.timings.method_ms, r.shifted.relative_l1, r.shifted.energy_ratio, r.flicker, reference.flicker,
                static_cast<unsigned long long>(reference.landed_photons), reference.shift);
  csv += line;
  char flicker_cell[64] = "-";
  if (c.moving_light) std::snprintf(flicker_cell, sizeof(flicker_cell), "%.4f (%.4f)", r.flicker, reference.flicker);
  char ms_cell[32] = "-";
  if (o.frames > 0) std::snprintf(ms_cell, sizeof(ms_cell), "%.2f", r.timings.method_ms);
  std::snprintf(line, sizeof(line), "| %s | %s | %.4f | %.4f | %.4f | %llu | %.0f | %s | %.5f (%.5f) | %s |\n", c.label, m.label,
                r.accuracy.relative_l1, r.accuracy.energy_ratio, r.accuracy.shape_l1, static_cast<unsigned long long>(r.nonfinite),
                r.processed, ms_cell, r.shifted.relative_l1, reference.shift, flicker_cell);
  table += line;
  std::fprintf(stderr, "%s, %s: relative L1 %.4f, energy %.4f, %llu NaN/Inf\n", c.label, m.label, r.accuracy.relative_l1,
               r.accuracy.energy_ratio, static_cast<unsigned long long>(r.nonfinite));
}

constexpr const char* kStabilityCsvHeader =
    "case,method,relative_l1,energy_ratio,shape_l1,nonfinite,photons_processed,caustic_ms,shift_l1,shift_energy,flicker,reference_"
    "flicker,reference_landed_photons,reference_shift_l1\n";

// DIR/stability.csv and DIR/README.md, from the rows of one process or of its cells joined; the
// configuration and the table on stdout.
void write_stability_results(const std::string& device, const StabilityOptions& o, const std::string& csv, const std::string& table) {
  char timing[64] = "one frame, untimed";
  if (o.frames > 0) std::snprintf(timing, sizeof(timing), "median of %u frames after one warm-up", o.frames);
  char config[512];
  std::snprintf(config, sizeof(config),
                "Device %s; photon grid %u^2, caustic map %u^2, frames %ux%u, %s; reference %llu photons (Fresnel on); metrics after a "
                "Gaussian blur of sigma %.3g texels (docs/accuracy.md). Light path: %d positions 0.02 apart.",
                device.c_str(), o.grid, o.caustic_size, o.width, o.height, timing, static_cast<unsigned long long>(o.reference_photons),
                o.blur, kPathSteps);
  const std::string header =
      "| case | method | relative L1 | energy ratio | shape L1 | NaN/Inf | photons | caustic ms | 1e-4 shift: L1 (reference) | flicker "
      "(reference) |\n"
      "|---|---|---|---|---|---|---|---|---|---|\n";
  std::cout << config << "\n\n" << header << table;
  if (!o.out_dir.empty()) {
    const std::filesystem::path dir(o.out_dir);
    io::write_text_atomically((dir / "stability.csv").string(), kStabilityCsvHeader + csv);
    io::write_text_atomically((dir / "README.md").string(),
                              "# caustica bench stability\n\n" + std::string(config) + "\n\n" + header + table);
  }
}

// One cell of the sweep: a method on a case. The cells run in this order, one process's rows' order.
struct StabilityCell {
  size_t case_index = 0, method = 0;
};

std::vector<StabilityCell> stability_cells(const StabilityOptions& o) {
  std::vector<StabilityCell> cells;
  for (size_t c = 0; c < o.cases.size(); ++c) {
    for (size_t m = 0; m < std::size(kStabilityMethods); ++m) cells.push_back({c, m});
  }
  return cells;
}

// The method's graph with the sweep's grid and caustic map size.
graph::GraphDesc method_graph(const Method& m, const StabilityOptions& o) {
  graph::GraphDesc g = graph::load_graph_file(graph_path(m.graph));
  std::vector<std::string> sets{"grid=" + std::to_string(o.grid), "caustic_size=" + std::to_string(o.caustic_size)};
  if (m.extra) sets.emplace_back(m.extra);
  graph::apply_overrides(g, sets);
  return g;
}

}  // namespace

// Where each caustic method breaks: every case of kStabilityCases x every method, against the
// photon reference (docs/stability.md reports a run); or one cell of that sweep (--cell), or the
// list of its cells.
int cmd_bench_stability(Args& args) {
  const std::vector<std::string> sweep = sweep_arguments(args);
  const StabilityOptions o = parse_stability_options(args);
  const std::vector<StabilityCell> cells = stability_cells(o);
  if (o.cells.list) {
    for (size_t k = 0; k < cells.size(); ++k) {
      const Method& m = kStabilityMethods[cells[k].method];
      std::printf("%zu %s %s%s%s grid=%u\n", k, o.cases[cells[k].case_index].name().c_str(), m.graph, m.extra ? ":" : "",
                  m.extra ? m.extra : "", o.grid);
    }
    return 0;
  }
  const bool one_cell = !o.cells.cell.empty();
  const size_t first = one_cell ? cell_index(o.cells.cell, cells.size()) : 0, end = one_cell ? first + 1 : cells.size();
  if (!o.out_dir.empty()) std::filesystem::create_directories(o.out_dir);
  vk::Context vk(device_options(o.device, o.validate));
  shader::ShaderCompiler& shaders = shader::process_shader_compiler();
  std::string csv, table;
  // A case's methods share its reference and its executor (the geometry stays on the device).
  std::shared_ptr<const scene::Scene> scene;
  std::optional<CaseReference> reference;
  std::unique_ptr<graph::Executor> executor;
  for (size_t k = first; k < end; ++k) {
    const StabilityCase& c = o.cases[cells[k].case_index];
    const Method& m = kStabilityMethods[cells[k].method];
    if (!executor || cells[k].case_index != cells[k - 1].case_index) {
      scene = std::make_shared<const scene::Scene>(scene::load_scene_file(scene_path(c.scene)));
      reference = trace_case_reference(c, *scene, o);
      executor = std::make_unique<graph::Executor>(vk, shaders, passes::builtin_registry());
      executor->set_scene(scene);
    }
    const graph::GraphDesc g = method_graph(m, o);
    if (!runs_on(vk, g)) {
      std::fprintf(stderr, "%s: skipped on %s, which lacks %s (ray queries)\n", m.label, vk.device_name().c_str(),
                   vk.ray_queries().missing.c_str());
      continue;
    }
    add_rows(c, m, measure_method(*executor, g, c, scene, reference->map, o), *reference, o, csv, table);
  }
  if (one_cell)
    write_cell(o.out_dir, first, cells.size(), kStabilityCsvHeader, {"stability", sweep, vk.device_name(), csv, table});
  else
    write_stability_results(vk.device_name(), o, csv, table);
  if (vk.validation_messages() > 0) {
    std::fprintf(stderr, "caustica: %u validation messages (see above)\n", vk.validation_messages());
    return 3;
  }
  return 0;
}

void write_merged_stability(const CellRows& rows, const std::string& out_dir) {
  Args args = sweep_args(rows.sweep, out_dir);
  const StabilityOptions o = parse_stability_options(args);
  std::filesystem::create_directories(out_dir);
  write_stability_results(rows.device, o, rows.csv, rows.table);
}

std::string stability_flags_help() {
  StabilityOptions o;
  return stability_flags(o).help();
}

}  // namespace caustica::cli::bench
