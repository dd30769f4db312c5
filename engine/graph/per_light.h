#pragma once
// Per-light and per-view passes and resources ("for_each": "light" or "caustic_view" in a graph
// file). Before anything else the compiler makes one instance of each per light of the scene, or
// per caustic view (scene::caustic_views: view K < lights is light K's, a point light's further
// cube faces follow), named "NAME#K" for light or view K:
// - in an instance, "$light" and "light.index" are K, and "light.NAME" is the scene's
//   "scene.lightK.NAME" (light.spot, light.point, light.refractors, ...; Scene::expression_values),
//   or for a view's "scene.causticK.NAME" (its light's, and light.light, light.face), so that its
//   "enabled" culls it per light and its resources are sized per light;
// - an instance's ports bound to a per-light resource bind that light's instance of it (a view's
//   instance, its light's); a per-view resource, that view's;
// - a pass that runs once reads a per-light or per-view resource through a per-light port
//   (PortDecl::per_light): element K ("PORT[K]" in PlannedPass::ports) is instance K.
// The graph file keeps what the user wrote; only the compiled plan holds the instances, whose
// expressions stay as written (so that a message about one quotes the user's text) and are read
// through light_scope.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "graph/expression.h"
#include "graph/graph_desc.h"

namespace caustica::graph {

inline constexpr std::string_view kForEachLight = "light";
inline constexpr std::string_view kForEachCausticView = "caustic_view";

// "shadow#2": instance 2 of per-light (or per-view) pass or resource "shadow".
std::string light_instance(std::string_view name, uint32_t index);
// The pass or resource of the file that `name` is an instance of ("shadow#2" -> "shadow"); `name`
// itself where it is none.
std::string_view instance_of(std::string_view name);
// "caustics[2]": element 2 of a per-light port.
std::string port_element(std::string_view port, uint32_t element);
// The port of "caustics[2]" and 2, or the name and -1 where it names no element.
std::pair<std::string, int> split_port_element(std::string_view key);

// `scope` as instance `instance` reads it: light.index is its index (Instance::index), light.NAME
// the scene's scene.lightK.NAME or scene.causticK.NAME, every other name as `scope` has it;
// `scope` itself for none (made once).
ExpressionScope light_scope(ExpressionScope scope, Instance instance);
// `text` with the instance's names written out ("light.view" -> "scene.light2.view"): how a plan
// shows what an instance read.
std::string as_read_by_light(std::string_view text, Instance instance);

// Whether the graph declares a per-light pass or resource.
bool has_per_light(const GraphDesc& graph);

// The graph with each per-light pass and resource instantiated for lights 0 .. lights-1, and each
// per-view one for the caustic views, view K being light view_lights[K]'s (above); throws
// InputError at the file's pointer where the parts do not fit together (a pass that runs once
// writing a per-light resource, an output that is one, a per-light pass reading a per-view resource).
GraphDesc expand_per_light(const GraphDesc& graph, uint32_t lights, const std::vector<uint32_t>& view_lights);

}  // namespace caustica::graph
