// compile_graph: the compiler's phases in order, each in a file of its own (compiler_internal.h).
#include "graph/compiler.h"

#include <algorithm>
#include <sstream>
#include <vector>

#include "graph/compiler_internal.h"
#include "graph/per_light.h"

namespace caustica::graph {

MemoryRequirements estimate_memory_requirements(const PlannedResource& resource) {
  if (resource.kind == ResourceKind::buffer) return {(resource.buffer_size + 255) & ~uint64_t{255}, 256, ~0u};
  uint64_t bytes = 0;
  uint64_t w = resource.width;
  uint64_t h = resource.height;
  for (uint32_t level = 0; level < resource.mips; ++level) {
    bytes += w * h * resource.layers * format_info(resource.format).bytes_per_texel;
    w = std::max<uint64_t>(1, w / 2);
    h = std::max<uint64_t>(1, h / 2);
  }
  return {(bytes + 4095) & ~uint64_t{4095}, 4096, ~0u};
}

namespace compiler_internal {

std::string mib(uint64_t bytes) {
  std::ostringstream out;
  out.precision(1);
  out << std::fixed << static_cast<double>(bytes) / (1024.0 * 1024.0) << " MiB";
  return out.str();
}

Plan Compiler::run() {
  plan_.graph_name = graph_.name;
  plan_.graph_path = graph_.doc.path();
  plan_.output_width = options_.output_width;
  plan_.output_height = options_.output_height;
  decide_enabled_and_fallbacks();
  size_resources();
  resolve_passes();
  build_edges();
  find_cycle();
  check_writer_order();
  cull_and_order();
  choose_tracer();
  find_dependencies();
  compute_lifetimes_and_usage();
  check_extent_groups();
  check_pass_rules();
  place_memory();
  record_barriers();
  keep_contents_across_frames();
  return std::move(plan_);
}

}  // namespace compiler_internal

std::map<std::string, double> typical_scene_values() {
  return {{"scene.refractors", 1},         {"scene.lights", 1},         {"scene.objects", 2},          {"scene.dispersive", 0},
          {"scene.diagonal", 10},          {"scene.ray_epsilon", 1e-3}, {"scene.surface_layers", 0},   {"scene.layer_textures", 0},
          {"scene.surface_textures", 0},   {"scene.light0.view", 1},    {"scene.light0.spot", 1},      {"scene.light0.point", 0},
          {"scene.light0.directional", 0}, {"scene.light0.objects", 2}, {"scene.light0.refractors", 1}};
}

namespace {
// The scene's values with each caustic view's light's values as the view's own (scene.causticK.NAME
// from scene.lightL.NAME where the scene gives it no value of that name: the scene gives a view its
// .light, .face and .view). Values without views (a test's own) have one view per light, its light's.
std::map<std::string, double> with_caustic_views(std::map<std::string, double> values, uint32_t lights) {
  if (!values.count("scene.caustic_views")) {
    values["scene.caustic_views"] = lights;
    for (uint32_t light = 0; light < lights; ++light) {
      values["scene.caustic" + std::to_string(light) + ".light"] = light;
      values["scene.caustic" + std::to_string(light) + ".face"] = -1;
    }
  }
  const auto views = static_cast<uint32_t>(std::clamp(values.at("scene.caustic_views"), 0.0, 1024.0));
  for (uint32_t view = 0; view < views; ++view) {
    const std::string to = "scene.caustic" + std::to_string(view) + ".";
    const auto light = values.find(to + "light");
    if (light == values.end()) continue;
    const std::string from = "scene.light" + std::to_string(static_cast<int>(light->second)) + ".";
    // Keys of "scene.caustic" sort before "scene.light": the insertions leave the walk's iterators be.
    for (auto it = values.lower_bound(from); it != values.end() && it->first.starts_with(from); ++it)
      values.try_emplace(to + it->first.substr(from.size()), it->second);
  }
  return values;
}

// The light of each caustic view (scene.causticK.light).
std::vector<uint32_t> view_lights(const std::map<std::string, double>& values, uint32_t lights) {
  std::vector<uint32_t> out;
  for (uint32_t view = 0; view < static_cast<uint32_t>(std::clamp(values.at("scene.caustic_views"), 0.0, 1024.0)); ++view) {
    const auto light = values.find("scene.caustic" + std::to_string(view) + ".light");
    out.push_back(light == values.end() ? view
                                        : static_cast<uint32_t>(std::clamp(light->second, 0.0, double(lights > 0 ? lights - 1 : 0))));
  }
  return out;
}
}  // namespace

Plan compile_graph(const GraphDesc& graph, const PassRegistry& registry, const CompileOptions& options) {
  // Without a scene (a device-less check), the typical scene's one light.
  const auto lights = options.scene_values.find("scene.lights");
  const double count = lights == options.scene_values.end() ? 1.0 : lights->second;
  const auto light_count = static_cast<uint32_t>(std::clamp(count, 0.0, 64.0));
  CompileOptions per_light = options;
  per_light.scene_values = with_caustic_views(options.scene_values, light_count);
  if (!has_per_light(graph)) return compiler_internal::Compiler(graph, registry, per_light).run();
  const GraphDesc expanded = expand_per_light(graph, light_count, view_lights(per_light.scene_values, light_count));
  // A per-light resource kept by its own name is light 0's (Plan::resolve reads it so).
  per_light.retained.clear();
  for (const std::string& name : options.retained) {
    const bool follows_lights = std::any_of(graph.resources.begin(), graph.resources.end(),
                                            [&](const ResourceDesc& r) { return r.name == name && !r.for_each.empty(); });
    per_light.retained.insert(follows_lights ? light_instance(name, 0) : name);
  }
  return compiler_internal::Compiler(expanded, registry, per_light).run();
}

}  // namespace caustica::graph
