// The caustica command: picks the subcommand. render.cpp has render and trace, validate.cpp,
// graph_cmd.cpp, reference.cpp (reference and merge) and compare.cpp the others, bench*.cpp the
// benchmarks, view.cpp view and edit; flags.h declares each command's flags as a table.
// Exit codes: 0 ok, 1 invalid input, 2 usage, 3 device or runtime failure (README).
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <string>
#include <utility>
#include <vector>

#include "cli.h"
#include "core/error.h"
#include "core/interrupt.h"
#include "core/paths.h"
#include "core/suggest.h"
#include "io/json_document.h"
#include "shader/shader_disk_cache.h"
#include "vk/context.h"

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
  for (const auto& [name, description] : listed)
    std::cout << "  " << name << std::string(width + 2 - name.size(), ' ') << description << "\n";
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
  install_interrupt_handlers();
  try {
    if (argc < 2) {
      Args none(argc, argv, 1);
      return cmd_render(none);
    }
    std::string command = argv[1];
    Args args(argc, argv, 2);
    if (command == "--help" || command == "-h" || command == "help") {
      std::cout << kMainHelp << "data folder (graphs, shaders, scenes): " << data_dir().string() << " (CAUSTICA_DATA_DIR overrides)\n";
      const auto cache = shader::ShaderDiskCache::default_folder();
      std::cout << "compiled shaders kept in: " << (cache ? cache->string() : "nowhere")
                << " (CAUSTICA_SHADER_CACHE_DIR overrides; off keeps none)\n";
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
  } catch (const Interrupted& e) {
    std::cerr << "caustica: interrupted (signal " << e.signal() << ")\n";
    return 128 + e.signal();
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
