// caustica validate: graphs, scenes and model files checked without a device.
#include <filesystem>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "builtin_passes.h"
#include "cli.h"
#include "core/error.h"
#include "core/paths.h"
#include "flags.h"
#include "graph/compiler.h"
#include "io/json_document.h"
#include "scene/scene.h"

namespace caustica::cli {
namespace {

// validate takes graphs and scenes alike: a bundled one by name is either.
std::string find_graph_or_scene(const std::string& given) {
  for (const char* folder : {"graphs", "scenes"}) {
    const std::string found = find_data_file(given, folder);
    if (std::filesystem::exists(found)) return found;
  }
  return given;
}

// A scene's warnings (its warnings name their files), with the plan's on stdout.
void print_warnings(const scene::Scene& scene) {
  for (const auto& warning : scene.warnings) std::cout << "warning: " << warning << "\n";
}

}  // namespace

int cmd_validate(Args& args) {
  std::vector<std::string> files;
  std::string scene_file;
  bool stage = true;
  const FlagTable flags{scene_flag(scene_file, nullptr,
                                   "compile the graphs as for this scene (a model file as render takes it), which\n"
                                   "is checked too"),
                        no_stage_flag(stage)};
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
                 "Exit 0 when every file is valid, 1 otherwise.\n\noptions:\n"
              << flags.help();
    return args.wants_help() ? 0 : 2;
  }
  flags.parse(args, [&files](const std::string& file) { files.push_back(find_graph_or_scene(file)); });
  int status = 0;
  std::map<std::string, double> scene_values = graph::typical_scene_values();
  if (!scene_file.empty()) {
    try {
      const scene::Scene scene = scene::load_scene_file(scene_file, stage);
      scene_values = scene.expression_values();
      print_warnings(scene);
      std::cout << scene_file << ": ok\n";
    } catch (const InputError& e) {
      std::cerr << e.what() << "\n";
      return 1;
    }
  }
  for (const std::string& file : files) {
    try {
      if (scene::is_model_file(file)) {  // a model opened as a scene, as --scene takes it
        print_warnings(scene::load_model_scene(file));
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
        print_warnings(scene::load_scene(doc));
      } else {
        graph::CompileOptions options;
        options.scene_values = scene_values;
        const graph::GraphDesc graph = graph::load_graph(std::move(doc));
        const graph::Plan plan = graph::compile_graph(graph, passes::builtin_registry(), options);
        for (const auto& warning : plan.warnings) std::cout << file << ": warning: " << warning << "\n";
        // A graph that traces with ray queries is valid only where the device it would run on has them.
        if (!plan.traced_passes.empty()) {
          vk::RayQuerySupport support;
          try {
            support = vk::probe_ray_queries("");
          } catch (const DeviceError& e) {
            support = {false, std::string("a Vulkan device (") + e.what() + ")"};
          }
          if (!support.available) {
            options.ray_queries = false;
            options.tracer = graph::tracer_from_environment();
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

}  // namespace caustica::cli
