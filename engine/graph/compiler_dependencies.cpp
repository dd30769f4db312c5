// What each pass's result depends on, and what a plan that reuses unchanged passes keeps.
#include "graph/compiler_internal.h"

namespace caustica::graph::compiler_internal {

void Compiler::find_dependencies() {
  // Per resource: its writers' dependencies; for a history resource, its source's, and the frame
  // (it changes every frame). A history input carries a later pass's dependencies to an earlier
  // one, so the walk over the order repeats until nothing grows (a few rounds: four bits).
  std::vector<uint32_t> written_from(plan_.resources.size(), 0);
  for (std::vector<uint32_t> before; before != written_from;) {
    before = written_from;
    for (uint32_t i = 0; i < order_.size(); ++i) {
      const Node& node = nodes_[order_[i]];
      uint32_t depends = node.decl->depends_on ? node.decl->depends_on(node.params) : kDependsOnFrame;
      if (!node.frame_params.empty()) depends |= kDependsOnFrame;
      for (const auto& b : node.bindings) {
        if (b.port->access != PortAccess::write) depends |= written_from[b.resource];
      }
      for (const auto& b : node.bindings) {
        if (b.port->access != PortAccess::read) written_from[b.resource] |= depends;
      }
      plan_.passes[i].depends = depends;
    }
    for (uint32_t r = 0; r < plan_.resources.size(); ++r) {
      if (plan_.resources[r].previous_of != kNoResource) written_from[r] = written_from[plan_.resources[r].previous_of] | kDependsOnFrame;
    }
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
          if (e.resource == b.resource && e.port->access != PortAccess::read) plan_.passes[earlier].depends |= plan_.passes[i].depends;
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
  for (PlannedResource& r : plan_.resources) r.kept_across_frames |= r.kind == ResourceKind::image && !r.transient;
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
