#pragma once
// The graph compiler's own parts, shared by the files of its phases and included by nothing else
// (not installed): compiler.cpp runs the phases in order (Compiler::run); compiler_resolve.cpp
// decides the enabled passes and fallbacks, sizes the resources and binds the passes' ports;
// compiler_order.cpp builds the dependency edges, refuses cycles, culls and orders the passes;
// compiler_memory.cpp computes lifetimes and usage and places transient memory (aliasing);
// compiler_barriers.cpp records the barriers.
#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "graph/compiler.h"
#include "graph/expression.h"

namespace caustica::graph::compiler_internal {

std::string mib(uint64_t bytes);

struct Binding {
  const PortDecl* port;
  uint32_t resource;
  std::string pointer;
  std::string key;  // in PlannedPass::ports: the port's name, or "PORT[K]" for element K of a per-light port
};

class Compiler {
 public:
  Compiler(const GraphDesc& graph, const PassRegistry& registry, const CompileOptions& options)
      : graph_(graph), registry_(registry), options_(options) {}

  Plan run();

 private:
  const GraphDesc& graph_;
  const PassRegistry& registry_;
  const CompileOptions& options_;
  Plan plan_;

  // Per pass of the graph file (index = file order); disabled passes keep a slot with decl == nullptr.
  struct Node {
    const PassDesc* desc = nullptr;
    const PassTypeDecl* decl = nullptr;
    nlohmann::json params;
    std::map<std::string, std::string> frame_params;  // PlannedPass::frame_params
    bool refused_binding = false;                     // a binding had an error: no "not connected" after it
    std::vector<Binding> bindings;
    std::vector<uint32_t> successors;
    std::vector<uint32_t> predecessors;
  };
  std::vector<Node> nodes_;
  // The errors of independent parts (resources, passes, parameters, ports), reported together.
  mutable ErrorList errors_;
  std::vector<std::vector<uint32_t>> writers_;  // per resource, node indices
  std::vector<std::vector<uint32_t>> readers_;
  std::vector<bool> enabled_;                    // per pass of the file
  std::map<std::string, std::string> redirect_;  // resource no enabled pass writes -> its fallback
  std::vector<uint32_t> order_;                  // node indices in execution order

  // compiler_resolve.cpp: enabled passes and fallbacks, parameters and expressions, resource sizes,
  // pass types, parameters and bindings.
  std::string redirected(const std::string& name) const;
  void decide_enabled_and_fallbacks();
  std::vector<std::string> resource_names_of_file() const;
  // The names an expression reads; a per-light or per-view instance's through graph::light_scope.
  ExpressionScope scope(Instance instance = {}) const;
  double evaluate(const std::string& text, const std::string& pointer, Instance instance = {}) const;
  uint32_t extent(const std::string& text, const std::string& pointer, const char* what, const ResourceDesc& resource) const;
  void size_resources();
  std::vector<std::string> resource_names() const;
  // Every declared parameter's value (for the first frame), and in `frame_params` those that are
  // expressions of the frame block; warns of numbers written in the old form, as strings.
  nlohmann::json resolve_params(const PassDesc& pass, const PassTypeDecl& decl, std::map<std::string, std::string>& frame_params);
  void bind_section(Node& node, const std::map<std::string, std::string>& section, bool outputs);
  uint32_t history_resource(const std::string& name, const std::string& source_name, const std::string& pointer);
  bool wanted(const std::string& resource) const;
  void check_format(const PortDecl& port, const PlannedResource& r, const PassDesc& pass, const std::string& pointer) const;
  // A user compute pass's invocations, from its "dispatch" expressions and resolved parameters.
  void resolve_dispatch(const PassDesc& pass, const nlohmann::json& params, const std::map<std::string, std::string>& frame_params,
                        UserShader& shader) const;
  void resolve_passes();

  // compiler_order.cpp: dependencies, cycles, writer order, culling and the execution order.
  int node_index(std::string_view name) const;
  void add_edge(uint32_t from, uint32_t to);
  void build_edges();
  void find_cycle() const;
  bool reaches(uint32_t from, uint32_t to) const;
  void check_writer_order() const;
  std::vector<uint32_t> least_memory_order(const std::vector<bool>& live) const;
  void warn_of_flat_cube_maps(const Node& node);
  void warn_of_undrawn_faces(const std::set<int>& drawn_views);
  void cull_and_order();
  void choose_tracer();

  // compiler_dependencies.cpp: what each pass depends on; what a plan that reuses passes keeps.
  // A pass's "light" parameter as the scene has it: the last light where it has fewer.
  int scene_light(int light) const;
  uint32_t own_lights(const Node& node) const;
  void find_dependencies();
  // In a plan that reuses unchanged passes: PlannedPass::refines and Plan::refines_apart.
  void find_refining_passes();
  // In a plan that reuses unchanged passes: PlannedPass::result_id, running_id and showing_id.
  void find_result_identities();
  // Each pass's identity by the order (its name, type, parameters, ports and what it reads);
  // `running`: without the sampling-only parameters (ParamDecl::sampling_only).
  std::vector<ResultIdentity> result_identities(bool running) const;
  void keep_contents_across_frames();

  // compiler_memory.cpp: lifetimes, usage flags, extent groups and memory placement.
  void compute_lifetimes_and_usage();
  void check_extent_groups() const;
  // Each pass type's own rule (PassTypeDecl::check): every error reported together, the warnings kept.
  void check_pass_rules();
  uint64_t place_in_order(const std::vector<uint32_t>& order, bool tightest);
  void place_memory();

  // compiler_barriers.cpp: barriers and each resource's final state.
  bool memory_overlaps(const PlannedResource& a, const PlannedResource& b) const;
  void record_barriers();
};

}  // namespace caustica::graph::compiler_internal
