#pragma once
// Per-light passes and resources ("for_each": "light" in a graph file). Before anything else the
// compiler makes one instance of each per light of the scene, named "NAME#K" for light K:
// - in an instance, "$light" and "light.index" are K, and "light.NAME" is the scene's
//   "scene.lightK.NAME" (light.spot, light.point, light.refractors, ...; Scene::expression_values),
//   so that its "enabled" culls it per light and its resources are sized per light;
// - an instance's ports bound to a per-light resource bind that light's instance of it;
// - a pass that runs once reads a per-light resource through a per-light port (PortDecl::per_light):
//   element K ("PORT[K]" in PlannedPass::ports) is light K's instance.
// The graph file keeps what the user wrote; only the compiled plan holds the instances, whose
// expressions stay as written (so that a message about one quotes the user's text) and are read
// through light_scope.
#include <cstdint>
#include <string>
#include <string_view>

#include "graph/expression.h"
#include "graph/graph_desc.h"

namespace caustica::graph {

inline constexpr std::string_view kForEachLight = "light";

// "shadow#2": light 2's instance of per-light pass or resource "shadow".
std::string light_instance(std::string_view name, uint32_t light);
// The pass or resource of the file that `name` is an instance of ("shadow#2" -> "shadow"); `name`
// itself where it is none.
std::string_view instance_of(std::string_view name);
// The light of an instance ("shadow#2" -> 2), or -1 for a name that is none.
int instance_light(std::string_view name);
// "caustics[2]": element 2 of a per-light port.
std::string port_element(std::string_view port, uint32_t element);
// The port of "caustics[2]" and 2, or the name and -1 where it names no element.
std::pair<std::string, int> split_port_element(std::string_view key);

// `scope` as light `light`'s instance reads it: light.index is the light, light.NAME the scene's
// scene.lightK.NAME, every other name as `scope` has it; `scope` itself for -1 (made once).
ExpressionScope light_scope(ExpressionScope scope, int light);
// `text` with light `light`'s names written out ("light.view" -> "scene.light2.view"): how a plan
// shows what an instance read.
std::string as_read_by_light(std::string_view text, uint32_t light);

// Whether the graph declares a per-light pass or resource.
bool has_per_light(const GraphDesc& graph);

// The graph with each per-light pass and resource instantiated for lights 0 .. lights-1 (above);
// throws InputError at the file's pointer where the per-light parts do not fit together (a pass
// that runs once writing a per-light resource, an output that is one).
GraphDesc expand_per_light(const GraphDesc& graph, uint32_t lights);

}  // namespace caustica::graph
