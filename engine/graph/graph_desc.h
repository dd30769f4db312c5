#pragma once
// A graph file as written: what the user said, with the pointer of every part for messages.
// Structural checks happen while loading; meaning (types, ports, order) is the compiler's job.
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "graph/instance.h"
#include "graph/pass_type.h"
#include "io/json_document.h"

namespace caustica::graph {

struct GraphParameter {
  ParamDecl decl;        // type, default, range, description
  nlohmann::json value;  // the default, or what --set gave
  std::string pointer;
  // "while_moving": the value a viewer's frame budget may use while the camera or a light moves and
  // the frame is still over its budget at a quarter of the window's size (a coarser photon grid,
  // smaller light maps); absent: never lowered.
  std::optional<nlohmann::json> while_moving;
  // "while_still": the value a viewer uses once nothing has moved for a moment, where the user has
  // not set the parameter in its panel and the device runs the graph with it (exact photons accumulating in
  // place of image-space ones); empty: the value as set. A list in the file gives cheaper values after
  // the first (a smaller slice of the photon grid a frame), which the viewer takes in turn while its
  // refining frames are over the frame budget, and back when they fit it (editor::StillLevels).
  std::vector<nlohmann::json> while_still;
};

struct ResourceDesc {
  std::string name;
  ResourceKind kind = ResourceKind::image;
  Format format = Format::rgba8;
  std::string width = "output.width";  // expressions
  std::string height = "output.height";
  std::string mips = "1";
  // Array layers; a layered image is read by shaders as an array (image2DArray, sampler2DArray).
  std::string layers = "1";
  std::string size;  // buffers: bytes
  // Read in this resource's place when no enabled pass writes it (a pass disabled for the scene).
  std::string fallback;
  // "fallback": null: when no enabled pass writes it, optional inputs bound to it are left unbound.
  bool fallback_to_nothing = false;
  // "light": one resource per light of the scene, its expressions read per light; "caustic_view":
  // one per caustic view (graph/per_light.h).
  std::string for_each;
  Instance instance;  // made by expand_per_light
  std::string pointer;
};

// A user pass's own declarations ("compute", "fullscreen") as written; the compiler checks them
// against the shader (graph/user_pass_type.h).
struct UserPassDesc {
  std::string shader;  // relative to the graph file, or else to the data folder
  std::vector<PortDecl> ports;
  std::vector<std::string> port_pointers;
  std::vector<ParamDecl> params;
  std::vector<std::string> param_pointers;
  std::string dispatch_port;          // compute: one invocation per texel of this port's image
  std::vector<std::string> dispatch;  // or invocations along x, y, z: expressions of sizes and parameters
  std::string dispatch_pointer;
  bool scene = false;  // binds the scene at bindings 0..2 (shaders/scene/scene.glsl's SCENE_* blocks)
  // Named counters the shader adds to, as a built-in pass's (PassSetup::add_counter): slot k of its
  // counter buffer is the k-th, a uint for a count, a float for a sum.
  struct Counter {
    std::string name;
    bool sum = false;
  };
  std::vector<Counter> counters;
  std::string counters_pointer;
};

struct PassDesc {
  std::string name;
  std::string type;
  nlohmann::json params = nlohmann::json::object();  // literals or "$parameter" references
  std::map<std::string, std::string> inputs;         // port -> resource
  std::map<std::string, std::string> outputs;
  std::vector<std::string> after;  // explicit ordering for resources written by several passes
  std::string enabled = "1";       // an expression (true/false in the file are 1/0); the pass runs when non-zero
  std::string for_each;            // "light" or "caustic_view": one instance per light or caustic view (graph/per_light.h)
  Instance instance;               // made by expand_per_light
  std::string pointer;
  std::optional<UserPassDesc> user;  // a "compute" or "fullscreen" pass
};

struct GraphDesc {
  JsonDocument doc;
  std::string name;
  std::string description;
  std::vector<GraphParameter> parameters;
  std::vector<ResourceDesc> resources;
  std::vector<PassDesc> passes;
  std::vector<std::string> outputs;  // the first one is what `render --out` writes
  // The graph's linear HDR result (before its tone map), which `render --out F.exr` writes; empty
  // where the graph does not say.
  std::string linear_output;

  const ResourceDesc* find_resource(std::string_view name) const;
  const GraphParameter* find_parameter(std::string_view name) const;
  LocatedError error(std::string_view pointer, const std::string& message) const { return doc.error(pointer, message); }
};

GraphDesc load_graph_file(const std::string& path);
GraphDesc load_graph(JsonDocument doc);

// Applies "name=value" overrides from --set; the value is parsed as JSON, or taken as a string.
// Throws InputError for an unknown name (with a suggestion) or a value of the wrong type or range;
// messages begin with `command` (the flag or command that gave the assignments).
void apply_overrides(GraphDesc& graph, const std::vector<std::string>& assignments, std::string_view command = "--set");

// The values at rest (a headless render, the viewer once nothing moves): each parameter's
// while_still value of `level` (its last where it lists fewer), except the parameters named in
// `kept` (those the user set). Returns "NAME=VALUE" for each one changed, for a note; empty where
// the graph declares none.
std::vector<std::string> apply_still_values(GraphDesc& graph, const std::set<std::string>& kept, size_t level = 0);

// The graph file's text with each parameter's "default" replaced by its current value (what --set
// or the viewer changed), and nothing else touched: same keys, order, spacing and comments-free
// layout. Throws InputError when the file changed on disk since it was loaded.
std::string graph_text_with_values(const GraphDesc& graph);

}  // namespace caustica::graph
