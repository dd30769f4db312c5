// The graph compiler's last phase (compiler_internal.h): the barriers each pass needs before it
// runs (hazards, layout transitions, memory another resource aliased), and each resource's state at
// the end of the frame.
#include "graph/compiler_internal.h"

namespace caustica::graph::compiler_internal {

namespace {

struct PortAccessInfo {
  VkPipelineStageFlags2 stages;
  VkAccessFlags2 reads;
  VkAccessFlags2 writes;
  VkImageLayout layout;
};

PortAccessInfo port_access(const PortDecl& port, PassQueue queue) {
  const VkPipelineStageFlags2 shader = queue == PassQueue::compute
                                           ? VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT
                                           : VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT;
  const bool reads = port.access != PortAccess::write;
  const bool writes = port.access != PortAccess::read;
  const bool image = port.kind == ResourceKind::image;
  switch (port.usage) {
    case PortUsage::sampled: return {shader, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT, 0, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
    case PortUsage::storage:
      return {shader, reads ? VK_ACCESS_2_SHADER_STORAGE_READ_BIT : 0, writes ? VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT : 0,
              image ? VK_IMAGE_LAYOUT_GENERAL : VK_IMAGE_LAYOUT_UNDEFINED};
    case PortUsage::color_attachment:
      return {VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, reads ? VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT : 0,
              VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    case PortUsage::depth_attachment:
      return {VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
              VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT, writes ? VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT : 0,
              writes ? VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL : VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL};
    case PortUsage::transfer_src:
      return {VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT, 0,
              image ? VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL : VK_IMAGE_LAYOUT_UNDEFINED};
    case PortUsage::transfer_dst:
      return {VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, 0, VK_ACCESS_2_TRANSFER_WRITE_BIT,
              image ? VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL : VK_IMAGE_LAYOUT_UNDEFINED};
    case PortUsage::uniform: return {shader, VK_ACCESS_2_UNIFORM_READ_BIT, 0, VK_IMAGE_LAYOUT_UNDEFINED};
    case PortUsage::indirect:
      return {VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT, VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT, 0, VK_IMAGE_LAYOUT_UNDEFINED};
  }
  return {};
}

struct Tracker {
  bool touched = false;
  VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;
  VkPipelineStageFlags2 write_stages = 0;  // last write (or layout transition), not yet waited on by all
  VkAccessFlags2 write_access = 0;
  VkPipelineStageFlags2 read_stages = 0;     // reads since the last write (for write-after-read)
  VkPipelineStageFlags2 visible_stages = 0;  // stages that already waited on the last write
  VkAccessFlags2 visible_access = 0;
};

}  // namespace

bool Compiler::memory_overlaps(const PlannedResource& a, const PlannedResource& b) const {
  return a.block == b.block && a.offset < b.offset + b.memory.size && b.offset < a.offset + a.memory.size;
}

void Compiler::record_barriers() {
  std::vector<Tracker> trackers(plan_.resources.size());
  for (uint32_t i = 0; i < order_.size(); ++i) {
    const Node& node = nodes_[order_[i]];
    for (const auto& b : node.bindings) {
      const PlannedResource& r = plan_.resources[b.resource];
      const bool image = r.kind == ResourceKind::image;
      Tracker& t = trackers[b.resource];
      PortAccessInfo a = port_access(*b.port, node.decl->queue);
      PlannedBarrier barrier;
      barrier.resource = b.resource;
      barrier.dst_stages = a.stages;
      barrier.dst_access = a.reads | a.writes;
      barrier.old_layout = t.layout;
      barrier.new_layout = image ? a.layout : VK_IMAGE_LAYOUT_UNDEFINED;
      const bool layout_change = image && t.layout != a.layout;
      bool needed = false;
      if (!t.touched) {
        // The memory may still be in use by an earlier resource of this frame that it aliases.
        if (r.transient) {
          for (uint32_t other = 0; other < plan_.resources.size(); ++other) {
            const PlannedResource& o = plan_.resources[other];
            if (other == b.resource || !o.used() || !o.transient || o.last_use >= i || !memory_overlaps(o, r)) continue;
            barrier.src_stages |= trackers[other].write_stages | trackers[other].read_stages;
            barrier.src_access |= trackers[other].write_access;
            barrier.aliasing = true;
          }
        }
        needed = image || barrier.aliasing;
      } else if (layout_change || a.writes) {
        barrier.src_stages = t.write_stages | t.read_stages;
        barrier.src_access = t.write_access;
        needed = layout_change || barrier.src_stages != 0;
      } else {
        bool covered = (a.stages & ~t.visible_stages) == 0 && (a.reads & ~t.visible_access) == 0;
        if (t.write_stages && !covered) {
          barrier.src_stages = t.write_stages;
          barrier.src_access = t.write_access;
          needed = true;
        }
      }
      if (needed) plan_.passes[i].barriers.push_back(barrier);

      if (a.writes) {
        t.write_stages = a.stages;
        t.write_access = a.writes;
        t.read_stages = 0;
        t.visible_stages = 0;
        t.visible_access = 0;
      } else if (layout_change) {
        t.write_stages = a.stages;  // later readers wait on the transition
        t.write_access = 0;
        t.read_stages = a.stages;
        t.visible_stages = a.stages;
        t.visible_access = a.reads;
      } else {
        t.read_stages |= a.stages;
        if (needed) {
          t.visible_stages |= a.stages;
          t.visible_access |= a.reads;
        }
      }
      t.layout = image ? a.layout : VK_IMAGE_LAYOUT_UNDEFINED;
      t.touched = true;
    }
  }
  for (uint32_t r = 0; r < plan_.resources.size(); ++r) {
    const Tracker& t = trackers[r];
    plan_.resources[r].final_state = {t.layout, t.write_stages | t.read_stages, t.write_access};
  }
}

}  // namespace caustica::graph::compiler_internal
