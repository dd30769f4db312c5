// caustica graph: plans, Graphviz, the schema, new defaults and the parameter table of graph files.
#include <cstdio>
#include <iostream>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "builtin_passes.h"
#include "cli.h"
#include "core/error.h"
#include "core/paths.h"
#include "core/suggest.h"
#include "flags.h"
#include "graph/compiler.h"
#include "graph/per_light.h"
#include "graph/report.h"
#include "graph/schema.h"
#include "io/files.h"
#include "io/json_reader.h"
#include "scene/acceleration.h"
#include "scene/bvh.h"
#include "scene/scene.h"

namespace caustica::cli {
namespace {

// What each light of the scene got (graph plan --scene S): what it reaches, its shadow and caustic
// views, the instances of the graph's per-light passes planned for it, and why the others are not.
nlohmann::ordered_json lights_report(const scene::Scene& scene, const graph::Plan& plan) {
  using json = nlohmann::ordered_json;
  const std::map<std::string, double> values = scene.expression_values();
  auto view_of = [](const scene::Light& light, const scene::View& view, float extent) {
    if (light.type == scene::LightType::directional) return json{{"half_side", extent}};
    return json{{"fov_degrees", view.fov_y_degrees}};
  };
  json lights = json::array();
  for (uint32_t k = 0; k < scene.lights.size(); ++k) {
    const scene::Light& light = scene.lights[k];
    const std::string prefix = "scene.light" + std::to_string(k) + ".";
    json entry{{"light", k},
               {"type", scene::light_type_name(light.type)},
               {"reaches", {{"objects", values.at(prefix + "objects")}, {"refractors", values.at(prefix + "refractors")}}}};
    if (light.type != scene::LightType::point) entry["shadow_view"] = view_of(light, light.view, light.extent);
    if (light.caustic_faces != 0) {
      // A point light among its refractors: a caustic view per cube face that holds one.
      static const char* const kFaces[] = {"+x", "-x", "+y", "-y", "+z", "-z"};
      entry["caustic_view"] = view_of(light, light.caustic_view, light.caustic_extent);
      entry["caustic_view"]["cube_faces"] = json::array();
      for (uint32_t face = 0; face < 6; ++face) {
        if (light.caustic_faces & (1u << face)) entry["caustic_view"]["cube_faces"].push_back(kFaces[face]);
      }
    } else if (light.has_caustic_view) {
      entry["caustic_view"] = view_of(light, light.caustic_view, light.caustic_extent);
      entry["caustic_view"]["fitted_to_refractors"] = light.caustic_view_projection() != light.view_projection();
    } else {
      entry["caustic_view"] = nullptr;
    }
    const auto of_this_light = [&](const std::string& name) {
      const auto it = plan.instances.find(name);
      return it != plan.instances.end() && it->second.light == static_cast<int>(k);
    };
    entry["passes"] = json::array();
    for (const auto& pass : plan.passes) {
      if (of_this_light(pass.name)) entry["passes"].push_back(pass.name);
    }
    entry["not_planned"] = json::object();
    for (const auto& [name, enabled] : plan.disabled_by) {
      if (of_this_light(name)) entry["not_planned"][name] = "disabled: " + enabled + " is 0";
    }
    for (const auto& name : plan.culled) {
      if (of_this_light(name)) entry["not_planned"][name] = "culled: nothing planned reads what it writes";
    }
    lights.push_back(std::move(entry));
  }
  return lights;
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

// graph set's flags: NAME=VALUE assignments go to the graph file, or to --out.
FlagTable set_table(std::string& out) {
  return {text_flag("--out", "NEW.json", "write the graph with the new defaults here, not into FILE", out)};
}

}  // namespace

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
    std::string out;
    std::cout << help << "\noptions of 'graph set':\n"
              << set_table(out).help()
              << "\noptions of 'graph plan' and 'graph dot': as render's (caustica render --help); they compile the graph's\n"
                 "parameters as declared (with --set), not render's values at rest\n";
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
    set_table(out).parse(args, [&sets](const std::string& assignment) { sets.push_back(assignment); });
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
  options.tracer = graph::tracer_from_environment();  // --tracer; without a device, auto means ray queries
  std::optional<scene::Scene> scene;
  if (o.scene_given) {
    scene = load_scene_and_warn(o.scene, o.stage);
    options.scene_values = scene->expression_values();
  }
  graph::Plan plan = graph::compile_graph(graph, passes::builtin_registry(), options);
  if (what == "dot") {
    std::cout << graph::plan_to_dot(plan);
    return 0;
  }
  nlohmann::json out = graph::plan_to_json(plan);
  if (scene) out["lights"] = lights_report(*scene, plan);
  if (plan.tracer == graph::Tracer::compute) {
    if (!scene) scene = load_scene_and_warn(o.scene, o.stage);
    // The compute tracer's BVH is built on the host: its size here is the device's, to the byte.
    const scene::TracerBvh bvh = scene::build_scene_bvh(*scene, std::vector<uint32_t>(scene->objects.size(), 0));
    out["memory"]["bvh"] = {
        {"scene", o.scene}, {"triangles", bvh.triangle_count}, {"nodes", bvh.node_count}, {"depth", bvh.depth}, {"bytes", bvh.bytes()}};
  } else if (!plan.traced_passes.empty()) {
    if (!scene) scene = load_scene_and_warn(o.scene, o.stage);
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

}  // namespace caustica::cli
