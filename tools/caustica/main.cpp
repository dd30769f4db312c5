// The caustica command: render, trace, validate, graph, reference, merge, compare, devices; bench.cpp has the benchmarks.
// Exit codes: 0 ok, 1 invalid input, 2 usage, 3 device or runtime failure (README).
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <optional>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "bench_common.h"
#include "builtin_passes.h"
#include "cli.h"
#include "core/error.h"
#include "core/paths.h"
#include "core/suggest.h"
#include "graph/executor.h"
#include "graph/report.h"
#include "graph/schema.h"
#include "io/image_io.h"
#include "io/json_reader.h"
#include "reference/camera_shard.h"
#include "reference/image_metrics.h"
#include "reference/photon_reference.h"
#include "reference/photon_shard.h"
#include "reference/refraction_reference.h"
#include "scene/acceleration.h"
#include "scene/scene.h"

using namespace caustica;
using namespace caustica::cli;

namespace {

const char* kMainHelp = R"(caustica: a frame-graph renderer whose pipelines are JSON files

usage: caustica <command> [options]

commands:
  render     render frames headless to PNG or EXR, with stats and resource dumps
  trace      render frames and write a Chrome trace-event file (Perfetto, chrome://tracing)
  validate   check graph and scene files; exit 0 when all are valid, 1 with messages otherwise
  graph      compiled plans and graph files: 'graph plan FILE' (JSON), 'graph dot FILE' (Graphviz),
             'graph schema' (the JSON Schema of graph files), 'graph set FILE NAME=VALUE...' (new defaults)
  graphs     list the bundled graphs, each by the name --graph takes, with its description's first sentence
  scenes     list the bundled scenes, each by the name --scene takes, with its description's first sentence
  devices    list the Vulkan devices
  bench      benchmarks: 'bench refraction' (deferred against forward refraction), 'bench photons' (the paper's
             table), 'bench accuracy' (speed against accuracy, the chart), 'bench stability' (where each method breaks),
             'bench convergence' (error against wall time while accumulating), 'bench load' (loading a scene or model)
  reference  the ground truth with Embree: the exact refraction image, or (--photons) the exact caustic,
             whole or (--shard I/K) as one of K parts for a cluster
  merge      joins the shards of a reference into its map or image (docs/cluster.md)
  view       the graph in a window: pass times, counters, parameters, hot reload (GLFW + ImGui)
  edit       the graph editor: passes as nodes, resources as wires, the frame live as you edit
  compare    how far one image is from another: relative L1 after a matched blur, energy ratio, PSNR

'caustica <command> --help' describes each command.
exit codes: 0 ok, 1 invalid input, 2 usage error, 3 device or runtime failure
)";

const char* kRenderOptionsHelp = R"(  --graph FILE          graph to run (default: graphs/caustics_adaptive.json in the data folder); a
                        bundled one also by its name from any folder (--graph caustics_regular)
  --scene FILE          scene for graphs that draw one (default: scenes/glass_bunny.json; a bundled
                        one also by its name, sphere_plane); a graph
                        without scene passes ignores it. A model file (.gltf, .glb, .obj, .off) is a
                        scene of its own: its camera (or one that frames it), its KHR_lights_punctual
                        lights (or a spot light placed for a caustic), and a floor under it
  --no-stage            with a model file: no floor
  --size WxH            output size (default 1280x720)
  --frames N            frames to run (default 1; timings are medians over frames 2..N)
  --accumulate N        N frames of a graph with an accumulate pass (graphs/caustics_progressive.json):
                        the image and --dump show the mean of the N frames' caustic maps
  --seconds S           run frames until S seconds have passed (an accumulating graph converges)
  --set NAME=VALUE      override a graph parameter (repeatable)
  --stats FILE.json     per-pass GPU/CPU times, frame times (median, 95th and 99th percentile), memory and counters
  --dump RES=FILE.exr   write an image resource as it stood at the end of the last frame (repeatable;
                        .exr keeps float values, .png only for 8-bit resources)
  --device NAME         Vulkan device whose name contains NAME (default: lavapipe)
  --validate            enable Khronos validation (with synchronization validation); any
                        message makes the command exit 3
  --memory-limit MIB    the engine's device-memory limit for the graph (default 1536)
  --orbit DEG           turn the camera about its target by DEG each frame and skip the passes whose inputs
                        did not change (the light's), as `caustica view --orbit` does: the viewer's frame
                        times without a window
)";

RenderOptions parse_render(Args& args, bool trace) {
  RenderOptions o;
  const std::vector<std::string> known = {"--graph",      "--scene",    "--out",          "--size",     "--frames",
                                          "--accumulate", "--seconds",  "--set",          "--stats",    "--dump",
                                          "--device",     "--validate", "--memory-limit", "--no-stage", "--orbit"};
  std::vector<std::string> counts;  // --frames, --accumulate, --seconds: one says how long to run
  std::set<std::string> given;
  while (!args.done()) {
    std::string a = args.take();
    if (a != "--set" && a != "--dump" && !(a == "--out" && !trace)) given_once(given, a);
    if (a == "--graph")
      o.graph = find_data_file(args.value(a), "graphs");
    else if (a == "--scene") {
      o.scene = find_data_file(args.value(a), "scenes");
      o.scene_given = true;
    } else if (a == "--no-stage")
      o.stage = false;
    else if (a == "--out")
      if (trace)
        o.trace = args.value(a);
      else
        o.outs.push_back(args.value(a));
    else if (a == "--stats")
      o.stats = args.value(a);
    else if (a == "--set")
      o.sets.push_back(args.value(a));
    else if (a == "--device")
      o.device = args.value(a);
    else if (a == "--validate")
      o.validate = true;
    else if (a == "--frames" || a == "--accumulate") {
      o.frames = static_cast<uint32_t>(parse_uint(a, args.value(a), 1, 100000));
      o.accumulate = a == "--accumulate";
      counts.push_back(a);
    } else if (a == "--seconds") {
      o.seconds = parse_uint(a, args.value(a), 1, 86400);
      counts.push_back(a);
    } else if (a == "--memory-limit")
      o.memory_limit_mib = parse_uint(a, args.value(a), 1, 1u << 20);
    else if (a == "--orbit")
      o.orbit_degrees = static_cast<float>(parse_number(a, args.value(a), -180, 180));
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
  if (counts.size() > 1) throw UsageError(counts[0] + " and " + counts[1] + " both say how long to run: give one of them");
  if (o.graph.empty()) o.graph = (data_dir() / kDefaultGraph).string();
  if (o.scene.empty()) o.scene = (data_dir() / kDefaultScene).string();
  if (trace && o.trace.empty()) throw UsageError("trace needs --out FILE.json");
  if (!trace && o.outs.empty()) o.outs.push_back("caustica.png");
  const auto is_exr = [](const std::string& f) { return std::filesystem::path(f).extension() == ".exr"; };
  if (o.outs.size() > 2 || (o.outs.size() == 2 && is_exr(o.outs[0]) == is_exr(o.outs[1]))) {
    throw UsageError("--out is given twice for the same kind of file: give one picture (.png) and one linear .exr at most");
  }
  // A long render must not fail at the end for an output it could never have written.
  for (const auto& out : o.outs) io::check_image_output(out);
  for (const auto& [resource, file] : o.dumps) io::check_image_output(file);
  for (const std::string* file : {&o.stats, &o.trace}) {
    if (!file->empty()) io::check_output_file(*file);
  }
  return o;
}

// Writes JSON through a temporary file so a failed run never leaves half a file.
void write_json(const std::string& path, const nlohmann::json& value) {
  io::write_text_atomically(path, value.dump(2) + "\n");
}

// What --out F.exr writes: an EXR holds linear values, so the graph's linear_output, or where the
// graph does not declare one and its first output is a tonemap pass's display-encoded 8-bit
// image, the tonemap's linear input; empty otherwise (the output as it is).
std::string linear_source_of_output(const graph::GraphDesc& graph, const std::string& out) {
  if (std::filesystem::path(out).extension() != ".exr" || graph.outputs.empty()) return "";
  if (!graph.linear_output.empty()) return graph.linear_output;
  // A graph that does not say: the input of the tone map that makes its first output.
  for (const auto& pass : graph.passes) {
    const auto target = pass.outputs.find("target");
    if (pass.type == "tonemap" && target != pass.outputs.end() && target->second == graph.outputs.front()) return pass.inputs.at("source");
  }
  return "";
}

int run_render(const RenderOptions& o, bool trace) {
  graph::GraphDesc graph = graph::load_graph_file(o.graph);
  graph::apply_overrides(graph, o.sets);
  std::set<std::string> retained;
  for (const auto& [resource, file] : o.dumps) retained.insert(resource);
  // Each --out with what it writes: the graph's first output, or for an .exr its linear source.
  std::vector<std::pair<std::string, std::string>> outs;
  for (const auto& out : o.outs) {
    outs.emplace_back(out, linear_source_of_output(graph, out));
    if (!outs.back().second.empty()) retained.insert(outs.back().second);
  }

  // Model no more than the graph needs: a graph without scene passes loads no scene.
  const bool needs_scene = std::any_of(graph.passes.begin(), graph.passes.end(), [](const graph::PassDesc& p) {
    const auto* decl = passes::builtin_registry().find(p.type);
    return decl && decl->needs_scene;
  });
  std::shared_ptr<const scene::Scene> scene;
  if (needs_scene) scene = std::make_shared<const scene::Scene>(scene::load_scene_file(o.scene, o.stage));

  vk::Context vk(device_options(o.device, o.validate));
  shader::ShaderCompiler shaders(data_dir() / "shaders");
  graph::Executor executor(vk, shaders, passes::builtin_registry());
  executor.set_scene(scene);
  executor.configure(graph, o.width, o.height,
                     {.retained = retained, .memory_limit_bytes = o.memory_limit_mib << 20, .reuse_unchanged_passes = o.orbit_degrees != 0.0f});
  for (const auto& warning : executor.plan().warnings) std::cerr << "caustica: warning: " << warning << "\n";
  const auto& planned = executor.plan().passes;
  if (o.accumulate && std::none_of(planned.begin(), planned.end(), [](const graph::PlannedPass& p) { return p.type == "accumulate"; })) {
    throw InputError(o.graph +
                     ": --accumulate needs an accumulate pass that runs on this scene (graphs/caustics_progressive.json has "
                     "one); --frames N runs frames without averaging them");
  }
  for (const auto& [resource, file] : o.dumps) {
    const int index = executor.plan().find_resource(executor.plan().resolve(resource));
    if (index < 0) {
      throw InputError("--dump " + resource + ": no pass that runs on this scene writes '" + resource +
                       "' (its fallback is null; e.g. a caustic map without a refractor)");
    }
    const auto& r = executor.plan().resources[static_cast<size_t>(index)];
    if (r.kind != graph::ResourceKind::image)
      throw InputError("--dump " + resource + ": '" + resource + "' is a buffer; --dump takes images");
    if (!r.used()) throw InputError("--dump " + resource + ": '" + resource + "' is not used by any pass that runs");
    const bool eight_bit = r.format == graph::Format::rgba8 || r.format == graph::Format::rgba8_srgb;
    if (!eight_bit && std::filesystem::path(file).extension() != ".exr") {
      throw InputError("--dump " + resource + "=" + file + ": '" + resource + "' holds " + graph::format_info(r.format).name +
                       " values, which an 8-bit PNG would clip and round; write it to a .exr file");
    }
  }

  graph::RunRecord run;
  run.device = vk.device_name();
  if (const auto* acceleration = executor.scene() ? executor.scene()->built_acceleration() : nullptr) {
    run.acceleration_bytes = acceleration->bytes();
    run.acceleration_build_ms = acceleration->sort_ms() + acceleration->build_ms();
  }
  const bool timed = o.seconds > 0;
  const bool show_progress = timed || o.frames >= 10 || (o.frames > 1 && ::isatty(STDERR_FILENO));
  ProgressLine progress(timed ? "second" : "frame", timed ? o.seconds : o.frames);
  const auto start = std::chrono::steady_clock::now();
  const auto elapsed_ms = [&] { return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count(); };
  scene::View camera = scene ? scene->camera : scene::View{};  // --orbit turns it
  for (uint32_t f = 0;; ++f) {
    const double started = elapsed_ms();
    // With --seconds, the last frame is the one that would end past the limit, judged by the one before.
    const double last_ms = run.frames.empty() ? 0.0 : started - run.frame_start_ms.back();
    const bool last = timed ? started + last_ms >= 1000.0 * static_cast<double>(o.seconds) : f + 1 == o.frames;
    run.frame_start_ms.push_back(started);
    if (f > 0 && o.orbit_degrees != 0.0f && scene) {
      camera.orbit(o.orbit_degrees);
      executor.set_view(camera, scene->lights);
    }
    run.frames.push_back(executor.run_frame(last));
    run.frame_wall_ms.push_back(elapsed_ms() - started);
    if (show_progress) progress.update(timed ? std::min<uint64_t>(o.seconds, static_cast<uint64_t>(elapsed_ms() / 1000.0)) : f + 1);
    if (last) break;
  }

  std::string written = trace ? o.trace : "";
  for (const auto& [out, linear] : outs) {
    io::write_image(out, executor.read_image(linear.empty() ? executor.plan().resources[executor.plan().outputs.front()].name : linear));
    const char* why = graph.linear_output.empty() ? "the tonemap's input" : "the graph's linear_output";
    written += (written.empty() ? "" : ", ") + out + (linear.empty() ? "" : " (linear: '" + linear + "', " + why + ")");
  }
  for (const auto& [resource, file] : o.dumps) {
    io::write_image(file, executor.read_image(resource));
    written += ", " + resource + " -> " + file;
  }
  if (!o.stats.empty()) write_json(o.stats, graph::stats_json(executor.plan(), run));
  if (trace) write_json(o.trace, graph::chrome_trace_json(executor.plan(), run));

  const auto& frame = run.frames.back();
  std::fprintf(stderr, "%s: %ux%u, %u frame%s on %s, last frame GPU %.2f ms, CPU %.2f ms -> %s\n", executor.plan().graph_name.c_str(),
               o.width, o.height, static_cast<uint32_t>(run.frames.size()), run.frames.size() == 1 ? "" : "s", run.device.c_str(),
               frame.gpu_ms, frame.cpu_ms, written.c_str());
  if (vk.validation_messages() > 0) {
    std::fprintf(stderr, "caustica: %u validation message%s (see above)\n", vk.validation_messages(),
                 vk.validation_messages() == 1 ? "" : "s");
    return 3;
  }
  return 0;
}

int cmd_render(Args& args) {
  if (args.wants_help()) {
    std::cout << "usage: caustica render [options]\n\nRenders frames of a graph headless and writes its first output.\n"
                 "With no options: the default graph at 1280x720 to caustica.png.\n\noptions:\n"
                 "  --out FILE            output image, .png (8-bit sRGB) or .exr (linear float: the graph's linear_output, its\n"
                 "                        HDR result before the tone map, or without one the tonemap's input); default\n"
                 "                        caustica.png; give it twice for both, one .png and one .exr\n"
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

// validate takes graphs and scenes alike: a bundled one by name is either.
std::string find_graph_or_scene(const std::string& given) {
  for (const char* folder : {"graphs", "scenes"}) {
    const std::string found = find_data_file(given, folder);
    if (std::filesystem::exists(found)) return found;
  }
  return given;
}

int cmd_validate(Args& args) {
  if (args.wants_help() || args.done()) {
    std::cout << "usage: caustica validate FILE... [--scene S [--no-stage]]\n\nChecks graphs and scenes without a device: a graph is "
                 "loaded and compiled at\n"
                 "1280x720 against the built-in pass types (as for a scene with one refractor, one light and two\n"
                 "objects; with --scene S, as for that scene, which is checked too, and the plan's warnings are\n"
                 "printed, e.g. passes that draw from a point light's view); a scene (a file with \"camera\" or \"objects\") is loaded\n"
                 "with its meshes; a model file (.gltf, .glb, .obj, .off) is loaded as --scene opens it; a JSON Schema "
                 "(graphs/schema.json) is skipped. Prints 'FILE: ok' or the problems\n"
                 "with file, line and JSON pointer.\n"
                 "A graph with a pass that traces exact paths (ray queries) is also checked against the device it\n"
                 "would run on (lavapipe by default; CAUSTICA_NO_RAY_QUERY=1 masks ray queries).\n"
                 "Exit 0 when every file is valid, 1 otherwise.\n";
    return args.wants_help() ? 0 : 2;
  }
  std::vector<std::string> files;
  std::string scene_file;
  bool stage = true;
  while (!args.done()) {
    const std::string a = args.take();
    if (a == "--scene")
      scene_file = find_data_file(args.value(a), "scenes");
    else if (a == "--no-stage")
      stage = false;
    else if (a.rfind("--", 0) == 0)
      unknown_option(a, {"--scene", "--no-stage"});
    else
      files.push_back(find_graph_or_scene(a));
  }
  int status = 0;
  std::map<std::string, double> scene_values = graph::typical_scene_values();
  if (!scene_file.empty()) {
    try {
      scene_values = scene::load_scene_file(scene_file, stage).expression_values();
      std::cout << scene_file << ": ok\n";
    } catch (const InputError& e) {
      std::cerr << e.what() << "\n";
      return 1;
    }
  }
  for (const std::string& file : files) {
    try {
      if (scene::is_model_file(file)) {  // a model opened as a scene, as --scene takes it
        scene::load_model_scene(file);
        std::cout << file << ": ok\n";
        continue;
      }
      JsonDocument doc = JsonDocument::load(file);
      const auto& root = doc.root();
      // graphs/schema.json sits beside the graphs, so that `validate graphs/*.json` meets it.
      if (root.is_object() && root.contains("$schema") && root["$schema"].is_string() &&
          root["$schema"].get<std::string>().find("json-schema.org") != std::string::npos) {
        std::cout << file << ": skipped (a JSON Schema, not a graph or a scene)\n";
        continue;
      }
      if (root.is_object() && (root.contains("camera") || root.contains("objects"))) {
        scene::load_scene(doc);
      } else {
        graph::CompileOptions options;
        options.scene_values = scene_values;
        const graph::GraphDesc graph = graph::load_graph(std::move(doc));
        const graph::Plan plan = graph::compile_graph(graph, passes::builtin_registry(), options);
        for (const auto& warning : plan.warnings) std::cout << file << ": warning: " << warning << "\n";
        // A graph that traces with ray queries is valid only where the device it would run on has them.
        if (!plan.ray_query_passes.empty()) {
          vk::RayQuerySupport support;
          try {
            support = vk::probe_ray_queries("");
          } catch (const DeviceError& e) {
            support = {false, std::string("a Vulkan device (") + e.what() + ")"};
          }
          if (!support.available) {
            options.ray_queries = false;
            options.ray_queries_missing = support.missing;
            graph::compile_graph(graph, passes::builtin_registry(), options);
          }
        }
      }
      std::cout << file << ": ok\n";
    } catch (const InputError& e) {
      std::cerr << e.what() << "\n";
      status = 1;
    }
  }
  return status;
}

// caustica graph params: what a graph takes, as a table a user reads before --set.
std::string value_text(const nlohmann::json& value) {
  return value.is_string() ? value.get<std::string>() : value.dump();
}

std::string range_text(const graph::ParamDecl& d) {
  if (d.type == graph::ParamType::choice) {
    std::string choices;
    for (const auto& c : d.choices) choices += (choices.empty() ? "" : "|") + c;
    return choices;
  }
  if (d.min && d.max)
    return JsonReader::format_number(*d.min) + " to " + JsonReader::format_number(*d.max) + (d.power_of_two ? ", powers of two" : "");
  return d.type == graph::ParamType::bool_ ? "true|false" : "";
}

void print_graph_params(const graph::GraphDesc& graph, const graph::PassRegistry& registry) {
  auto row = [](std::string indent, const std::string& name, std::string_view type, const std::string& value, const std::string& range,
                const std::string& note) {
    std::printf("%s%-24s %-7s %-15s %-26s %s\n", indent.c_str(), name.c_str(), std::string(type).c_str(), value.c_str(), range.c_str(),
                note.c_str());
  };
  std::printf("graph parameters of %s (render, view, bench: --set NAME=VALUE; graph set FILE NAME=VALUE):\n", graph.name.c_str());
  if (graph.parameters.empty()) std::printf("  (none)\n");
  for (const auto& p : graph.parameters) {
    std::string note = p.decl.description;
    if (p.while_moving) note += " [while moving: " + value_text(*p.while_moving) + "]";
    if (!p.while_still.empty()) {
      std::string values;
      for (const auto& v : p.while_still) values += (values.empty() ? "" : ", then ") + value_text(v);
      note += " [while still: " + values + (p.while_still.size() > 1 ? " while refining is over the frame budget" : "") + "]";
    }
    row("  ", p.decl.name, graph::param_type_name(p.decl.type), value_text(p.value), range_text(p.decl), note);
  }
  std::printf(
      "\npass parameters (set in the graph file; \"$NAME\" follows graph parameter NAME; [per frame]: may be an "
      "expression of frame.*; [sampling only]: how fast an accumulated mean converges, not to what, so a change keeps the "
      "mean):\n");
  for (const auto& pass : graph.passes) {
    const graph::PassTypeDecl* decl = registry.find(pass.type);
    if (!decl || decl->params.empty()) continue;
    std::printf("  %s (%s)\n", pass.name.c_str(), pass.type.c_str());
    for (const auto& d : decl->params) {
      const bool given = pass.params.contains(d.name);
      const std::string value = given ? value_text(pass.params[d.name]) : value_text(d.default_value) + " (default)";
      row("    ", d.name, graph::param_type_name(d.type), value, range_text(d),
          std::string(d.per_frame ? "[per frame] " : "") + (d.sampling_only ? "[sampling only] " : "") + d.description);
    }
  }
}

int cmd_graph(Args& args) {
  const char* help =
      "usage: caustica graph plan FILE [--size WxH] [--set NAME=VALUE]... [--scene S]\n"
      "       caustica graph dot FILE [--size WxH] [--set NAME=VALUE]... [--scene S]\n"
      "       caustica graph schema      (the JSON Schema of graph files, as in graphs/schema.json)\n"
      "       caustica graph set FILE NAME=VALUE... [--out NEW.json]\n"
      "       caustica graph params FILE (the graph's parameters, which --set sets, and each pass's, with types,\n"
      "                                   values, ranges and descriptions)\n\n"
      "'set' writes parameter values into the graph file as their defaults (or into NEW.json): only those values\n"
      "change, the rest of the file stays as it was written. The viewer's Save does the same.\n\n"
      "Compiles a graph without a device and prints the plan: 'plan' as JSON (order, culled passes,\n"
      "lifetimes, memory offsets, barriers, memory.transient_bytes_aliased/unaliased), 'dot' as Graphviz.\n"
      "Memory sizes are the device-independent estimate (tightly packed texels). A graph that traces with ray\n"
      "queries adds memory.acceleration: the scene's (--scene S, default scenes/glass_bunny.json) build inputs\n"
      "exactly and its acceleration structures at lavapipe 25's layout; render --stats reports the driver's own.\n"
      "Expressions about the scene (scene.refractors, scene.lights, scene.objects, scene.dispersive, scene.diagonal,\n"
      "scene.ray_epsilon) see --scene S, or one refractor that does not disperse, one light and two objects 10 apart\n"
      "(ray epsilon 0.001) without it.\n";
  if (args.wants_help()) {
    std::cout << help;
    return 0;
  }
  if (args.done()) throw UsageError("graph needs 'plan', 'dot', 'schema', 'set' or 'params'; see caustica graph --help");
  std::string what = args.take();
  if (what == "schema") {
    std::cout << graph::graph_schema_json(passes::builtin_registry()).dump(2) << "\n";
    return 0;
  }
  if (what == "set") {
    if (args.done()) throw UsageError("graph set needs a FILE and NAME=VALUE assignments");
    const std::string file = args.take();
    std::string out = file;
    std::vector<std::string> sets;
    while (!args.done()) {
      std::string a = args.take();
      if (a == "--out")
        out = args.value(a);
      else if (a.rfind("--", 0) == 0)
        unknown_option(a, {"--out"});
      else
        sets.push_back(a);
    }
    if (sets.empty()) throw UsageError("graph set needs at least one NAME=VALUE");
    io::check_output_file(out);
    graph::GraphDesc graph = graph::load_graph_file(file);
    graph::apply_overrides(graph, sets, "graph set");
    io::write_text_atomically(out, graph::graph_text_with_values(graph));
    return 0;
  }
  if (what == "params") {
    if (args.done()) throw UsageError("graph params needs a FILE");
    const std::string file = find_data_file(args.take(), "graphs");
    if (!args.done()) throw UsageError("graph params takes one FILE; unexpected '" + args.take() + "'");
    print_graph_params(graph::load_graph_file(file), passes::builtin_registry());
    return 0;
  }
  if (what != "plan" && what != "dot")
    throw UsageError("graph " + what + ": expected 'plan', 'dot', 'schema', 'set' or 'params'" +
                     did_you_mean(what, {"plan", "dot", "schema", "set", "params"}));
  if (args.done()) throw UsageError("graph " + what + " needs a FILE");
  const std::string given = args.take();
  if (given.rfind("--", 0) == 0)
    throw UsageError("graph " + what + ": the FILE comes before the options, as in caustica graph " + what + " FILE " + given + " ...");
  const std::string file = find_data_file(given, "graphs");
  RenderOptions o = parse_render(args, false);
  graph::GraphDesc graph = graph::load_graph_file(file);
  graph::apply_overrides(graph, o.sets);
  graph::CompileOptions options;
  options.output_width = o.width;
  options.output_height = o.height;
  options.memory_limit_bytes = o.memory_limit_mib << 20;
  options.scene_values = graph::typical_scene_values();
  std::optional<scene::Scene> scene;
  if (o.scene_given) {
    scene = scene::load_scene_file(o.scene, o.stage);
    options.scene_values = scene->expression_values();
  }
  graph::Plan plan = graph::compile_graph(graph, passes::builtin_registry(), options);
  if (what == "dot") {
    std::cout << graph::plan_to_dot(plan);
    return 0;
  }
  nlohmann::json out = graph::plan_to_json(plan);
  if (!plan.ray_query_passes.empty()) {
    if (!scene) scene = scene::load_scene_file(o.scene, o.stage);
    const scene::AccelerationEstimate estimate = scene::estimate_acceleration(*scene);
    out["memory"]["acceleration"] = {{"scene", o.scene},
                                     {"triangles", estimate.triangles},
                                     {"instances", estimate.instances},
                                     {"input_bytes", estimate.input_bytes},
                                     {"structure_bytes_estimate", estimate.structure_bytes},
                                     {"bytes_estimate", estimate.total()}};
  }
  std::cout << out.dump(2) << "\n";
  return 0;
}

struct Shard {
  uint64_t index = 0, count = 0;  // count 0: the whole reference
};

// --shard I/K, I from 0; auto/K: I is the array index that Slurm or Kubernetes gives the process.
Shard parse_shard(const std::string& text) {
  const std::string usage = "--shard " + text + ": expected INDEX/COUNT, INDEX from 0 to COUNT - 1 or auto, e.g. 3/64 or auto/64";
  const size_t slash = text.find('/');
  if (slash == std::string::npos) throw UsageError(usage + (text == "auto" ? " (auto gives the index; the count is yours to give)" : ""));
  Shard shard;
  try {
    shard.count = parse_uint("--shard", text.substr(slash + 1), 1, 1'000'000);
  } catch (const UsageError&) {
    throw UsageError(usage + " (the count '" + text.substr(slash + 1) + "' is not a whole number from 1 to 1000000)");
  }
  std::string index = text.substr(0, slash), from = "--shard";
  if (index == "auto") {
    std::tie(index, from) = bench::scheduler_index();
    if (from.empty()) {
      throw UsageError("--shard " + text + ": neither SLURM_ARRAY_TASK_ID (a Slurm job array) nor JOB_COMPLETION_INDEX (a Kubernetes " +
                       "Indexed Job) is set; outside a scheduler give the index: --shard I/" + std::to_string(shard.count));
    }
  }
  try {
    shard.index = parse_uint(from, index, 0, shard.count - 1);
  } catch (const UsageError&) {
    const std::string what = from == "--shard" ? "the index '" + index + "'" : "the index that " + from + " gives, '" + index + "',";
    throw UsageError(usage + " (" + what + " is not a whole number from 0 to " + std::to_string(shard.count - 1) + ")");
  }
  return shard;
}

void print_photon_flux(const reference::PhotonTotals& t) {
  std::printf("flux emitted %.6g: direct %.6g, entering a refractor %.6g\n", t.emitted, t.direct, t.entering);
  std::printf(
      "of the entering flux: landed in the map %.6g (%.2f%%), off the map %.6g, escaped %.6g, trapped %.6g, absorbed %.6g; "
      "reflected off the outside first %.6g (followed)\n",
      t.landed, t.entering > 0 ? 100.0 * t.landed / t.entering : 0.0, t.off_map, t.escaped, t.trapped, t.absorbed, t.reflected);
}

// One shard of the photon reference: its range's sums, exactly, with what it is a part of.
int trace_photon_shard(const scene::Scene& scene, reference::PhotonOptions photons, const Shard& shard, const std::string& out) {
  const auto start = std::chrono::steady_clock::now();
  const auto [first, end] = reference::shard_range(photons.photons, shard.index, shard.count);
  ProgressLine progress("photons", end - first);
  if (end - first >= 10'000'000 || ::isatty(STDERR_FILENO)) photons.progress = [&](uint64_t done, uint64_t) { progress.update(done); };
  const reference::TracedShard traced = reference::trace_photon_shard(scene, photons, shard.index, shard.count);
  const reference::PhotonShard& header = traced.shard;
  reference::write_photon_shard(out, header, traced.map_units);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("shard %llu/%llu: photons %llu to %llu of %llu in %.2f s (%.1f M/s), seed %llu\n",
              static_cast<unsigned long long>(shard.index), static_cast<unsigned long long>(shard.count),
              static_cast<unsigned long long>(header.first), static_cast<unsigned long long>(header.end - 1),
              static_cast<unsigned long long>(header.total), seconds, double(end - first) / seconds * 1e-6,
              static_cast<unsigned long long>(header.seed));
  print_photon_flux(header.totals);
  std::fprintf(stderr, "reference: %s shard %llu/%llu -> %s\n", scene.name.c_str(), static_cast<unsigned long long>(shard.index),
               static_cast<unsigned long long>(shard.count), out.c_str());
  return 0;
}

// One shard of the ray-traced camera reference: its range of rows, exactly, with what it is a part of.
int trace_camera_shard(const scene::Scene& scene, uint32_t width, uint32_t height, const io::ImageData* caustic_map, uint64_t seed,
                       const Shard& shard, const std::string& out) {
  const auto start = std::chrono::steady_clock::now();
  const reference::TracedCameraShard traced =
      reference::trace_camera_shard(scene, width, height, caustic_map, seed, shard.index, shard.count);
  const reference::CameraShard& header = traced.shard;
  reference::write_camera_shard(out, header, traced.rows);
  std::printf("shard %llu/%llu: rows %llu to %llu of %ux%u in %.2f s, seed %llu\n", static_cast<unsigned long long>(shard.index),
              static_cast<unsigned long long>(shard.count), static_cast<unsigned long long>(header.first),
              static_cast<unsigned long long>(header.end - 1), width, height,
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), static_cast<unsigned long long>(seed));
  std::fprintf(stderr, "reference: %s shard %llu/%llu -> %s\n", scene.name.c_str(), static_cast<unsigned long long>(shard.index),
               static_cast<unsigned long long>(shard.count), out.c_str());
  return 0;
}

int cmd_reference(Args& args) {
  if (args.wants_help()) {
    std::cout << "usage: caustica reference --scene FILE --out FILE.exr|.png [--size WxH] [--caustics MAP.exr] [--exposure E]\n"
                 "                          [--seed K] [--shard I/K]\n"
                 "       caustica reference --scene FILE --photons N --out MAP.exr [--seed K] [--map-size N]\n"
                 "                          [--camera IMAGE.exr [--size WxH]] [--no-fresnel] [--shard I/K]\n\n"
                 "Without --photons: ray traces the scene's camera image on its exact geometry with Embree (every\n"
                 "core): refraction at every interface, total internal reflection followed inside, Fresnel\n"
                 "transmittance and absorption, and otherwise the engine's own lighting model. It is the ground truth\n"
                 "that image-space refraction is measured against (docs/refraction.md). Writes linear radiance (EXR)\n"
                 "or an 8-bit PNG tone mapped as the engine's tonemap pass does (1 - exp(-E L), sRGB). With --caustics\n"
                 "MAP.exr (a map from --photons), surfaces the first light sees past the refractors also receive that\n"
                 "map's caustic, projected as the engine's lighting pass projects its own: the scene's reference picture\n"
                 "with caustics, seen directly and through the glass. A pixel whose ray meets a rough refractor averages\n"
                 "paths drawn from random numbers keyed on the seed and the pixel's place in the image.\n\n"
                 "With --photons: traces N photons from the first (spot or directional) light through every interface, Fresnel and\n"
                 "total internal reflection exact, to the receivers, and writes the caustic map as the engine holds it\n"
                 "(flux per texel of the light's image plane, --map-size texels a side) and, with --camera, the caustic\n"
                 "irradiance the camera sees. Deterministic for a seed on any number of cores (docs/accuracy.md).\n\n"
                 "With --shard I/K: traces only the I-th of K contiguous ranges of the N photons (each photon's random\n"
                 "numbers depend on the seed and its index alone) and writes their sums, exactly, to --out (an EXR whose\n"
                 "header holds the range, the photon count, the seed and the scene's and the engine's identity, written\n"
                 "under a temporary name and renamed); 'caustica merge' adds the K files into the map that one process\n"
                 "writes, bit for bit. 'auto/K' takes I from SLURM_ARRAY_TASK_ID (a Slurm job array, --array=0-K-1) or\n"
                 "JOB_COMPLETION_INDEX (a Kubernetes Indexed Job); docs/cluster.md.\n\n"
                 "Without --photons, --shard I/K traces the I-th of K contiguous ranges of the image's rows (each\n"
                 "pixel as the whole image's run traces it) and writes them to --out: an EXR of those rows (32-bit\n"
                 "floats, its data window the rows, its display window the image) whose header holds the rows, the\n"
                 "image's size, the seed, the --caustics map's identity and the scene's and the engine's identity,\n"
                 "written under a temporary name and renamed; 'caustica merge' joins the K files into the EXR that one\n"
                 "process writes, bit for bit.\n\n"
                 "options:\n"
                 "  --scene FILE          the scene (default: scenes/glass_bunny.json), or a model file (as for render)\n"
                 "  --no-stage            with a model file: no floor\n"
                 "  --out FILE            the image (required)\n"
                 "  --size WxH            camera image size (default 1280x720)\n"
                 "  --photons N           photons to trace, e.g. 1e8\n"
                 "  --seed K              random seed (default 1): the photons', or the rough refractors' paths\n"
                 "  --map-size N          side of the light-space map (default 512, the graphs' caustic_size)\n"
                 "  --camera FILE.exr     also write the caustic irradiance seen by the camera\n"
                 "  --no-fresnel          transmit every photon unless total internal reflection (the graphs' fresnel=false)\n"
                 "  --shard I/K           trace the I-th of K parts of the photons, or without --photons of the image's\n"
                 "                        rows (I from 0; auto/K: from the scheduler)\n"
                 "  --caustics MAP.exr    without --photons: light the picture with this caustic map too\n"
                 "  --exposure E          without --photons: the PNG's exposure (default 1, as the graphs')\n";
    return 0;
  }
  std::string scene_file = (data_dir() / kDefaultScene).string(), out, camera_out, caustics_file;
  uint32_t width = 1280, height = 720;
  float exposure = 1.0f;
  bool exposure_given = false;
  bool stage = true;
  reference::PhotonOptions photons;
  photons.photons = 0;
  Shard shard;
  std::set<std::string> given;
  while (!args.done()) {
    std::string a = args.take();
    if (a == "--scene")
      scene_file = find_data_file(args.value(a), "scenes");
    else if (a == "--out")
      out = args.value(a);
    else if (a == "--size")
      parse_size(args.value(a), width, height);
    else if (a == "--photons")
      photons.photons = parse_uint(a, args.value(a), 1, 100'000'000'000ull);
    else if (a == "--seed")
      photons.seed = parse_uint(a, args.value(a), 0, ~0ull);
    else if (a == "--map-size")
      photons.map_size = static_cast<uint32_t>(parse_uint(a, args.value(a), 1, 8192));
    else if (a == "--camera")
      camera_out = args.value(a);
    else if (a == "--no-fresnel")
      photons.fresnel = false;
    else if (a == "--shard") {
      given_once(given, a);
      shard = parse_shard(args.value(a));
    } else if (a == "--no-stage")
      stage = false;
    else if (a == "--caustics")
      caustics_file = args.value(a);
    else if (a == "--exposure") {
      exposure = static_cast<float>(parse_number(a, args.value(a), 0.0, 100.0));
      exposure_given = true;
    } else
      unknown_option(a, {"--scene", "--out", "--size", "--photons", "--seed", "--map-size", "--camera", "--no-fresnel", "--caustics",
                         "--exposure", "--no-stage", "--shard"});
  }
  if (out.empty()) throw UsageError("reference needs --out FILE.exr");
  if (photons.photons == 0 && (!camera_out.empty() || !photons.fresnel)) throw UsageError("--camera and --no-fresnel go with --photons");
  if (photons.photons > 0 && (!caustics_file.empty() || exposure_given)) throw UsageError("--caustics and --exposure go without --photons");
  const std::string out_extension = io::check_image_output(out);
  if (!camera_out.empty()) io::check_image_output(camera_out);
  if (shard.count > 0 && photons.photons == 0) {
    if (out_extension != ".exr") throw UsageError(out + ": a shard is an EXR of the image's rows: --out must end in .exr");
    if (exposure_given) throw UsageError("--exposure goes without --shard: a shard holds linear radiance");
    if (shard.count > height) {
      throw UsageError("--shard " + std::to_string(shard.index) + "/" + std::to_string(shard.count) + ": more shards than the " +
                       std::to_string(height) + " rows of the image");
    }
  } else if (shard.count > 0) {
    if (!camera_out.empty()) throw UsageError("--camera goes without --shard: a shard holds the light-space map's sums only");
    if (out_extension != ".exr") throw UsageError(out + ": a shard is an EXR of sums: --out must end in .exr");
    if (shard.count > photons.photons) {
      throw UsageError("--shard " + std::to_string(shard.index) + "/" + std::to_string(shard.count) + ": more shards than the " +
                       std::to_string(photons.photons) + " photons");
    }
  }
  const scene::Scene scene = scene::load_scene_file(scene_file, stage);
  if (shard.count > 0 && photons.photons > 0) return trace_photon_shard(scene, photons, shard, out);
  const auto start = std::chrono::steady_clock::now();
  if (photons.photons > 0) {
    if (!camera_out.empty()) {
      photons.camera_width = width;
      photons.camera_height = height;
    }
    const bool show_progress = photons.photons >= 10'000'000 || ::isatty(STDERR_FILENO);
    ProgressLine progress("photons", photons.photons);
    if (show_progress) photons.progress = [&](uint64_t done, uint64_t) { progress.update(done); };
    const auto result = reference::trace_photon_reference(scene, photons);
    io::write_image(out, result.caustic_map);
    if (!camera_out.empty()) io::write_image(camera_out, result.camera);
    const auto& t = result.totals;
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("photons %llu in %.2f s (%.1f M/s), seed %llu\n", static_cast<unsigned long long>(t.photons), seconds,
                double(t.photons) / seconds * 1e-6, static_cast<unsigned long long>(photons.seed));
    print_photon_flux(t);
    std::fprintf(stderr, "reference: %s -> %s%s%s\n", scene.name.c_str(), out.c_str(), camera_out.empty() ? "" : ", ", camera_out.c_str());
    return 0;
  }
  std::optional<io::ImageData> caustic_map;
  if (!caustics_file.empty()) caustic_map = io::read_image(caustics_file);
  if (shard.count > 0) return trace_camera_shard(scene, width, height, caustic_map ? &*caustic_map : nullptr, photons.seed, shard, out);
  auto image = reference::render_refraction_reference(scene, width, height, caustic_map ? &*caustic_map : nullptr, photons.seed);
  if (out_extension == ".png") {
    for (size_t i = 0; i < image.radiance.rgba.size(); ++i) {
      if (i % 4 != 3) image.radiance.rgba[i] = 1.0f - std::exp(-exposure * image.radiance.rgba[i]);
    }
  }
  io::write_image(out, image.radiance);
  std::fprintf(stderr, "reference: %s %ux%u in %.2f s -> %s\n", scene.name.c_str(), width, height,
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), out.c_str());
  return 0;
}

int cmd_merge(Args& args) {
  if (args.wants_help()) {
    std::cout << "usage: caustica merge SHARD.exr... --out OUT.exr\n\n"
                 "Joins the shards of a reference (one file per index) into what one process writes, bit for bit:\n"
                 "- photon shards ('caustica reference --photons N --shard I/K'): adds them, in the order of their\n"
                 "  photon ranges, one file at a time, into the caustic map of 'caustica reference --photons N'. They\n"
                 "  must tile the N photons exactly, from one scene, seed, photon count, map size, Fresnel setting and\n"
                 "  engine build.\n"
                 "- camera shards ('caustica reference --size WxH --shard I/K', without --photons): places their rows,\n"
                 "  one file at a time, into the EXR image of 'caustica reference --size WxH'. They must tile the image's\n"
                 "  rows exactly, from one scene (with its camera), seed, image size, --caustics map and engine build.\n"
                 "The first file's kind decides. Otherwise nothing is written and every problem is named: the missing\n"
                 "photons or rows with the shard indices that trace them (resubmit those), an overlap, a duplicate, a\n"
                 "shard of another run or of the other kind. Exit 0, 1 for such shards, 2 for a usage error\n"
                 "(docs/cluster.md).\n\n"
                 "options:\n"
                 "  --out OUT.exr         the merged map or image (required; written under a temporary name and renamed)\n";
    return 0;
  }
  std::string out;
  const std::vector<std::string> files = bench::merge_inputs(args, out);
  if (files.empty()) throw UsageError("merge needs the shard files: caustica merge SHARD.exr... --out OUT.exr");
  if (out.empty()) throw UsageError("merge needs --out OUT.exr");
  if (io::check_image_output(out) != ".exr") throw UsageError(out + ": the merged map or image is linear: --out must end in .exr");
  for (const auto& file : files) {
    if (std::filesystem::weakly_canonical(std::filesystem::absolute(file)) ==
        std::filesystem::weakly_canonical(std::filesystem::absolute(out))) {
      throw UsageError("--out " + out + " is one of the shards: merging would replace it");
    }
  }
  const auto start = std::chrono::steady_clock::now();
  auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  if (reference::shard_file_kind(files.front()) == "caustica camera shard") {
    const auto merged = reference::merge_camera_shards(files);
    io::write_image(out, merged.image);
    const auto& whole = merged.whole;
    std::printf("merged %zu shards: image %ux%llu, seed %llu, scene %s, in %.2f s\n", files.size(), whole.width,
                static_cast<unsigned long long>(whole.total), static_cast<unsigned long long>(whole.seed), whole.scene_name.c_str(),
                seconds());
  } else {
    const auto merged = reference::merge_photon_shards(files);
    io::write_image(out, merged.caustic_map);
    const auto& whole = merged.whole;
    std::printf("merged %zu shards: photons %llu, seed %llu, scene %s, in %.2f s\n", files.size(),
                static_cast<unsigned long long>(whole.total), static_cast<unsigned long long>(whole.seed), whole.scene_name.c_str(),
                seconds());
    print_photon_flux(whole.totals);
  }
  std::fprintf(stderr, "merge: %s\n", out.c_str());
  return 0;
}

int cmd_compare(Args& args) {
  if (args.wants_help()) {
    std::cout << "usage: caustica compare A B [--blur SIGMA] [--json] [--max-l1 X]\n\n"
                 "Compares image A (an engine output, e.g. --dump caustics=A.exr) with image B (the reference, e.g.\n"
                 "caustica reference --photons), both the same size (docs/accuracy.md):\n"
                 "  relative_l1    sum |A - B| / sum |B| on luminance after both are blurred by the same Gaussian\n"
                 "  energy_ratio   sum A / sum B on luminance (above 1: A has more energy than B)\n"
                 "  shape_l1       the same L1 with each image divided by its own sum (0 to 2): misplaced energy only\n"
                 "  mean_error, rms_error, max_error         |A - B| over the unblurred colour values\n"
                 "  psnr                                    20 log10(peak / rms_error) in dB, the peak B's largest colour value\n"
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
    if (a == "--blur")
      sigma = parse_number(a, args.value(a), 0, 64);
    else if (a == "--max-l1")
      max_l1 = parse_number(a, args.value(a), 0, 1e30);
    else if (a == "--json")
      json = true;
    else if (a.rfind("--", 0) == 0)
      unknown_option(a, {"--blur", "--json", "--max-l1"});
    else
      files.push_back(a);
  }
  if (files.size() != 2) throw UsageError("compare needs two images, A and B; see caustica compare --help");
  const io::ImageData a = io::read_image(files[0]), b = io::read_image(files[1]);
  const auto c = reference::compare_images(a, b, sigma);
  const nlohmann::json metrics = {{"relative_l1", c.relative_l1}, {"energy_ratio", c.energy_ratio}, {"shape_l1", c.shape_l1},
                                  {"mean_error", c.mean_error},   {"rms_error", c.rms_error},       {"psnr", c.psnr},
                                  {"max_error", c.max_error},     {"nonfinite_a", c.nonfinite_a},   {"nonfinite_b", c.nonfinite_b},
                                  {"blur_sigma", sigma}};
  if (json) {
    std::cout << metrics.dump(2) << "\n";
  } else {
    std::printf(
        "relative_l1   %.6g   (blur sigma %.3g px)\nenergy_ratio  %.6g\nshape_l1      %.6g\nmean_error    %.6g\nrms_error     %.6g\npsnr   "
        "       %.4g dB\n"
        "max_error     %.6g\nnonfinite     %llu in A, %llu in B\n",
        c.relative_l1, sigma, c.energy_ratio, c.shape_l1, c.mean_error, c.rms_error, c.psnr, c.max_error,
        static_cast<unsigned long long>(c.nonfinite_a), static_cast<unsigned long long>(c.nonfinite_b));
  }
  if (max_l1 >= 0 && !(c.relative_l1 <= max_l1)) {
    std::fprintf(stderr, "caustica: %s: relative L1 %.6g against %s is above --max-l1 %.6g\n", files[0].c_str(), c.relative_l1,
                 files[1].c_str(), max_l1);
    return 1;
  }
  return 0;
}

// The first sentence of a description, for a listing of one line a file.
std::string first_sentence(const std::string& text) {
  const size_t end = text.find(". ");
  std::string sentence = end == std::string::npos ? text : text.substr(0, end + 1);
  constexpr size_t kWidth = 100;
  if (sentence.size() > kWidth) sentence = sentence.substr(0, kWidth - 3) + "...";
  return sentence;
}

// caustica graphs / caustica scenes: the bundled files of `folder`, by the name --graph or --scene
// takes from any folder, with the first sentence of each one's description.
int cmd_list(Args& args, const char* folder, const char* flag) {
  if (args.wants_help()) {
    std::cout << "usage: caustica " << folder << "\n\nLists the bundled " << folder << " (in the data folder), each by the name " << flag
              << " NAME takes\nfrom any folder, with the first sentence of its description. A file in the current folder is taken\n"
                 "before a bundled one of the same name.\n";
    return 0;
  }
  if (!args.done()) throw UsageError(std::string(folder) + " takes no arguments");
  const std::filesystem::path root = data_dir() / folder;
  std::vector<std::pair<std::string, std::string>> listed;  // name, description
  for (const auto& entry : std::filesystem::recursive_directory_iterator(root)) {
    if (!entry.is_regular_file() || entry.path().extension() != ".json" || entry.path().filename() == "schema.json") continue;
    std::string name = std::filesystem::relative(entry.path(), root).replace_extension().generic_string();
    if (name.rfind("models/", 0) == 0) continue;  // the meshes' own files, not scenes
    std::string description;
    try {
      const JsonDocument doc = JsonDocument::load(entry.path().string());
      if (doc.root().contains("description") && doc.root()["description"].is_string()) description = doc.root()["description"];
    } catch (const InputError& e) {
      description = std::string("(cannot be read: ") + e.what() + ")";
    }
    listed.emplace_back(std::move(name), first_sentence(description));
  }
  std::sort(listed.begin(), listed.end());
  size_t width = 0;
  for (const auto& [name, description] : listed) width = std::max(width, name.size());
  std::cout << "bundled " << folder << " in " << root.string() << " (" << flag << " NAME):\n";
  for (const auto& [name, description] : listed) std::cout << "  " << name << std::string(width + 2 - name.size(), ' ') << description << "\n";
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
      std::cout << kMainHelp << "data folder (graphs, shaders, scenes): " << data_dir().string() << " (CAUSTICA_DATA_DIR overrides)\n";
      return 0;
    }
    if (command == "render") return cmd_render(args);
    if (command == "trace") return cmd_trace(args);
    if (command == "validate") return cmd_validate(args);
    if (command == "graph") return cmd_graph(args);
    if (command == "devices") return cmd_devices(args);
    if (command == "graphs") return cmd_list(args, "graphs", "--graph");
    if (command == "scenes") return cmd_list(args, "scenes", "--scene");
    if (command == "reference") return cmd_reference(args);
    if (command == "merge") return cmd_merge(args);
    if (command == "bench") return cmd_bench(args);
    if (command == "compare") return cmd_compare(args);
    if (command == "view") return cmd_view(args);
    if (command == "edit") return cmd_edit(args);
    throw UsageError("unknown command '" + command + "'" +
                     did_you_mean(command, {"render", "trace", "validate", "graph", "graphs", "scenes", "devices", "reference", "merge",
                                            "bench", "compare", "view", "edit"}) +
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
