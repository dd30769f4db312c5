// The graph compiler's ordering phases (compiler_internal.h): the dependency edges (writers before
// readers, "after"), cycles and unordered writers refused with their messages, the passes that
// nothing needs culled, and the execution order with the least peak of live transient memory.
#include <algorithm>
#include <map>
#include <queue>
#include <set>

#include "core/suggest.h"
#include "graph/compiler_internal.h"

namespace caustica::graph::compiler_internal {

// ---- dependencies --------------------------------------------------------------------------

int Compiler::node_index(std::string_view name) const {
  for (size_t i = 0; i < nodes_.size(); ++i) {
    if (nodes_[i].desc->name == name) return static_cast<int>(i);
  }
  return -1;
}

void Compiler::add_edge(uint32_t from, uint32_t to) {
  auto& s = nodes_[from].successors;
  if (std::find(s.begin(), s.end(), to) != s.end()) return;
  s.push_back(to);
  nodes_[to].predecessors.push_back(from);
}

void Compiler::build_edges() {
  writers_.assign(plan_.resources.size(), {});
  readers_.assign(plan_.resources.size(), {});
  for (uint32_t i = 0; i < nodes_.size(); ++i) {
    for (const auto& b : nodes_[i].bindings) {
      (b.port->access == PortAccess::read ? readers_ : writers_)[b.resource].push_back(i);
    }
  }
  for (uint32_t i = 0; i < nodes_.size(); ++i) {
    if (!nodes_[i].decl) continue;
    for (const auto& b : nodes_[i].bindings) {
      if (b.port->access != PortAccess::read) continue;
      const PlannedResource& read = plan_.resources[b.resource];
      const uint32_t written = read.previous_of != kNoResource ? read.previous_of : b.resource;
      if (!writers_[written].empty()) continue;
      std::string why = "input '" + b.port->name + "' of pass '" + nodes_[i].desc->name + "' reads '" + read.name + "', " +
                        (written != b.resource ? "the previous frame's '" + plan_.resources[written].name + "', " : "") +
                        "which no pass writes";
      for (const auto& other : nodes_) {
        if (other.decl) continue;
        for (const auto& [port, resource] : other.desc->outputs) {
          if (resource == plan_.resources[written].name) why += " (pass '" + other.desc->name + "' that writes it is disabled)";
        }
      }
      if (b.port->optional && written == b.resource) {
        why += "; the input is optional: remove \"" + b.port->name +
               "\" from the pass's \"inputs\" to leave it unbound, or give resource '" + read.name +
               "' \"fallback\": null to unbind it wherever nothing writes it";
      }
      throw graph_.error(b.pointer, why);
    }
  }
  for (uint32_t r = 0; r < plan_.resources.size(); ++r) {
    for (uint32_t w : writers_[r]) {
      for (uint32_t reader : readers_[r]) add_edge(w, reader);
    }
  }
  std::vector<std::string> names;
  for (const auto& n : nodes_) names.push_back(n.desc->name);
  for (uint32_t i = 0; i < nodes_.size(); ++i) {
    if (!nodes_[i].decl) continue;
    const auto& after = nodes_[i].desc->after;
    for (size_t j = 0; j < after.size(); ++j) {
      std::string pointer = nodes_[i].desc->pointer + "/after/" + std::to_string(j);
      int other = node_index(after[j]);
      if (other < 0) throw graph_.error(pointer, "no pass named '" + after[j] + "'" + did_you_mean(after[j], names));
      if (static_cast<uint32_t>(other) == i) throw graph_.error(pointer, "pass '" + after[j] + "' cannot come after itself");
      if (!nodes_[static_cast<size_t>(other)].decl) continue;  // ordering against a disabled pass is moot
      add_edge(static_cast<uint32_t>(other), i);
    }
  }
}

void Compiler::find_cycle() const {
  enum Mark : uint8_t { unseen, open, done };
  std::vector<Mark> mark(nodes_.size(), unseen);
  std::vector<uint32_t> path;
  // Iterative DFS: the stack holds (node, next successor index) so deep graphs cannot overflow.
  for (uint32_t start = 0; start < nodes_.size(); ++start) {
    if (mark[start] != unseen || !nodes_[start].decl) continue;
    std::vector<std::pair<uint32_t, size_t>> stack{{start, 0}};
    mark[start] = open;
    path.assign(1, start);
    while (!stack.empty()) {
      auto& [node, next] = stack.back();
      if (next < nodes_[node].successors.size()) {
        uint32_t succ = nodes_[node].successors[next++];
        if (mark[succ] == open) {
          auto begin = std::find(path.begin(), path.end(), succ);
          std::string text;
          for (auto it = begin; it != path.end(); ++it) text += nodes_[*it].desc->name + " -> ";
          text += nodes_[succ].desc->name;
          throw graph_.error(nodes_[succ].desc->pointer, "cycle: " + text);
        }
        if (mark[succ] == unseen) {
          mark[succ] = open;
          path.push_back(succ);
          stack.emplace_back(succ, 0);
        }
      } else {
        mark[node] = done;
        path.pop_back();
        stack.pop_back();
      }
    }
  }
}

bool Compiler::reaches(uint32_t from, uint32_t to) const {
  std::vector<bool> seen(nodes_.size(), false);
  std::vector<uint32_t> stack{from};
  while (!stack.empty()) {
    uint32_t n = stack.back();
    stack.pop_back();
    if (n == to) return true;
    for (uint32_t s : nodes_[n].successors) {
      if (!seen[s]) {
        seen[s] = true;
        stack.push_back(s);
      }
    }
  }
  return false;
}

void Compiler::check_writer_order() const {
  for (uint32_t r = 0; r < plan_.resources.size(); ++r) {
    const auto& w = writers_[r];
    for (size_t a = 0; a < w.size(); ++a) {
      for (size_t b = a + 1; b < w.size(); ++b) {
        if (!nodes_[w[a]].decl || !nodes_[w[b]].decl) continue;
        if (reaches(w[a], w[b]) || reaches(w[b], w[a])) continue;
        const auto& second = *nodes_[w[b]].desc;
        std::string pointer = second.pointer;
        for (const auto& binding : nodes_[w[b]].bindings) {
          if (binding.resource == r) pointer = binding.pointer;
        }
        throw graph_.error(pointer, "'" + plan_.resources[r].name + "' is written by passes '" + nodes_[w[a]].desc->name + "' and '" +
                                        second.name + "' with no order between them; add \"after\": [\"" + nodes_[w[a]].desc->name +
                                        "\"] to pass '" + second.name + "'");
      }
    }
  }
}

// The execution order: of the orders the edges allow, one with the least peak of live transient
// memory (the lifetimes, and so what aliasing can share, follow from the order), found by a
// search over the sets of passes already run; among the best, file order. Sizes are the
// device-independent estimate, so that every device gets the same order. Graphs with more
// passes than the search takes keep file order.
std::vector<uint32_t> Compiler::least_memory_order(const std::vector<bool>& live) const {
  constexpr size_t kMaxSearchedPasses = 16;
  std::vector<uint32_t> nodes;
  std::vector<int> index(nodes_.size(), -1);
  for (uint32_t i = 0; i < nodes_.size(); ++i) {
    if (!live[i]) continue;
    index[i] = static_cast<int>(nodes.size());
    nodes.push_back(i);
  }
  if (nodes.size() > kMaxSearchedPasses) {
    // Kahn's algorithm, the ready pass that comes first in the file: the plan is stable under
    // unrelated edits.
    std::vector<uint32_t> pending(nodes_.size(), 0), order;
    for (uint32_t i : nodes) {
      for (uint32_t s : nodes_[i].successors) pending[s] += live[s] ? 1 : 0;
    }
    std::priority_queue<uint32_t, std::vector<uint32_t>, std::greater<>> ready;
    for (uint32_t i : nodes) {
      if (pending[i] == 0) ready.push(i);
    }
    while (!ready.empty()) {
      uint32_t n = ready.top();
      ready.pop();
      order.push_back(n);
      for (uint32_t s : nodes_[n].successors) {
        if (live[s] && --pending[s] == 0) ready.push(s);
      }
    }
    return order;
  }
  std::vector<uint32_t> before(nodes.size(), 0);  // bit j: nodes[j] must run first
  for (uint32_t k = 0; k < nodes.size(); ++k) {
    for (uint32_t p : nodes_[nodes[k]].predecessors) {
      if (live[p]) before[k] |= 1u << index[p];
    }
  }
  struct Use {
    uint32_t passes;  // bit k: nodes[k] binds the resource
    uint64_t bytes;
  };
  std::vector<Use> uses;
  for (uint32_t r = 0; r < plan_.resources.size(); ++r) {
    if (!plan_.resources[r].transient) continue;
    uint32_t passes = 0;
    for (uint32_t k = 0; k < nodes.size(); ++k) {
      for (const auto& b : nodes_[nodes[k]].bindings) passes |= b.resource == r ? 1u << k : 0u;
    }
    if (passes != 0) uses.push_back({passes, estimate_memory_requirements(plan_.resources[r]).size});
  }
  // Bytes live while nodes[k] runs after the passes in `done`: what it binds, and what was used
  // before and is still to be used after.
  auto live_bytes = [&](uint32_t done, uint32_t k) {
    const uint32_t after = done | 1u << k;
    uint64_t bytes = 0;
    for (const Use& u : uses) {
      if ((u.passes >> k & 1u) != 0 || ((u.passes & done) != 0 && (u.passes & ~after) != 0)) bytes += u.bytes;
    }
    return bytes;
  };
  const uint32_t all = (1u << nodes.size()) - 1u;
  constexpr uint64_t kUnknown = ~uint64_t{0};
  std::vector<uint64_t> least_peak_after(size_t{1} << nodes.size(), kUnknown);  // of the passes still to run
  auto peak_from = [&](auto& self, uint32_t done) -> uint64_t {
    if (done == all) return 0;
    uint64_t& memo = least_peak_after[done];
    if (memo != kUnknown) return memo;
    uint64_t best = kUnknown;
    for (uint32_t k = 0; k < nodes.size(); ++k) {
      if ((done >> k & 1u) == 0 && (before[k] & ~done) == 0)
        best = std::min(best, std::max(live_bytes(done, k), self(self, done | 1u << k)));
    }
    return memo = best;
  };
  // Kahn's rule (the ready pass first in the file) among the passes that keep the least peak.
  const uint64_t least_peak = peak_from(peak_from, 0);
  std::vector<uint32_t> order;
  for (uint32_t done = 0; done != all;) {
    for (uint32_t k = 0; k < nodes.size(); ++k) {
      if ((done >> k & 1u) == 0 && (before[k] & ~done) == 0 &&
          std::max(live_bytes(done, k), peak_from(peak_from, done | 1u << k)) <= least_peak) {
        order.push_back(nodes[k]);
        done |= 1u << k;
        break;
      }
    }
  }
  return order;
}

// A point light's shadow pass that writes an image of one layer (a graph made for spot lights): the
// map stays cleared and the light unshadowed, which compiles but is rarely what the graph means.
void Compiler::warn_of_flat_cube_maps(const Node& node) {
  for (const auto& b : node.bindings) {
    if (!b.port->cube_layers || b.port->access == PortAccess::read || plan_.resources[b.resource].layers == 6) continue;
    // Without refractors the map is a caustic's receivers, drawn from the caustic view (shadow_map).
    if (!node.params.value("refractors_cast_shadows", true)) continue;
    const int light = scene_light(node.params.value("light", 0));
    const auto point = options_.scene_values.find("scene.light" + std::to_string(light) + ".point");
    if (point == options_.scene_values.end() || point->second == 0.0) continue;
    const std::string message = "pass '" + node.desc->name + "' draws light " + std::to_string(light) + "'s shadow into '" +
                                plan_.resources[b.resource].name + "', which has one layer; light " + std::to_string(light) +
                                " is a point light, whose shadow map needs its six cube faces (\"layers\": \"1 + 5 * light.point\" "
                                "in a per-light graph), so it stays unshadowed";
    plan_.warnings.push_back(graph_.error(node.desc->pointer, message).what());
  }
}

void Compiler::cull_and_order() {
  std::vector<bool> live(nodes_.size(), false);
  std::vector<uint32_t> stack;
  auto keep = [&](uint32_t n) {
    if (!live[n]) {
      live[n] = true;
      stack.push_back(n);
    }
  };
  for (uint32_t i = 0; i < nodes_.size(); ++i) {
    if (!nodes_[i].decl) continue;
    if (nodes_[i].decl->side_effects) keep(i);
    for (const auto& b : nodes_[i].bindings) {
      // What is kept (--dump, the viewer's inspector) is wanted as an output is (Compiler::wanted).
      const PlannedResource& written = plan_.resources[b.resource];
      if (b.port->access != PortAccess::read && (written.output || options_.retained.count(written.name))) keep(i);
    }
  }
  for (size_t i = 0; i < graph_.outputs.size(); ++i) {
    uint32_t r = plan_.outputs[i];
    bool written = std::any_of(writers_[r].begin(), writers_[r].end(), [&](uint32_t w) { return nodes_[w].decl != nullptr; });
    if (!written)
      throw graph_.error("/outputs/" + std::to_string(i), "output '" + plan_.resources[r].name + "' is not written by any enabled pass");
  }
  while (!stack.empty()) {
    uint32_t n = stack.back();
    stack.pop_back();
    for (uint32_t p : nodes_[n].predecessors) keep(p);
    // What a history input reads was written in the last frame: its writers are needed, without
    // an edge (they may come after the reader in the frame).
    for (const auto& b : nodes_[n].bindings) {
      const uint32_t source = plan_.resources[b.resource].previous_of;
      if (source != kNoResource) {
        for (uint32_t w : writers_[source]) keep(w);
      }
    }
  }
  order_ = least_memory_order(live);
  for (uint32_t i = 0; i < nodes_.size(); ++i) {
    if (nodes_[i].decl && !live[i]) plan_.culled.push_back(nodes_[i].desc->name);
  }
  std::set<int> drawn_views;  // the caustic views that planned passes draw from
  for (uint32_t n : order_) {
    const Node& node = nodes_[n];
    PlannedPass pass;
    pass.name = node.desc->name;
    pass.type = node.decl->type;
    pass.pointer = node.desc->pointer;
    pass.decl = node.decl;
    pass.params = node.params;
    pass.frame_params = node.frame_params;
    pass.instance = node.desc->instance;
    if (!pass.frame_params.empty() && plan_.expression_values.empty()) {
      const ExpressionScope compile_time = scope();
      for (const auto& name : compile_time.known_names) plan_.expression_values[name] = *compile_time.lookup(name);
    }
    for (const auto& b : node.bindings) pass.ports[b.key] = b.resource;
    if (pass.decl->traces_scene && pass.decl->traces_scene(pass.params)) plan_.traced_passes.push_back(pass.name);
    if (pass.decl->jitters_camera && pass.decl->jitters_camera(pass.params)) plan_.jitters_camera = true;
    if (pass.decl->uses_light_view && pass.decl->uses_light_view(pass.params)) drawn_views.insert(pass.params.value("light", 0));
    warn_of_flat_cube_maps(node);
    plan_.passes.push_back(std::move(pass));
  }
  warn_of_undrawn_faces(drawn_views);
}

// A point light among its refractors throws its caustics through several cube faces, each a caustic
// view: a graph whose caustic passes are made once, or once per light, draws from its first alone
// and loses the rest of its caustic (said once per light).
void Compiler::warn_of_undrawn_faces(const std::set<int>& drawn_views) {
  const auto value = [&](const std::string& name, double otherwise) {
    const auto it = options_.scene_values.find(name);
    return it == options_.scene_values.end() ? otherwise : it->second;
  };
  std::map<int, std::pair<int, int>> faces;  // light -> its views, and how many of them are drawn
  for (int view = 0; view < static_cast<int>(value("scene.caustic_views", 0)); ++view) {
    const std::string prefix = "scene.caustic" + std::to_string(view) + ".";
    if (value(prefix + "face", -1) < 0) continue;
    auto& [views, drawn] = faces[static_cast<int>(value(prefix + "light", 0))];
    ++views;
    drawn += drawn_views.count(view) ? 1 : 0;
  }
  for (const auto& [light, counts] : faces) {
    if (counts.second == 0 || counts.second == counts.first) continue;
    plan_.warnings.push_back("light " + std::to_string(light) +
                             " is a point light among its refractors, which throws its caustics through " + std::to_string(counts.first) +
                             " cube faces (caustic views), and the graph draws from " + std::to_string(counts.second) +
                             " of them; make its caustic passes and resources \"for_each\": "
                             "\"caustic_view\" (the bundled graphs do) to draw them all");
  }
}

// One tracer for the whole plan: the one asked for, else ray queries where the device has them (or
// a pass must have them), else the compute tracer, which every device runs.
void Compiler::choose_tracer() {
  if (plan_.traced_passes.empty()) return;
  const PlannedPass* first = nullptr;
  const PlannedPass* ray_queries_only = nullptr;
  for (const PlannedPass& pass : plan_.passes) {
    if (std::find(plan_.traced_passes.begin(), plan_.traced_passes.end(), pass.name) == plan_.traced_passes.end()) continue;
    if (!first) first = &pass;
    if (pass.decl->ray_queries_only && !ray_queries_only) ray_queries_only = &pass;
  }
  const Tracer tracer = options_.tracer.value_or(ray_queries_only || options_.ray_queries ? Tracer::ray_query : Tracer::compute);
  const PlannedPass& named = ray_queries_only ? *ray_queries_only : *first;
  const std::string pass = "pass '" + named.name + "' (" + named.type + ")";
  if (tracer == Tracer::ray_query && !options_.ray_queries) {
    throw graph_.error(named.pointer,
                       pass + " traces exact paths with ray queries (VK_KHR_ray_query, VK_KHR_acceleration_structure)" +
                           (ray_queries_only ? std::string() : " as the tracer asked for (ray_query)") + ", and this device lacks " +
                           options_.ray_queries_missing + "; " +
                           (ray_queries_only ? named.decl->ray_query_alternative : "trace with the compute tracer (--tracer compute)"));
  }
  if (tracer == Tracer::compute && ray_queries_only) {
    throw graph_.error(named.pointer, pass + " traces with ray queries alone, and the tracer asked for is the compute tracer; " +
                                          named.decl->ray_query_alternative);
  }
  plan_.tracer = tracer;
}

}  // namespace caustica::graph::compiler_internal
