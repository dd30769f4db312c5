// The caustica command: render, trace, validate, graph plan|dot, devices.
// Exit codes: 0 ok, 1 invalid input, 2 usage, 3 device or runtime failure (DESIGN.md).
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <set>
#include <string>
#include <vector>

#include "builtin_passes.h"
#include "core/error.h"
#include "core/paths.h"
#include "core/suggest.h"
#include "graph/executor.h"
#include "graph/report.h"
#include "graph/schema.h"
#include "io/image_io.h"
#include "io/json_reader.h"
#include "reference/image_metrics.h"
#include "reference/photon_reference.h"
#include "reference/refraction_reference.h"
#include "scene/scene.h"

using namespace caustica;

namespace {

constexpr const char* kDefaultGraph = "graphs/caustics_adaptive.json";
constexpr const char* kDefaultScene = "scenes/bunny_plane.json";

const char* kMainHelp = R"(caustica: a frame-graph renderer whose pipelines are JSON files

usage: caustica <command> [options]

commands:
  render     render frames headless to PNG or EXR, with stats and resource dumps
  trace      render frames and write a Chrome trace-event file (Perfetto, chrome://tracing)
  validate   check graph and scene files; exit 0 when all are valid, 1 with messages otherwise
  graph      print the compiled plan of a graph: 'graph plan FILE' (JSON) or 'graph dot FILE'
  devices    list the Vulkan devices
  bench      benchmarks: 'bench refraction' (deferred against forward refraction), 'bench photons' (the paper's table)
  reference  the ground truth with Embree: the exact refraction image, or (--photons) the exact caustic
  compare    how far one image is from another: relative L1 after a matched blur, energy ratio, PSNR

'caustica <command> --help' describes each command.
exit codes: 0 ok, 1 invalid input, 2 usage error, 3 device or runtime failure
)";

const char* kRenderOptionsHelp = R"(  --graph FILE          graph to run (default: graphs/caustics_adaptive.json in the data folder)
  --scene FILE          scene for graphs that draw one (default: scenes/bunny_plane.json); a graph
                        without scene passes ignores it
  --size WxH            output size (default 1280x720)
  --frames N            frames to run (default 1; timings are medians over frames 2..N)
  --set NAME=VALUE      override a graph parameter (repeatable)
  --stats FILE.json     per-pass GPU/CPU times, frame times, memory and counters
  --dump RES=FILE.exr   write an image resource as it stood at the end of the last frame (repeatable)
  --device NAME         Vulkan device whose name contains NAME (default: lavapipe)
  --validate            enable Khronos validation (with synchronization validation); any
                        message makes the command exit 3
  --memory-limit MIB    the engine's device-memory limit for the graph (default 1536)
)";

struct RenderOptions {
  std::string graph;
  std::string scene;
  bool scene_given = false;
  std::string out = "caustica.png";
  std::string stats;
  std::string trace;
  uint32_t width = 1280;
  uint32_t height = 720;
  uint32_t frames = 1;
  std::vector<std::string> sets;
  std::vector<std::pair<std::string, std::string>> dumps;
  std::string device;
  bool validate = false;
  uint64_t memory_limit_mib = 1536;
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

uint64_t parse_uint(const std::string& flag, const std::string& text, uint64_t min, uint64_t max) {
  size_t used = 0;
  unsigned long long v = 0;
  try {
    v = std::stoull(text, &used);
    // Counts such as 1e8 photons: a whole mantissa and a small whole exponent.
    if (used < text.size() && text[used] == 'e' && used + 1 < text.size() && text.size() - used <= 3 &&
        std::all_of(text.begin() + static_cast<std::ptrdiff_t>(used) + 1, text.end(), [](char c) { return c >= '0' && c <= '9'; })) {
      for (int e = std::stoi(text.substr(used + 1)); e > 0 && v <= max; --e) v *= 10;
      used = text.size();
    }
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || text.empty() || text[0] == '-' || v < min || v > max) {
    throw UsageError(flag + " " + text + ": expected a whole number from " + std::to_string(min) + " to " + std::to_string(max));
  }
  return v;
}

// CAUSTICA_FAULT=device_lost|out_of_memory makes the device fail on purpose, so tests can check
// that such failures end the run with exit code 3 and no output (README, "Testing error paths").
vk::ContextOptions device_options(const std::string& device, bool validate) {
  vk::ContextOptions options{device, validate, false};
  const char* fault = std::getenv("CAUSTICA_FAULT");
  if (fault == nullptr || *fault == '\0') return options;
  const std::string name = fault;
  if (name == "device_lost") options.injected_fault = VK_ERROR_DEVICE_LOST;
  else if (name == "out_of_memory") options.injected_fault = VK_ERROR_OUT_OF_DEVICE_MEMORY;
  else throw UsageError("CAUSTICA_FAULT=" + name + ": expected device_lost or out_of_memory");
  return options;
}

void unknown_option(const std::string& arg, const std::vector<std::string>& known) {
  throw UsageError("unknown option '" + arg + "'" + did_you_mean(arg, known) + "; see --help");
}

double parse_number(const std::string& flag, const std::string& text, double min, double max) {
  size_t used = 0;
  double v = 0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || text.empty() || !std::isfinite(v) || v < min || v > max) {
    throw UsageError(flag + " " + text + ": expected a number from " + JsonReader::format_number(min) + " to " + JsonReader::format_number(max));
  }
  return v;
}

void parse_size(const std::string& v, uint32_t& width, uint32_t& height) {
  size_t x = v.find('x');
  if (x == std::string::npos) throw UsageError("--size " + v + ": expected WIDTHxHEIGHT, e.g. 1280x720");
  width = static_cast<uint32_t>(parse_uint("--size width", v.substr(0, x), 1, 16384));
  height = static_cast<uint32_t>(parse_uint("--size height", v.substr(x + 1), 1, 16384));
}

RenderOptions parse_render(Args& args, bool trace) {
  RenderOptions o;
  const std::vector<std::string> known = {"--graph", "--scene", "--out", "--size", "--frames", "--set", "--stats", "--dump", "--device", "--validate",
                                          "--memory-limit"};
  while (!args.done()) {
    std::string a = args.take();
    if (a == "--graph") o.graph = args.value(a);
    else if (a == "--scene") {
      o.scene = args.value(a);
      o.scene_given = true;
    }
    else if (a == "--out") (trace ? o.trace : o.out) = args.value(a);
    else if (a == "--stats") o.stats = args.value(a);
    else if (a == "--set") o.sets.push_back(args.value(a));
    else if (a == "--device") o.device = args.value(a);
    else if (a == "--validate") o.validate = true;
    else if (a == "--frames") o.frames = static_cast<uint32_t>(parse_uint(a, args.value(a), 1, 100000));
    else if (a == "--memory-limit") o.memory_limit_mib = parse_uint(a, args.value(a), 1, 1u << 20);
    else if (a == "--size") {
      parse_size(args.value(a), o.width, o.height);
    } else if (a == "--dump") {
      std::string v = args.value(a);
      size_t eq = v.find('=');
      if (eq == std::string::npos || eq == 0 || eq + 1 == v.size()) throw UsageError("--dump " + v + ": expected RESOURCE=FILE.exr");
      o.dumps.emplace_back(v.substr(0, eq), v.substr(eq + 1));
    } else {
      unknown_option(a, known);
    }
  }
  if (o.graph.empty()) o.graph = (data_dir() / kDefaultGraph).string();
  if (o.scene.empty()) o.scene = (data_dir() / kDefaultScene).string();
  if (trace && o.trace.empty()) throw UsageError("trace needs --out FILE.json");
  // A long render must not fail at the end for an output it could never have written.
  if (!o.out.empty()) io::check_image_output(o.out);
  for (const auto& [resource, file] : o.dumps) io::check_image_output(file);
  for (const std::string* file : {&o.stats, &o.trace}) {
    if (!file->empty()) io::check_output_file(*file);
  }
  return o;
}

// One line on stderr, rewritten in place: "LABEL done/total (p%)  elapsed, left"; ends the line when done.
void print_progress(const char* label, uint64_t done, uint64_t total, std::chrono::steady_clock::time_point start) {
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double left = done > 0 ? elapsed / double(done) * double(total - done) : 0.0;
  std::fprintf(stderr, "\r%s %llu/%llu (%.0f%%)  %.1f s elapsed, %.1f s left   ", label, static_cast<unsigned long long>(done),
               static_cast<unsigned long long>(total), 100.0 * double(done) / double(total), elapsed, left);
  if (done == total) std::fprintf(stderr, "\n");
}

// Writes JSON through a temporary file so a failed run never leaves half a file.
void write_json(const std::string& path, const nlohmann::json& value) { io::write_text_atomically(path, value.dump(2) + "\n"); }

int run_render(const RenderOptions& o, bool trace) {
  graph::GraphDesc graph = graph::load_graph_file(o.graph);
  graph::apply_overrides(graph, o.sets);
  std::set<std::string> retained;
  for (const auto& [resource, file] : o.dumps) retained.insert(resource);

  // Model no more than the graph needs: a graph without scene passes loads no scene.
  const bool needs_scene = std::any_of(graph.passes.begin(), graph.passes.end(), [](const graph::PassDesc& p) {
    const auto* decl = passes::builtin_registry().find(p.type);
    return decl && decl->needs_scene;
  });
  std::shared_ptr<const scene::Scene> scene;
  if (needs_scene) scene = std::make_shared<const scene::Scene>(scene::load_scene_file(o.scene));

  vk::Context vk(device_options(o.device, o.validate));
  shader::ShaderCompiler shaders(data_dir() / "shaders");
  graph::Executor executor(vk, shaders, passes::builtin_registry());
  executor.set_scene(scene);
  executor.configure(graph, o.width, o.height, retained, o.memory_limit_mib << 20);
  for (const auto& [resource, file] : o.dumps) {
    const auto& r = executor.plan().resources[static_cast<size_t>(executor.plan().find_resource(executor.plan().resolve(resource)))];
    if (r.kind != graph::ResourceKind::image) throw InputError("--dump " + resource + ": '" + resource + "' is a buffer; --dump takes images");
    if (!r.used()) throw InputError("--dump " + resource + ": '" + resource + "' is not used by any pass that runs");
  }

  graph::RunRecord run;
  run.device = vk.device_name();
  const bool show_progress = o.frames >= 10 || (o.frames > 1 && ::isatty(STDERR_FILENO));
  const auto start = std::chrono::steady_clock::now();
  for (uint32_t f = 0; f < o.frames; ++f) {
    run.frame_start_ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    run.frames.push_back(executor.run_frame(f + 1 == o.frames));
    if (show_progress) print_progress("frame", f + 1, o.frames, start);
  }

  if (!trace) {
    const auto& outputs = executor.plan().outputs;
    io::write_image(o.out, executor.read_image(executor.plan().resources[outputs.front()].name));
  }
  for (const auto& [resource, file] : o.dumps) io::write_image(file, executor.read_image(resource));
  if (!o.stats.empty()) write_json(o.stats, graph::stats_json(executor.plan(), run));
  if (trace) write_json(o.trace, graph::chrome_trace_json(executor.plan(), run));

  const auto& frame = run.frames.back();
  std::fprintf(stderr, "%s: %ux%u, %u frame%s on %s, last frame GPU %.2f ms, CPU %.2f ms -> %s\n", executor.plan().graph_name.c_str(),
               o.width, o.height, o.frames, o.frames == 1 ? "" : "s", run.device.c_str(), frame.gpu_ms, frame.cpu_ms,
               trace ? o.trace.c_str() : o.out.c_str());
  if (vk.validation_messages() > 0) {
    std::fprintf(stderr, "caustica: %u validation message%s (see above)\n", vk.validation_messages(), vk.validation_messages() == 1 ? "" : "s");
    return 3;
  }
  return 0;
}

int cmd_render(Args& args) {
  if (args.wants_help()) {
    std::cout << "usage: caustica render [options]\n\nRenders frames of a graph headless and writes its first output.\n"
                 "With no options: the default graph at 1280x720 to caustica.png.\n\noptions:\n"
                 "  --out FILE            output image, .png (8-bit sRGB) or .exr (linear float); default caustica.png\n"
              << kRenderOptionsHelp;
    return 0;
  }
  return run_render(parse_render(args, false), false);
}

int cmd_trace(Args& args) {
  if (args.wants_help()) {
    std::cout << "usage: caustica trace --out TRACE.json [--frames N] [render options]\n\n"
                 "Runs frames and writes Chrome trace-event JSON that Perfetto (ui.perfetto.dev) and chrome://tracing\n"
                 "open: a GPU track with each pass from timestamps, a CPU track with recording times, one counter\n"
                 "track per pass counter, and the graph and pass names as metadata.\n\noptions:\n"
                 "  --out FILE.json       the trace file (required)\n"
              << kRenderOptionsHelp;
    return 0;
  }
  return run_render(parse_render(args, true), true);
}

int cmd_validate(Args& args) {
  if (args.wants_help() || args.done()) {
    std::cout << "usage: caustica validate FILE...\n\nChecks graphs and scenes without a device: a graph is loaded and compiled at\n"
                 "1280x720 against the built-in pass types (as for a scene with one refractor, one light and two\n"
                 "objects); a scene (a file with \"camera\" or \"objects\") is loaded\n"
                 "with its meshes. Prints 'FILE: ok' or the problems with file, line and JSON pointer.\n"
                 "Exit 0 when every file is valid, 1 otherwise.\n";
    return args.wants_help() ? 0 : 2;
  }
  int status = 0;
  while (!args.done()) {
    std::string file = args.take();
    try {
      JsonDocument doc = JsonDocument::load(file);
      if (doc.root().is_object() && (doc.root().contains("camera") || doc.root().contains("objects"))) {
        scene::load_scene(doc);
      } else {
        graph::CompileOptions options;
        options.scene_values = graph::typical_scene_values();
        graph::compile_graph(graph::load_graph(std::move(doc)), passes::builtin_registry(), options);
      }
      std::cout << file << ": ok\n";
    } catch (const InputError& e) {
      std::cerr << e.what() << "\n";
      status = 1;
    }
  }
  return status;
}

int cmd_graph(Args& args) {
  const char* help =
      "usage: caustica graph plan FILE [--size WxH] [--set NAME=VALUE]... [--scene S]\n"
      "       caustica graph dot FILE [--size WxH] [--set NAME=VALUE]... [--scene S]\n"
      "       caustica graph schema      (the JSON Schema of graph files, as in graphs/schema.json)\n\n"
      "Compiles a graph without a device and prints the plan: 'plan' as JSON (order, culled passes,\n"
      "lifetimes, memory offsets, barriers, memory.transient_bytes_aliased/unaliased), 'dot' as Graphviz.\n"
      "Memory sizes are the device-independent estimate (tightly packed texels). Expressions about the scene\n"
      "(scene.refractors, scene.lights, scene.objects) see --scene S, or one refractor, one light and two\n"
      "objects without it.\n";
  if (args.wants_help()) {
    std::cout << help;
    return 0;
  }
  if (args.done()) throw UsageError("graph needs 'plan', 'dot' or 'schema'; see caustica graph --help");
  std::string what = args.take();
  if (what == "schema") {
    std::cout << graph::graph_schema_json(passes::builtin_registry()).dump(2) << "\n";
    return 0;
  }
  if (what != "plan" && what != "dot") throw UsageError("graph " + what + ": expected 'plan' or 'dot'" + did_you_mean(what, {"plan", "dot", "schema"}));
  if (args.done()) throw UsageError("graph " + what + " needs a FILE");
  std::string file = args.take();
  if (file.rfind("--", 0) == 0) throw UsageError("graph " + what + ": the FILE comes before the options, as in caustica graph " + what + " FILE " + file + " ...");
  RenderOptions o = parse_render(args, false);
  graph::GraphDesc graph = graph::load_graph_file(file);
  graph::apply_overrides(graph, o.sets);
  graph::CompileOptions options;
  options.output_width = o.width;
  options.output_height = o.height;
  options.memory_limit_bytes = o.memory_limit_mib << 20;
  options.scene_values = graph::typical_scene_values();
  if (o.scene_given) options.scene_values = scene::load_scene_file(o.scene).expression_values();
  graph::Plan plan = graph::compile_graph(graph, passes::builtin_registry(), options);
  if (what == "plan") std::cout << graph::plan_to_json(plan).dump(2) << "\n";
  else std::cout << graph::plan_to_dot(plan);
  return 0;
}

int cmd_reference(Args& args) {
  if (args.wants_help()) {
    std::cout << "usage: caustica reference --scene FILE --out FILE.exr [--size WxH]\n"
                 "       caustica reference --scene FILE --photons N --out MAP.exr [--seed K] [--map-size N]\n"
                 "                          [--camera IMAGE.exr [--size WxH]] [--no-fresnel]\n\n"
                 "Without --photons: ray traces the scene's camera image on its exact geometry with Embree (every\n"
                 "core): refraction at every interface, total internal reflection followed inside, Fresnel\n"
                 "transmittance and absorption, and otherwise the engine's own lighting model. It is the ground truth\n"
                 "that image-space refraction is measured against (docs/refraction.md). Writes linear radiance (EXR)\n"
                 "or an 8-bit PNG.\n\n"
                 "With --photons: traces N photons from the first (spot) light through every interface, Fresnel and\n"
                 "total internal reflection exact, to the receivers, and writes the caustic map as the engine holds it\n"
                 "(flux per texel of the light's image plane, --map-size texels a side) and, with --camera, the caustic\n"
                 "irradiance the camera sees. Deterministic for a seed on any number of cores (docs/accuracy.md).\n\n"
                 "options:\n"
                 "  --scene FILE          the scene (default: scenes/bunny_plane.json)\n"
                 "  --out FILE            the image (required)\n"
                 "  --size WxH            camera image size (default 1280x720)\n"
                 "  --photons N           photons to trace, e.g. 1e8\n"
                 "  --seed K              random seed (default 1)\n"
                 "  --map-size N          side of the light-space map (default 512, the graphs' caustic_size)\n"
                 "  --camera FILE.exr     also write the caustic irradiance seen by the camera\n"
                 "  --no-fresnel          transmit every photon unless total internal reflection (the graphs' fresnel=false)\n";
    return 0;
  }
  std::string scene_file = (data_dir() / kDefaultScene).string(), out, camera_out;
  uint32_t width = 1280, height = 720;
  reference::PhotonOptions photons;
  photons.photons = 0;
  while (!args.done()) {
    std::string a = args.take();
    if (a == "--scene") scene_file = args.value(a);
    else if (a == "--out") out = args.value(a);
    else if (a == "--size") parse_size(args.value(a), width, height);
    else if (a == "--photons") photons.photons = parse_uint(a, args.value(a), 1, 100'000'000'000ull);
    else if (a == "--seed") photons.seed = parse_uint(a, args.value(a), 0, ~0ull);
    else if (a == "--map-size") photons.map_size = static_cast<uint32_t>(parse_uint(a, args.value(a), 1, 8192));
    else if (a == "--camera") camera_out = args.value(a);
    else if (a == "--no-fresnel") photons.fresnel = false;
    else unknown_option(a, {"--scene", "--out", "--size", "--photons", "--seed", "--map-size", "--camera", "--no-fresnel"});
  }
  if (out.empty()) throw UsageError("reference needs --out FILE.exr");
  if (photons.photons == 0 && (!camera_out.empty() || !photons.fresnel)) throw UsageError("--camera and --no-fresnel go with --photons");
  io::check_image_output(out);
  if (!camera_out.empty()) io::check_image_output(camera_out);
  const scene::Scene scene = scene::load_scene_file(scene_file);
  const auto start = std::chrono::steady_clock::now();
  if (photons.photons > 0) {
    if (!camera_out.empty()) {
      photons.camera_width = width;
      photons.camera_height = height;
    }
    const bool show_progress = photons.photons >= 10'000'000 || ::isatty(STDERR_FILENO);
    if (show_progress) photons.progress = [&](uint64_t done, uint64_t total) { print_progress("photons", done, total, start); };
    const auto result = reference::trace_photon_reference(scene, photons);
    io::write_image(out, result.caustic_map);
    if (!camera_out.empty()) io::write_image(camera_out, result.camera);
    const auto& t = result.totals;
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("photons %llu in %.2f s (%.1f M/s), seed %llu\n", static_cast<unsigned long long>(t.photons), seconds,
                double(t.photons) / seconds * 1e-6, static_cast<unsigned long long>(photons.seed));
    std::printf("flux emitted %.6g: direct %.6g, entering a refractor %.6g\n", t.emitted, t.direct, t.entering);
    std::printf("of the entering flux: landed in the map %.6g (%.2f%%), off the map %.6g, reflected off the outside %.6g, escaped %.6g, trapped %.6g, absorbed %.6g\n",
                t.landed, t.entering > 0 ? 100.0 * t.landed / t.entering : 0.0, t.off_map, t.reflected, t.escaped, t.trapped, t.absorbed);
    std::fprintf(stderr, "reference: %s -> %s%s%s\n", scene.name.c_str(), out.c_str(), camera_out.empty() ? "" : ", ", camera_out.c_str());
    return 0;
  }
  auto image = reference::render_refraction_reference(scene, width, height);
  io::write_image(out, image.radiance);
  std::fprintf(stderr, "reference: %s %ux%u in %.2f s -> %s\n", scene.name.c_str(), width, height,
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), out.c_str());
  return 0;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
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
    if (a == "--scene") scenes.push_back(args.value(a));
    else if (a == "--size") parse_size(args.value(a), width, height);
    else if (a == "--frames") frames = static_cast<uint32_t>(parse_uint(a, args.value(a), 2, 1000));
    else if (a == "--sphere-detail") sphere_details.push_back(static_cast<uint32_t>(parse_uint(a, args.value(a), 3, 1024)));
    else if (a == "--device") device = args.value(a);
    else if (a == "--csv") csv = args.value(a);
    else unknown_option(a, {"--scene", "--size", "--frames", "--sphere-detail", "--device", "--csv"});
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
  if (cases.empty()) throw UsageError("bench refraction needs --scene FILE or --sphere-detail N (repeatable)");

  vk::Context vk(device_options(device, false));
  shader::ShaderCompiler shaders(data_dir() / "shaders");
  const char* graphs[2] = {"refraction_forward", "refraction_deferred"};
  std::string table = "| scene | refractor triangles | forward: refraction passes | deferred: refraction passes | deferred / forward | forward frame | deferred frame |\n|---|---|---|---|---|---|---|\n";
  std::string rows_csv = "scene,refractor_triangles,forward_refraction_ms,deferred_refraction_ms,forward_frame_ms,deferred_frame_ms\n";
  for (const auto& c : cases) {
    std::unique_ptr<graph::Executor> executors[2];
    for (int g = 0; g < 2; ++g) {
      executors[g] = std::make_unique<graph::Executor>(vk, shaders, passes::builtin_registry());
      executors[g]->set_scene(c.scene);
      executors[g]->configure(graph::load_graph_file((data_dir() / "graphs" / (std::string(graphs[g]) + ".json")).string()), width, height);
    }
    std::vector<double> refraction[2], frame[2];
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
      std::fprintf(stderr, "\r%s: frame %u/%u   ", c.label.c_str(), f + 1, frames + 2);
    }
    std::fprintf(stderr, "\n");
    size_t triangles = 0;
    for (const auto& o : c.scene->objects) triangles += o.material.refractor ? o.mesh.indices.size() / 3 : 0;
    const double fw = median(refraction[0]), df = median(refraction[1]);
    char row[512];
    std::snprintf(row, sizeof(row), "| %s | %zu | %.2f ms | %.2f ms | %.2f | %.2f ms | %.2f ms |\n", c.label.c_str(), triangles, fw, df, df / fw,
                  median(frame[0]), median(frame[1]));
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
  std::string scene_file = (data_dir() / kDefaultScene).string(), out_dir, device;
  std::vector<uint32_t> grids{256, 512, 1024, 2048, 4096, 8192, 16384};
  uint32_t frames = 3, regular_max = 16384;
  while (!args.done()) {
    std::string a = args.take();
    if (a == "--scene") scene_file = args.value(a);
    else if (a == "--out") out_dir = args.value(a);
    else if (a == "--device") device = args.value(a);
    else if (a == "--frames") frames = static_cast<uint32_t>(parse_uint(a, args.value(a), 1, 100));
    else if (a == "--regular-max") regular_max = static_cast<uint32_t>(parse_uint(a, args.value(a), 64, 65536));
    else if (a == "--grids") {
      grids.clear();
      std::string list = args.value(a);
      for (size_t start = 0; start <= list.size();) {
        size_t comma = std::min(list.find(',', start), list.size());
        const uint64_t g = parse_uint("--grids", list.substr(start, comma - start), 64, 65536);
        if ((g & (g - 1)) != 0) throw UsageError("--grids: " + std::to_string(g) + " is not a power of two");
        grids.push_back(static_cast<uint32_t>(g));
        start = comma + 1;
      }
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
  };
  const Method methods[] = {{"regular", "caustics_regular"},
                            {"hierarchical", "caustics_hierarchical"},
                            {"adaptive_max_level", "caustics_adaptive_maxlevel"},
                            {"adaptive_max_error", "caustics_adaptive_maxerror"},
                            {"adaptive_hybrid", "caustics_adaptive"}};
  std::string csv = "grid,method,processed,gpu_ms\n";
  std::string table = "| photon grid | regular | hierarchical | adaptive, max level | adaptive, max error | adaptive, hybrid |\n|---|---|---|---|---|---|\n";
  std::string times = "| photon grid | regular | hierarchical | adaptive, max level | adaptive, max error | adaptive, hybrid |\n|---|---|---|---|---|---|\n";
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
      graph::apply_overrides(g, {"grid=" + std::to_string(grid)});
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
      std::fprintf(stderr, "\r%u^2 %s: %.0f photons, %.2f ms          ", grid, m.name, processed, median(ms));
    }
    std::fprintf(stderr, "\n");
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

int cmd_bench(Args& args) {
  const char* help =
      "usage: caustica bench refraction [--scene FILE]... [--sphere-detail N]... [--size WxH] [--frames N] [--csv FILE]\n"
      "       caustica bench photons [--scene FILE] [--grids 256,512,...] [--frames N] [--regular-max G] [--out DIR]\n\n"
      "photons: the paper's table on a scene (default the bunny): photons processed by the regular, hierarchical and\n"
      "adaptive (max level, max error, hybrid) caustic maps for each effective grid, and the caustic pass's GPU time;\n"
      "DIR/photons.csv has columns grid, method, processed, gpu_ms. --regular-max skips the regular map above a grid.\n\n"
      "Deferred against forward refraction on the same scenes, one run, frames interleaved: median GPU time of the\n"
      "refraction passes (refractor_buffers + the refraction pass) and of the whole frame. --sphere-detail renders\n"
      "the ball-lens scene with its sphere tessellated into N slices (triangle count alone varies).\n";
  if (args.wants_help()) {
    std::cout << help;
    return 0;
  }
  if (args.done()) throw UsageError("bench needs a benchmark name: refraction or photons; see caustica bench --help");
  std::string what = args.take();
  if (what == "refraction") return cmd_bench_refraction(args);
  if (what == "photons") return cmd_bench_photons(args);
  throw UsageError("bench " + what + ": unknown benchmark" + did_you_mean(what, {"refraction", "photons"}));
}

int cmd_compare(Args& args) {
  if (args.wants_help()) {
    std::cout << "usage: caustica compare A B [--blur SIGMA] [--json] [--max-l1 X]\n\n"
                 "Compares image A (an engine output, e.g. --dump caustics=A.exr) with image B (the reference, e.g.\n"
                 "caustica reference --photons), both the same size (docs/accuracy.md):\n"
                 "  relative_l1    sum |A - B| / sum |B| on luminance after both are blurred by the same Gaussian\n"
                 "  energy_ratio   sum A / sum B on luminance (above 1: A has more energy than B)\n"
                 "  mean_error, rms_error, psnr, max_error   OpenImageIO's comparison of the unblurred colours\n"
                 "  nonfinite_a, nonfinite_b                NaN or Inf values in each image\n\n"
                 "options:\n"
                 "  --blur SIGMA          Gaussian sigma in pixels for relative_l1 and energy_ratio (default 1.5; 0: none)\n"
                 "  --json                print the metrics as JSON\n"
                 "  --max-l1 X            exit 1 when relative_l1 is above X (for tests)\n";
    return 0;
  }
  std::vector<std::string> files;
  double sigma = 1.5, max_l1 = -1;
  bool json = false;
  while (!args.done()) {
    std::string a = args.take();
    if (a == "--blur") sigma = parse_number(a, args.value(a), 0, 64);
    else if (a == "--max-l1") max_l1 = parse_number(a, args.value(a), 0, 1e30);
    else if (a == "--json") json = true;
    else if (a.rfind("--", 0) == 0) unknown_option(a, {"--blur", "--json", "--max-l1"});
    else files.push_back(a);
  }
  if (files.size() != 2) throw UsageError("compare needs two images, A and B; see caustica compare --help");
  const auto c = reference::compare_images(io::read_image(files[0]), io::read_image(files[1]), sigma);
  const nlohmann::json metrics = {{"relative_l1", c.relative_l1}, {"energy_ratio", c.energy_ratio}, {"mean_error", c.mean_error},
                                  {"rms_error", c.rms_error},     {"psnr", c.psnr},                 {"max_error", c.max_error},
                                  {"nonfinite_a", c.nonfinite_a}, {"nonfinite_b", c.nonfinite_b},   {"blur_sigma", sigma}};
  if (json) {
    std::cout << metrics.dump(2) << "\n";
  } else {
    std::printf("relative_l1   %.6g   (blur sigma %.3g px)\nenergy_ratio  %.6g\nmean_error    %.6g\nrms_error     %.6g\npsnr          %.4g dB\n"
                "max_error     %.6g\nnonfinite     %llu in A, %llu in B\n",
                c.relative_l1, sigma, c.energy_ratio, c.mean_error, c.rms_error, c.psnr, c.max_error,
                static_cast<unsigned long long>(c.nonfinite_a), static_cast<unsigned long long>(c.nonfinite_b));
  }
  if (max_l1 >= 0 && !(c.relative_l1 <= max_l1)) {
    std::fprintf(stderr, "caustica: %s: relative L1 %.6g against %s is above --max-l1 %.6g\n", files[0].c_str(), c.relative_l1, files[1].c_str(), max_l1);
    return 1;
  }
  return 0;
}

int cmd_devices(Args& args) {
  if (args.wants_help()) {
    std::cout << "usage: caustica devices\n\nLists the Vulkan devices; --device NAME picks one by a part of its name.\n";
    return 0;
  }
  for (const auto& d : vk::Context::list_devices()) {
    std::cout << d.name << "  (Vulkan " << VK_API_VERSION_MAJOR(d.api_version) << "." << VK_API_VERSION_MINOR(d.api_version)
              << (d.type == VK_PHYSICAL_DEVICE_TYPE_CPU ? ", CPU" : "") << ")\n";
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc < 2) {
      Args none(argc, argv, 1);
      return cmd_render(none);
    }
    std::string command = argv[1];
    Args args(argc, argv, 2);
    if (command == "--help" || command == "-h" || command == "help") {
      std::cout << kMainHelp;
      return 0;
    }
    if (command == "render") return cmd_render(args);
    if (command == "trace") return cmd_trace(args);
    if (command == "validate") return cmd_validate(args);
    if (command == "graph") return cmd_graph(args);
    if (command == "devices") return cmd_devices(args);
    if (command == "reference") return cmd_reference(args);
    if (command == "bench") return cmd_bench(args);
    if (command == "compare") return cmd_compare(args);
    throw UsageError("unknown command '" + command + "'" + did_you_mean(command, {"render", "trace", "validate", "graph", "devices", "reference", "bench", "compare"}) +
                     "; see caustica --help");
  } catch (const InputError& e) {
    std::cerr << "caustica: " << e.what() << "\n";
    return 1;
  } catch (const UsageError& e) {
    std::cerr << "caustica: " << e.what() << "\n";
    return 2;
  } catch (const DeviceError& e) {
    std::cerr << "caustica: device error: " << e.what() << "\n";
    return 3;
  } catch (const std::exception& e) {
    std::cerr << "caustica: runtime error: " << e.what() << "\n";
    return 3;
  }
}
