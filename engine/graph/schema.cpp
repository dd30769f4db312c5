#include "graph/schema.h"

#include "graph/plan.h"

namespace caustica::graph {
namespace {

using json = nlohmann::ordered_json;

json param_schema(const ParamDecl& p) {
  json s;
  switch (p.type) {
    case ParamType::float_: s["type"] = "number"; break;
    case ParamType::int_: s["type"] = "integer"; break;
    case ParamType::bool_: s["type"] = "boolean"; break;
    case ParamType::choice: s["enum"] = p.choices; break;
  }
  if (p.min) s["minimum"] = *p.min;
  if (p.max) s["maximum"] = *p.max;
  if (p.power_of_two) s["enum"] = powers_of_two_within(p);
  s["default"] = json::parse(p.default_value.dump());
  if (!p.description.empty()) s["description"] = p.description;
  // Any parameter may instead name a graph parameter ("$name"), and a number or flag may be an
  // expression (of the frame block too where the pass reads it every frame).
  json instead =
      p.type == ParamType::choice
          ? json{{"type", "string"}, {"pattern", "^\\$"}}
          : json{{"type", "string"},
                 {"description",
                  std::string("\"$name\" (a graph parameter) or an expression of output.width, output.height, the "
                              "scene's values and the graph's parameters") +
                      (p.per_frame ? ", and of the frame: frame.index, frame.since_reset, frame.jitter_x, frame.jitter_y" : "")}};
  return {{"anyOf", json::array({s, instead})}, {"description", p.description}};
}

json ports_schema(const PassTypeDecl& decl, bool outputs) {
  json props = json::object();
  for (const auto& port : decl.ports) {
    if ((port.access != PortAccess::read) != outputs) continue;
    // An input may read a resource as the previous frame left it: "NAME@previous".
    props[port.name] = {
        {"type", "string"},
        {"description",
         outputs ? port.description : port.description + " (a resource, or \"NAME@previous\": NAME as the last frame left it)"}};
  }
  return {{"type", "object"}, {"properties", props}, {"additionalProperties", false}};
}

// One "if the type is T then ..." clause per pass type: a built-in type's parameters and ports, or
// for a user pass type, its own "shader", "ports" and "parameters" (which the compiler checks).
json per_type_schemas(const PassRegistry& registry) {
  json per_type = json::array();
  for (const auto& [name, decl] : registry.types()) {
    if (decl.user_kind != UserShaderKind::none) {
      per_type.push_back({{"if", {{"properties", {{"type", {{"const", name}}}}}}},
                          {"then", {{"description", decl.description}, {"required", {"shader"}}}},
                          {"else",
                           {{"not",
                             {{"anyOf",
                               {{{"required", {"shader"}}},
                                {{"required", {"ports"}}},
                                {{"required", {"parameters"}}},
                                {{"required", {"dispatch"}}},
                                {{"required", {"scene"}}},
                                {{"required", {"counters"}}}}}}}}}});
      continue;
    }
    json params = json::object();
    for (const auto& p : decl.params) params[p.name] = param_schema(p);
    per_type.push_back({{"if", {{"properties", {{"type", {{"const", name}}}}}}},
                        {"then",
                         {{"description", decl.description},
                          {"properties",
                           {{"params", {{"type", "object"}, {"properties", params}, {"additionalProperties", false}}},
                            {"inputs", ports_schema(decl, false)},
                            {"outputs", ports_schema(decl, true)}}}}}});
  }
  return per_type;
}

// A graph parameter, `with_viewer_values` (a graph's own) or without (a user pass's parameters).
json parameter_schema(bool with_viewer_values) {
  json parameter = {
      {"type", "object"},
      {"required", {"type", "default"}},
      {"properties",
       {{"type", {{"enum", {"float", "int", "bool", "choice"}}}},
        {"default", json::object()},
        {"min", {{"type", "number"}}},
        {"max", {{"type", "number"}}},
        {"power_of_two",
         {{"type", "boolean"},
          {"description", "an int that must be a power of two within min (at least 1) and max, such as a photon grid"}}},
        {"choices", {{"type", "array"}, {"items", {{"type", "string"}}}}},
        {"description", {{"type", "string"}}},
        {"while_moving",
         {{"description",
           "the value a viewer's frame budget may use while the camera or a light moves and a quarter of the window's size is still "
           "over budget"}}},
        {"while_still",
         {{"description",
           "the value a viewer uses once nothing has moved for a moment, unless the user set the parameter or the device cannot run "
           "the graph with it; or a list of values, each cheaper than the one before, that the viewer takes in turn while its refining "
           "frames at rest are over the frame budget"}}}}},
      {"additionalProperties", false}};
  if (!with_viewer_values) {
    for (const char* viewer_only : {"while_moving", "while_still"}) parameter["properties"].erase(viewer_only);
  }
  return parameter;
}

json user_port_schema() {
  return {{"type", "object"},
          {"required", {"access"}},
          {"properties",
           {{"type", {{"enum", {"image", "buffer"}}, {"default", "image"}}},
            {"access", {{"enum", {"read", "write", "read_write"}}}},
            {"usage", {{"enum", {"sampled", "storage", "color_attachment", "uniform"}}}},
            {"formats", {{"type", "array"}, {"items", {{"enum", format_names()}}}}},
            {"extent_group", {{"type", "string"}}},
            {"layers", {{"type", "integer"}, {"minimum", 1}, {"maximum", kMaxImageLayers}}},
            {"description", {{"type", "string"}}}}},
          {"additionalProperties", false}};
}

json resource_schema(const json& expression) {
  return {{"type", "object"},
          {"properties",
           {{"type", {{"enum", {"image", "buffer"}}, {"default", "image"}}},
            {"format", {{"enum", format_names()}}},
            {"width", expression},
            {"height", expression},
            {"mips", expression},
            {"layers", expression},
            {"size", expression},
            {"fallback",
             {{"type", {"string", "null"}},
              {"description",
               "resource read in this one's place when no enabled pass writes it; null leaves optional inputs bound to it unbound"}}},
            {"for_each",
             {{"enum", {"light", "caustic_view"}},
              {"description",
               "one resource per light of the scene, or per caustic view (a light's, or each cube face of a point light among its "
               "refractors), named NAME#K; its expressions may name light.index and light.*"}}},
            {"description", {{"type", "string"}}}}},
          {"additionalProperties", false}};
}

json user_counter_schema() {
  return {{"anyOf", json::array({{{"type", "string"}},
                                 {{"type", "object"},
                                  {"required", {"name"}},
                                  {"properties", {{"name", {{"type", "string"}}}, {"kind", {{"enum", {"count", "sum"}}}}}},
                                  {"additionalProperties", false}}})}};
}

json pass_schema(const PassRegistry& registry, const json& expression) {
  json types = json::array();
  for (const auto& entry : registry.types()) types.push_back(entry.first);
  return {
      {"type", "object"},
      {"required", {"name", "type"}},
      {"properties",
       {{"name", {{"type", "string"}}},
        {"type", {{"enum", types}}},
        {"params", {{"type", "object"}}},
        {"inputs", {{"type", "object"}}},
        {"outputs", {{"type", "object"}}},
        {"after", {{"type", "array"}, {"items", {{"type", "string"}}}}},
        {"enabled",
         {{"type", {"boolean", "string"}},
          {"description", "true, false, or an expression such as \"scene.refractors\"; the pass runs when it is non-zero"}}},
        {"for_each",
         {{"enum", {"light", "caustic_view"}},
          {"description",
           "one instance per light of the scene, named NAME#K: \"$light\" and light.index are K, light.NAME the scene's "
           "scene.lightK.NAME (spot, point, directional, objects, refractors); its per-light resources are light K's. "
           "\"caustic_view\": one per caustic view K (light K's for K below the lights, then a point light's further cube "
           "faces), light.NAME its light's (scene.causticK.NAME, with light.light and light.face)"}}},
        {"description", {{"type", "string"}}},
        {"shader", {{"type", "string"}, {"description", "compute and fullscreen: the .comp or .frag file, relative to the graph file"}}},
        {"ports",
         {{"type", "object"},
          {"description", "compute and fullscreen: the ports, each bound to the shader's binding (or fragment output) of its name"},
          {"additionalProperties", user_port_schema()}}},
        {"parameters",
         {{"type", "object"},
          {"description",
           "compute and fullscreen: the parameters, each a member of the shader's push-constant block or of its uniform block Params"},
          {"additionalProperties", parameter_schema(false)}}},
        {"dispatch",
         {{"description", "compute: a port whose image it covers (one invocation a texel), or [x, y, z] invocations"},
          {"anyOf", json::array({{{"type", "string"}}, {{"type", "array"}, {"minItems", 1}, {"maxItems", 3}, {"items", expression}}})}}},
        {"scene", {{"type", "boolean"}, {"description", "compute and fullscreen: the scene at bindings 0..2 (scene/scene.glsl)"}}},
        {"counters",
         {{"type", "array"},
          {"description",
           "compute and fullscreen: named counters (--stats, trace) that the shader adds to at their index in its counter buffer "
           "(uint counters[] for a count, float sums[] for a sum)"},
          {"items", user_counter_schema()}}}}},
      {"additionalProperties", false},
      {"allOf", per_type_schemas(registry)}};
}

}  // namespace

json graph_schema_json(const PassRegistry& registry) {
  const json expression = {{"type", {"string", "integer"}},
                           {"description", "a number or an expression of output.width, output.height and graph parameters"}};
  return {
      {"$schema", "http://json-schema.org/draft-07/schema#"},
      {"title", "caustica render graph"},
      {"description", "Generated by 'caustica graph schema'; do not edit by hand."},
      {"type", "object"},
      {"required", {"resources", "passes", "outputs"}},
      {"properties",
       {{"$schema", {{"type", "string"}}},
        {"name", {{"type", "string"}}},
        {"description", {{"type", "string"}}},
        {"parameters", {{"type", "object"}, {"additionalProperties", parameter_schema(true)}}},
        {"resources", {{"type", "object"}, {"additionalProperties", resource_schema(expression)}}},
        {"passes", {{"type", "array"}, {"minItems", 1}, {"items", pass_schema(registry, expression)}}},
        {"outputs", {{"type", "array"}, {"minItems", 1}, {"items", {{"type", "string"}}}}},
        {"linear_output",
         {{"type", "string"}, {"description", "the graph's linear HDR result (before its tone map), which `render --out F.exr` writes"}}},
        {"editor", {{"type", "object"}, {"description", "the graph editor's layout (pass positions); the engine ignores it"}}}}},
      {"additionalProperties", false}};
}

}  // namespace caustica::graph
