// caustica render and caustica trace: frames of a graph headless, to pictures, stats and traces.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <set>
#include <string>
#include <vector>

#include "builtin_passes.h"
#include "cli.h"
#include "core/error.h"
#include "core/paths.h"
#include "flags.h"
#include "graph/executor.h"
#include "graph/report.h"
#include "io/files.h"
#include "io/image_io.h"
#include "scene/acceleration.h"
#include "scene/scene.h"

namespace caustica::cli {
namespace {

// --frames, --accumulate and --seconds each say how long to run; `counts` collects those given.
FlagTable render_flags(RenderOptions& o, bool trace, std::vector<std::string>& counts) {
  FlagTable table;
  if (trace) {
    table.add(text_flag("--out", "FILE.json", "the trace file (required)", o.trace));
  } else {
    table.add({"--out", "FILE",
               "output image, .png (8-bit sRGB) or .exr (linear float: the graph's linear_output, its\n"
               "HDR result before the tone map, or without one the tonemap's input); default\n"
               "caustica.png; give it twice for both, one .png and one .exr",
               [&o](const std::string& v) { o.outs.push_back(v); }, true});
  }
  const auto count = [&o, &counts](const char* flag, uint64_t max) {
    return [&o, &counts, flag, max](const std::string& v) {
      const uint64_t n = parse_uint(flag, v, 1, max);
      if (std::string(flag) == "--seconds") {
        o.seconds = n;
      } else {
        o.frames = static_cast<uint32_t>(n);
        o.accumulate = std::string(flag) == "--accumulate";
      }
      counts.push_back(flag);
    };
  };
  table.add(graph_flag(o.graph))
      .add(scene_flag(o.scene, &o.scene_given,
                      "scene for graphs that draw one (default: scenes/glass_bunny.json; a bundled\n"
                      "one also by its name, sphere_plane); a graph\n"
                      "without scene passes ignores it. A model file (.gltf, .glb, .obj, .off) is a\n"
                      "scene of its own: its camera (or one that frames it), its KHR_lights_punctual\n"
                      "lights (or a spot light placed for a caustic), and a floor under it"))
      .add(no_stage_flag(o.stage))
      .add(size_flag(o.width, o.height, "output size (default 1280x720)"))
      .add({"--frames", "N", "frames to run (default 1; timings are medians over frames 2..N)", count("--frames", 100000)})
      .add({"--accumulate", "N",
            "N frames of a graph with an accumulate pass (graphs/caustics_progressive.json):\n"
            "the image and --dump show the mean of the N frames' caustic maps",
            count("--accumulate", 100000)})
      .add({"--seconds", "S", "run frames until S seconds have passed (an accumulating graph converges)", count("--seconds", 86400)})
      .add(set_flag(o.sets))
      .add(moving_flag(o.moving))
      .add(stats_flag(o.stats, "per-pass GPU/CPU times, frame times (median, 95th and 99th percentile), memory and counters"))
      .add({"--dump", "RES=FILE.exr",
            "write an image resource as it stood at the end of the last frame (repeatable;\n"
            ".exr keeps float values, .png only for 8-bit resources)",
            [&o](const std::string& v) {
              const size_t eq = v.find('=');
              if (eq == std::string::npos || eq == 0 || eq + 1 == v.size())
                throw UsageError("--dump " + v + ": expected RESOURCE=FILE.exr");
              o.dumps.emplace_back(v.substr(0, eq), v.substr(eq + 1));
            },
            true})
      .add(device_flag(o.device))
      .add(tracer_flag())
      .add(validate_flag(o.validate))
      .add(frame_timeout_flag(o.frame_timeout_s, nullptr,
                              "default 120, a plan's first frame 900\n(lavapipe compiles its pipelines as they first run)"))
      .add(uint_flag("--memory-limit", "MIB", "the engine's device-memory limit for the graph (default 1536)", o.memory_limit_mib, 1,
                     1u << 20))
      .add(orbit_flag(o.orbit_degrees,
                      "turn the camera about its target by DEG each frame and skip the passes whose inputs\n"
                      "did not change (the light's), as `caustica view --orbit` does: the viewer's frame\n"
                      "times without a window"));
  return table;
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

// Checks each --dump against the plan: an image that a pass that runs writes, in a file that can hold its values.
void check_dumps(const graph::Plan& plan, const RenderOptions& o) {
  for (const auto& [resource, file] : o.dumps) {
    const int index = plan.find_resource(plan.resolve(resource));
    if (index < 0) {
      throw InputError("--dump " + resource + ": no pass that runs on this scene writes '" + resource +
                       "' (its fallback is null; e.g. a caustic map without a refractor)");
    }
    const auto& r = plan.resources[static_cast<size_t>(index)];
    if (r.kind != graph::ResourceKind::image)
      throw InputError("--dump " + resource + ": '" + resource + "' is a buffer; --dump takes images");
    if (!r.used()) throw InputError("--dump " + resource + ": '" + resource + "' is not used by any pass that runs");
    const bool eight_bit = r.format == graph::Format::rgba8 || r.format == graph::Format::rgba8_srgb;
    if (!eight_bit && std::filesystem::path(file).extension() != ".exr") {
      throw InputError("--dump " + resource + "=" + file + ": '" + resource + "' holds " + graph::format_info(r.format).name +
                       " values, which an 8-bit PNG would clip and round; write it to a .exr file");
    }
  }
}

// Runs the frames: --frames of them, or those that fit in --seconds; --orbit turns the camera.
graph::RunRecord run_frames(graph::Executor& executor, const scene::Scene* scene, const RenderOptions& o, const vk::Context& vk) {
  graph::RunRecord run;
  run.device = vk.device_name();
  if (const auto* acceleration = executor.scene() ? executor.scene()->built_acceleration() : nullptr) {
    run.acceleration_bytes = acceleration->bytes();
    run.acceleration_build_ms = acceleration->sort_ms() + acceleration->build_ms();
  }
  if (const auto* bvh = executor.scene() ? executor.scene()->built_tracer_bvh() : nullptr) {
    run.acceleration_bytes += bvh->bytes;
    run.acceleration_build_ms += bvh->build_ms;
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
  return run;
}

int run_render(const RenderOptions& o, bool trace) {
  graph::GraphDesc declared = graph::load_graph_file(o.graph);
  graph::apply_overrides(declared, o.sets);
  graph::GraphDesc graph = declared;
  const std::vector<std::string> still = o.moving ? std::vector<std::string>{} : apply_at_rest(graph, o.sets);
  std::set<std::string> retained;
  for (const auto& [resource, file] : o.dumps) retained.insert(resource);
  // Each --out with what it writes: the graph's first output, or for an .exr its linear source.
  std::vector<std::pair<std::string, std::string>> outs;
  for (const auto& out : o.outs) {
    outs.emplace_back(out, linear_source_of_output(graph, out));
    if (!outs.back().second.empty()) retained.insert(outs.back().second);
  }

  // Model no more than the graph needs: a graph without scene passes (built-in, or user passes with
  // "scene": true) loads no scene.
  const bool needs_scene = std::any_of(graph.passes.begin(), graph.passes.end(), [](const graph::PassDesc& p) {
    const auto* decl = passes::builtin_registry().find(p.type);
    return (decl && decl->needs_scene) || (p.user && p.user->scene);
  });
  std::shared_ptr<const scene::Scene> scene;
  if (needs_scene) scene = std::make_shared<const scene::Scene>(load_scene_and_warn(o.scene, o.stage));

  vk::Context vk(device_options(o.device, o.validate));
  shader::ShaderCompiler& shaders = shader::process_shader_compiler();
  graph::Executor executor(vk, shaders, passes::builtin_registry());
  executor.set_scene(scene);
  if (o.frame_timeout_s > 0) executor.set_frame_timeout(o.frame_timeout_s, o.frame_timeout_s);
  const graph::ConfigureOptions options{
      .retained = retained, .memory_limit_bytes = o.memory_limit_mib << 20, .reuse_unchanged_passes = o.orbit_degrees != 0.0f};
  configure_at_rest(o.graph, graph, declared, still, [&](const graph::GraphDesc& g) { executor.configure(g, o.width, o.height, options); });
  for (const auto& warning : executor.plan().warnings) std::cerr << "caustica: warning: " << warning << "\n";
  const auto& planned = executor.plan().passes;
  if (o.accumulate && std::none_of(planned.begin(), planned.end(), [](const graph::PlannedPass& p) { return p.type == "accumulate"; })) {
    throw InputError(o.graph +
                     ": --accumulate needs an accumulate pass that runs on this scene (graphs/caustics_progressive.json has "
                     "one); --frames N runs frames without averaging them");
  }
  check_dumps(executor.plan(), o);
  const graph::RunRecord run = run_frames(executor, scene.get(), o, vk);

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

const char* kAtRestHelp =
    "\nThe graph's parameters are those at rest, as the viewer's once nothing moves: each one's first\n"
    "\"while_still\" value (caustics_progressive: distance=ray_query, exact photons), except those --set\n"
    "sets; on a device that cannot run them (no VK_KHR_ray_query) the declared values, with a note.\n"
    "--moving keeps the declared values (those while moving).\n";

}  // namespace

RenderOptions parse_render(Args& args, bool trace) {
  RenderOptions o;
  std::vector<std::string> counts;  // --frames, --accumulate, --seconds: one says how long to run
  render_flags(o, trace, counts).parse(args);
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

int cmd_render(Args& args) {
  if (args.wants_help()) {
    RenderOptions o;
    std::vector<std::string> counts;
    std::cout << "usage: caustica render [options]\n\nRenders frames of a graph headless and writes its first output.\n"
                 "With no options: the default graph at 1280x720 to caustica.png.\n"
              << kAtRestHelp << "\noptions:\n"
              << render_flags(o, false, counts).help();
    return 0;
  }
  return run_render(parse_render(args, false), false);
}

int cmd_trace(Args& args) {
  if (args.wants_help()) {
    RenderOptions o;
    std::vector<std::string> counts;
    std::cout << "usage: caustica trace --out TRACE.json [--frames N] [render options]\n\n"
                 "Runs frames and writes Chrome trace-event JSON that Perfetto (ui.perfetto.dev) and chrome://tracing\n"
                 "open: a GPU track with each pass from timestamps, a CPU track with recording times, one counter\n"
                 "track per pass counter, and the graph and pass names as metadata.\n"
              << kAtRestHelp << "\noptions:\n"
              << render_flags(o, true, counts).help();
    return 0;
  }
  return run_render(parse_render(args, true), true);
}

}  // namespace caustica::cli
