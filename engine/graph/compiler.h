#pragma once
#include <functional>
#include <map>
#include <set>
#include <string>

#include "graph/graph_desc.h"
#include "graph/plan.h"

namespace caustica::graph {

struct DeviceLimits {
  uint32_t max_image_dimension_2d = 16384;
  uint64_t max_storage_buffer_range = 128ull << 20;  // lavapipe's; docs/lavapipe.md
  uint64_t max_buffer_size = 4ull << 30;
};

using MemoryRequirementsFn = std::function<MemoryRequirements(const PlannedResource&)>;

// A device-independent stand-in for vkGetDevice*MemoryRequirements: tightly packed texels, 4 KiB
// alignment for images and 256 bytes for buffers, any memory type. Used where no device exists.
MemoryRequirements estimate_memory_requirements(const PlannedResource& resource);

struct CompileOptions {
  uint32_t output_width = 1280;
  uint32_t output_height = 720;
  DeviceLimits limits;
  uint64_t memory_limit_bytes = 1536ull << 20;  // the engine's own limit; lavapipe enforces none
  std::set<std::string> retained;               // resources kept whole to the end of the frame (--dump)
  bool alias = true;                            // share memory between disjoint lifetimes
  // Keep what passes that do not depend on the frame write, so that the executor can skip them
  // while their dependencies are unchanged (the viewer and editor; benchmarks measure every pass).
  bool reuse_unchanged_passes = false;
  MemoryRequirementsFn memory_requirements = estimate_memory_requirements;
  // What the scene offers expressions ("scene.refractors", "scene.lights", "scene.objects",
  // "scene.dispersive", "scene.diagonal", "scene.ray_epsilon"): a pass's "enabled" can depend on it. Empty when there
  // is no scene.
  std::map<std::string, double> scene_values;
  // Whether the device has ray queries, and if not what it lacks (for the message): a plan that
  // traces (PassTypeDecl::traces_scene) then takes the compute tracer, and one that must have ray
  // queries is refused. Device-less tools that cannot ask a device leave it true.
  bool ray_queries = true;
  std::string ray_queries_missing;
  // The tracer asked for (render's --tracer, CAUSTICA_TRACER); unset: ray queries where the device
  // has them (on lavapipe as fast as the compute tracer, on a GPU with hardware for them faster:
  // docs/benchmarks.md), else the compute tracer.
  std::optional<Tracer> tracer;
};

// The scene values `caustica validate` and `graph plan` assume without a scene file.
std::map<std::string, double> typical_scene_values();

// Validates and compiles; throws InputError naming the file, line and JSON pointer of the problem.
Plan compile_graph(const GraphDesc& graph, const PassRegistry& registry, const CompileOptions& options);

}  // namespace caustica::graph
