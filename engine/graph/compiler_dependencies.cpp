// What each pass's result depends on, and what a plan that reuses unchanged passes keeps.
#include <algorithm>
#include <functional>
#include <map>
#include <string>

#include "graph/compiler_internal.h"

namespace caustica::graph::compiler_internal {

int Compiler::scene_light(int light) const {
  const auto count = options_.scene_values.find("scene.lights");
  return count != options_.scene_values.end() && count->second >= 1 ? std::min(light, static_cast<int>(count->second) - 1) : light;
}

// The lights a pass whose type depends on the lights follows by itself: a per-light instance its
// own, a built-in pass with a "light" parameter (which light it draws from, the last where there
// are fewer) that one, any other every light (a user pass's shader may read them all).
uint32_t Compiler::own_lights(const Node& node) const {
  int light = node.desc->instance.light;
  if (light < 0 && !node.desc->user && node.decl->find_param("light") && node.params.contains("light") &&
      node.params["light"].is_number_integer()) {
    light = scene_light(node.params["light"].get<int>());
  }
  return light >= 0 && light < 32 ? 1u << light : kAllLights;
}

void Compiler::find_dependencies() {
  // Per resource: its writers' dependencies; for a history resource, its source's, and the frame
  // (it changes every frame). A history input carries a later pass's dependencies to an earlier
  // one, so the walk over the order repeats until nothing grows (a few rounds: four bits).
  // The lights followed walk alongside: a per-light instance follows its own light where its type
  // depends on the lights, and every pass the lights its inputs' writers follow.
  std::vector<uint32_t> written_from(plan_.resources.size(), 0), lights_from(plan_.resources.size(), 0);
  for (bool grew = true; grew;) {
    const std::vector<uint32_t> before = written_from, lights_before = lights_from;
    for (uint32_t i = 0; i < order_.size(); ++i) {
      const Node& node = nodes_[order_[i]];
      uint32_t depends = node.decl->depends_on ? node.decl->depends_on(node.params) : kDependsOnFrame;
      if (!node.frame_params.empty()) depends |= kDependsOnFrame;
      uint32_t lights = (depends & kDependsOnLights) ? own_lights(node) : 0u;
      for (const auto& b : node.bindings) {
        if (b.port->access == PortAccess::write) continue;
        depends |= written_from[b.resource];
        lights |= lights_from[b.resource];
      }
      for (const auto& b : node.bindings) {
        if (b.port->access == PortAccess::read) continue;
        written_from[b.resource] |= depends;
        lights_from[b.resource] |= lights;
      }
      plan_.passes[i].depends = depends;
      plan_.passes[i].lights = depends & kDependsOnLights ? lights : kAllLights;
    }
    for (uint32_t r = 0; r < plan_.resources.size(); ++r) {
      if (plan_.resources[r].previous_of == kNoResource) continue;
      written_from[r] = written_from[plan_.resources[r].previous_of] | kDependsOnFrame;
      lights_from[r] = kAllLights;
    }
    grew = before != written_from || lights_before != lights_from;
  }
  for (uint32_t r = 0; r < plan_.resources.size(); ++r) {
    if (plan_.resources[r].previous_of != kNoResource) plan_.resources[r].history_depends = written_from[r];
  }
  // A jittered camera looks elsewhere every frame, though its key (what restarts history) holds.
  if (plan_.jitters_camera) {
    for (PlannedPass& pass : plan_.passes) pass.depends |= pass.depends & kDependsOnCamera ? kDependsOnFrame : 0u;
  }
  // A pass that rewrites what an earlier one wrote (a read_write port) reads that pass's result as it
  // is in this frame: when it runs, the earlier writers run again first. Latest first, so that a
  // chain of rewrites reaches its first writer.
  for (uint32_t i = static_cast<uint32_t>(order_.size()); i-- > 0;) {
    for (const auto& b : nodes_[order_[i]].bindings) {
      if (b.port->access != PortAccess::read_write) continue;
      for (uint32_t earlier = 0; earlier < i; ++earlier) {
        for (const auto& e : nodes_[order_[earlier]].bindings) {
          if (e.resource != b.resource || e.port->access == PortAccess::read) continue;
          plan_.passes[earlier].depends |= plan_.passes[i].depends;
          plan_.passes[earlier].lights |= plan_.passes[i].lights;
        }
      }
    }
  }
  plan_.reuses_unchanged_passes = options_.reuse_unchanged_passes;
  if (!plan_.reuses_unchanged_passes) return;
  for (uint32_t i = 0; i < order_.size(); ++i) {
    if (!plan_.passes[i].reusable(true)) continue;
    for (const auto& b : nodes_[order_[i]].bindings) {
      if (b.port->access != PortAccess::read) plan_.resources[b.resource].transient = false;
    }
  }
  find_refining_passes();
  find_result_identities();
  for (PlannedResource& r : plan_.resources) r.kept_across_frames |= r.kind == ResourceKind::image && !r.transient;
}

std::vector<ResultIdentity> Compiler::result_identities(bool running) const {
  // What each resource holds so far in the order: its last writer's identity and the port.
  std::vector<std::optional<std::pair<size_t, std::string>>> content(plan_.resources.size());
  std::vector<ResultIdentity> identities;
  identities.reserve(order_.size());
  for (uint32_t i = 0; i < order_.size(); ++i) {
    const Node& node = nodes_[order_[i]];
    const PlannedPass& pass = plan_.passes[i];
    nlohmann::json params = node.params;
    std::map<std::string, std::string> frame_params = node.frame_params;
    for (const ParamDecl& p : node.decl->params) {
      if (!running || !p.sampling_only) continue;
      params.erase(p.name);
      frame_params.erase(p.name);
    }
    std::string text =
        pass.name + "\n" + pass.type + "\n" + params.dump() + "\n" + nlohmann::json(frame_params).dump() + "\n" + node.decl->result_source;
    std::vector<ResultIdentity> inputs;
    for (const auto& b : node.bindings) {
      const PlannedResource& r = plan_.resources[b.resource];
      text += "\n" + b.key + " " + std::to_string(static_cast<int>(r.kind)) + " " + std::to_string(static_cast<int>(r.format)) + " " +
              std::to_string(r.width) + "x" + std::to_string(r.height) + " " + std::to_string(r.mips) + " " + std::to_string(r.layers) +
              " " + std::to_string(r.buffer_size);
      if (b.port->access == PortAccess::write) continue;
      text += " reads";
      if (const auto& written = content[b.resource]) {
        text += " input " + std::to_string(inputs.size()) + "." + written->second;
        inputs.push_back(identities[written->first]);
      }
    }
    identities.emplace_back(std::move(text), std::move(inputs));
    for (const auto& b : node.bindings) {
      if (b.port->access != PortAccess::read) content[b.resource] = std::pair{size_t{i}, b.key};
    }
  }
  // A later pass that rewrites what a pass wrote leaves the frame's end state of it: the pass's
  // result is carried with that pass's or not at all (as find_dependencies runs them together).
  for (uint32_t i = static_cast<uint32_t>(order_.size()); i-- > 0;) {
    for (const auto& b : nodes_[order_[i]].bindings) {
      if (b.port->access == PortAccess::read) continue;
      for (uint32_t later = i + 1; later < order_.size(); ++later) {
        for (const auto& l : nodes_[order_[later]].bindings) {
          if (l.resource != b.resource || l.port->access == PortAccess::read) continue;
          identities[i] = ResultIdentity("then", {identities[i], identities[later]});
        }
      }
    }
  }
  return identities;
}

void Compiler::find_result_identities() {
  const std::vector<ResultIdentity> results = result_identities(false), running = result_identities(true);
  for (uint32_t i = 0; i < order_.size(); ++i) {
    PlannedPass& pass = plan_.passes[i];
    // A history input's image is not carried into another plan, so a pass that reads one starts over.
    const auto& bindings = nodes_[order_[i]].bindings;
    const bool reads_history = std::any_of(bindings.begin(), bindings.end(),
                                           [&](const auto& b) { return plan_.resources[b.resource].previous_of != kNoResource; });
    if (pass.reusable(true)) pass.result_id = results[i];
    if (pass.refines && !reads_history) pass.running_id = running[i];
    if (plan_.refines_apart && !pass.refines && !pass.result_id) pass.showing_id = running[i];
  }
}

void Compiler::find_refining_passes() {
  // A pass refines when it accumulates or when a refining pass reads what it writes (a history
  // input reads its source's writers): latest first, so that a chain reaches its first pass.
  auto accumulates = [&](const Node& node) {
    return node.decl->accumulates || std::any_of(node.bindings.begin(), node.bindings.end(),
                                                 [&](const auto& b) { return plan_.resources[b.resource].previous_of != kNoResource; });
  };
  std::vector<bool> read_by_refining(plan_.resources.size(), false);
  bool any_accumulates = false;
  for (uint32_t i = static_cast<uint32_t>(order_.size()); i-- > 0;) {
    const Node& node = nodes_[order_[i]];
    bool refines = accumulates(node);
    any_accumulates |= refines;
    for (const auto& b : node.bindings) refines |= b.port->access != PortAccess::read && read_by_refining[b.resource];
    if (!refines) continue;
    plan_.passes[i].refines = true;
    for (const auto& b : node.bindings) {
      if (b.port->access == PortAccess::write) continue;
      read_by_refining[b.resource] = true;
      if (const uint32_t source = plan_.resources[b.resource].previous_of; source != kNoResource) read_by_refining[source] = true;
    }
  }
  if (!any_accumulates) return;
  // The running results persist; apart they run only where what a showing pass reads from a
  // refining one persists too (a pass that changes every frame and is read by both would otherwise
  // have to run in both, and move on twice).
  for (uint32_t i = 0; i < order_.size(); ++i) {
    if (!accumulates(nodes_[order_[i]])) continue;
    for (const auto& b : nodes_[order_[i]].bindings) {
      if (b.port->access != PortAccess::read) plan_.resources[b.resource].transient = false;
    }
  }
  std::vector<bool> written_by_refining(plan_.resources.size(), false);
  plan_.refines_apart = true;
  for (uint32_t i = 0; i < order_.size(); ++i) {
    for (const auto& b : nodes_[order_[i]].bindings) {
      if (plan_.passes[i].refines) {
        if (b.port->access != PortAccess::read) written_by_refining[b.resource] = true;
      } else if (b.port->access != PortAccess::write && written_by_refining[b.resource] && plan_.resources[b.resource].transient) {
        plan_.refines_apart = false;
      }
    }
  }
  if (!plan_.refines_apart) return;
  // What the showing passes write persists too, so that a display frame can show in steps
  // (DisplayStep), each reading what the steps before it left.
  for (uint32_t i = 0, showing = 0; i < order_.size(); ++i) {
    if (plan_.passes[i].refines) continue;
    plan_.passes[i].showing = showing++;
    for (const auto& b : nodes_[order_[i]].bindings) {
      if (b.port->access != PortAccess::read) plan_.resources[b.resource].transient = false;
    }
  }
}

void Compiler::keep_contents_across_frames() {
  // A kept image's first barrier of a frame changes its layout from where the last frame left it,
  // not from "undefined", which would let the device discard what a skipped pass wrote or what a
  // history input reads next frame. (The executor puts each kept image in that layout once, when it
  // creates it.)
  std::vector<bool> first_seen(plan_.resources.size(), false);
  for (uint32_t i = 0; i < plan_.passes.size(); ++i) {
    PlannedPass& pass = plan_.passes[i];
    for (PlannedBarrier& barrier : pass.barriers) {
      const PlannedResource& r = plan_.resources[barrier.resource];
      if (first_seen[barrier.resource]) continue;
      first_seen[barrier.resource] = true;
      if (r.kind == ResourceKind::image && r.kept_across_frames && barrier.old_layout == VK_IMAGE_LAYOUT_UNDEFINED) {
        barrier.old_layout = r.final_state.layout;
        barrier.src_stages |= r.final_state.stages;
        barrier.src_access |= r.final_state.access;
      }
    }
  }
}

}  // namespace caustica::graph::compiler_internal
