// What a frame records besides its passes: barriers, history resources, carried results, read-back.
#include <algorithm>

#include "graph/executor_internal.h"

namespace caustica::graph {
namespace {

// Back from where `to_transfer` took the read-back images that are kept across frames: where the
// next frame's first barriers expect them.
std::vector<PlannedBarrier> back_from_transfer(const Plan& plan, const std::vector<PlannedBarrier>& to_transfer) {
  std::vector<PlannedBarrier> back;
  for (const PlannedBarrier& b : to_transfer) {
    if (plan.resources[b.resource].kind != ResourceKind::image || !plan.resources[b.resource].kept_across_frames) continue;
    back.push_back({b.resource, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_NONE, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                    VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT, b.new_layout, b.old_layout, false});
  }
  return back;
}

}  // namespace

std::vector<PlannedBarrier> kept_images_to_final_layouts(const Plan& plan) {
  std::vector<PlannedBarrier> barriers;
  for (uint32_t r = 0; r < plan.resources.size(); ++r) {
    const PlannedResource& res = plan.resources[r];
    if (!res.used() || !res.kept_across_frames || res.kind != ResourceKind::image) continue;
    barriers.push_back({r, VK_PIPELINE_STAGE_2_NONE, VK_ACCESS_2_NONE, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                        VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT, VK_IMAGE_LAYOUT_UNDEFINED, res.final_state.layout,
                        false});
  }
  return barriers;
}

VkImageAspectFlags aspect_of(Format format) {
  return format_info(format).depth ? VK_IMAGE_ASPECT_DEPTH_BIT : VK_IMAGE_ASPECT_COLOR_BIT;
}

VkImageMemoryBarrier2 whole_image_barrier(VkImage image, const PlannedResource& res, VkPipelineStageFlags2 src_stages,
                                          VkAccessFlags2 src_access, VkPipelineStageFlags2 dst_stages, VkAccessFlags2 dst_access,
                                          VkImageLayout old_layout, VkImageLayout new_layout) {
  return vk::image_transition(image, aspect_of(res.format), old_layout, new_layout, src_stages, src_access, dst_stages, dst_access, res.mips,
                              res.layers);
}

void pipeline_barrier(VkCommandBuffer cmd, const std::vector<VkImageMemoryBarrier2>& images, const std::vector<VkBufferMemoryBarrier2>& buffers) {
  VkDependencyInfo dependency{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
  dependency.imageMemoryBarrierCount = static_cast<uint32_t>(images.size());
  dependency.pImageMemoryBarriers = images.data();
  dependency.bufferMemoryBarrierCount = static_cast<uint32_t>(buffers.size());
  dependency.pBufferMemoryBarriers = buffers.data();
  vkCmdPipelineBarrier2(cmd, &dependency);
}

void copy_whole_image(VkCommandBuffer cmd, const PlannedResource& res, VkImage from, VkImage to) {
  const VkImageAspectFlags aspect = aspect_of(res.format);
  std::vector<VkImageCopy> levels;
  for (uint32_t level = 0; level < res.mips; ++level) {
    const VkImageSubresourceLayers layers{aspect, level, 0, res.layers};
    levels.push_back({layers, {}, layers, {}, {std::max(1u, res.width >> level), std::max(1u, res.height >> level), 1}});
  }
  vkCmdCopyImage(cmd, from, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, to, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                 static_cast<uint32_t>(levels.size()), levels.data());
}

void Executor::record_barriers(VkCommandBuffer cmd, const std::vector<PlannedBarrier>& barriers) const {
  if (barriers.empty()) return;
  std::vector<VkImageMemoryBarrier2> images;
  std::vector<VkBufferMemoryBarrier2> buffers;
  for (const auto& b : barriers) {
    const PlannedResource& res = plan_->resources[b.resource];
    if (res.kind == ResourceKind::image) {
      images.push_back(whole_image_barrier(realized_->images[b.resource].image.get(), res, b.src_stages, b.src_access, b.dst_stages,
                                           b.dst_access, b.old_layout, b.new_layout));
    } else {
      VkBufferMemoryBarrier2 bb{VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER_2};
      bb.srcStageMask = b.src_stages;
      bb.srcAccessMask = b.src_access;
      bb.dstStageMask = b.dst_stages;
      bb.dstAccessMask = b.dst_access;
      bb.srcQueueFamilyIndex = bb.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
      bb.buffer = realized_->buffers[b.resource].buffer.get();
      bb.size = VK_WHOLE_SIZE;
      buffers.push_back(bb);
    }
  }
  pipeline_barrier(cmd, images, buffers);
}

void Executor::record_carried(VkCommandBuffer cmd) {
  if (carried_.images.empty()) return;
  std::vector<VkImageMemoryBarrier2> before, after;
  for (const ImageMove& move : carried_.images) {
    const PlannedResource& was = carried_.plan->resources[move.from];
    const PlannedResource& res = plan_->resources[move.to];
    const VkImage to = realized_->images[move.to].image.get();
    if (move.handed) {
      // A handed image goes on from where the plan before left it (run_frame's first barriers skip it).
      after.push_back(whole_image_barrier(to, res, was.final_state.stages, was.final_state.access, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                                          VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT, was.final_state.layout,
                                          res.final_state.layout));
      continue;
    }
    before.push_back(whole_image_barrier(carried_.realized->images[move.from].image.get(), was, was.final_state.stages,
                                         was.final_state.access, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT,
                                         was.final_state.layout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL));
    // After kept_images_to_final_layouts' transition of it; overwritten whole.
    before.push_back(whole_image_barrier(to, res, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_WRITE_BIT,
                                         VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                                         VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL));
    after.push_back(whole_image_barrier(to, res, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                                        VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT,
                                        VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, res.final_state.layout));
  }
  vk_.begin_label(cmd, "carried results");
  pipeline_barrier(cmd, before);
  for (const ImageMove& move : carried_.images) {
    if (!move.handed)
      copy_whole_image(cmd, plan_->resources[move.to], carried_.realized->images[move.from].image.get(), realized_->images[move.to].image.get());
  }
  pipeline_barrier(cmd, after);
  vk_.end_label(cmd);
}

void Executor::record_history(VkCommandBuffer cmd, const FrameDecision& decision) {
  Realized& real = *realized_;
  const Plan& p = *plan_;
  std::vector<PlannedBarrier> before, after;
  std::vector<std::pair<uint32_t, bool>> fills;  // history resource, and whether it restarts (zeros) or copies
  for (const auto& [h, restart] : decision.history_restarts) {
    const PlannedResource& history = p.resources[h];
    fills.emplace_back(h, restart);
    const bool image = history.kind == ResourceKind::image;
    const VkImageLayout dst_layout = image ? VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL : VK_IMAGE_LAYOUT_UNDEFINED;
    const VkImageLayout src_layout = image ? VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL : VK_IMAGE_LAYOUT_UNDEFINED;
    const AccessState& was = history.final_state;
    // Its old contents are overwritten whole: from "undefined".
    before.push_back({h, was.stages, was.access, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                      VK_IMAGE_LAYOUT_UNDEFINED, dst_layout, false});
    after.push_back({h, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                     VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT, dst_layout, was.layout, false});
    if (restart) continue;
    const AccessState& source = p.resources[history.previous_of].final_state;
    before.push_back({history.previous_of, source.stages, source.access, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                      VK_ACCESS_2_TRANSFER_READ_BIT, source.layout, src_layout, false});
    after.push_back({history.previous_of, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_NONE, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                     VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT, src_layout, source.layout, false});
  }
  if (fills.empty()) return;
  vk_.begin_label(cmd, "history");
  record_barriers(cmd, before);
  for (const auto& [h, restart] : fills) {
    const PlannedResource& history = p.resources[h];
    if (history.kind == ResourceKind::buffer) {
      const VkBuffer to = real.buffers[h].buffer.get();
      if (restart)
        vkCmdFillBuffer(cmd, to, 0, VK_WHOLE_SIZE, 0);
      else
        vkCmdCopyBuffer(cmd, real.buffers[history.previous_of].buffer.get(), to, 1, std::array{VkBufferCopy{0, 0, history.buffer_size}}.data());
      continue;
    }
    const VkImage to = real.images[h].image.get();
    const VkImageSubresourceRange all{aspect_of(history.format), 0, history.mips, 0, history.layers};
    if (restart && format_info(history.format).depth) {
      const VkClearDepthStencilValue zero{};
      vkCmdClearDepthStencilImage(cmd, to, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &zero, 1, &all);
    } else if (restart) {
      const VkClearColorValue zero{};
      vkCmdClearColorImage(cmd, to, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &zero, 1, &all);
    } else {
      copy_whole_image(cmd, history, real.images[history.previous_of].image.get(), to);
    }
  }
  record_barriers(cmd, after);
  vk_.end_label(cmd);
}

void Executor::record_read_back(VkCommandBuffer cmd) {
  const Realized& real = *realized_;
  const Plan& p = *plan_;
  std::vector<PlannedBarrier> to_transfer;
  for (const auto& rb : real.readbacks) {
    const PlannedResource& res = p.resources[rb.resource];
    to_transfer.push_back({rb.resource, res.final_state.stages, res.final_state.access, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                           VK_ACCESS_2_TRANSFER_READ_BIT, res.final_state.layout,
                           res.kind == ResourceKind::image ? VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL : VK_IMAGE_LAYOUT_UNDEFINED, false});
  }
  vk_.begin_label(cmd, "read back");
  record_barriers(cmd, to_transfer);
  for (const auto& rb : real.readbacks) {
    const PlannedResource& res = p.resources[rb.resource];
    if (res.kind == ResourceKind::image) {
      VkBufferImageCopy copy{};
      copy.imageSubresource = {aspect_of(res.format), 0, 0, res.layers};
      copy.imageExtent = {res.width, res.height, 1};
      vkCmdCopyImageToBuffer(cmd, real.images[rb.resource].image.get(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, rb.buffer.get(), 1, &copy);
    } else {
      VkBufferCopy copy{0, 0, rb.bytes};
      vkCmdCopyBuffer(cmd, real.buffers[rb.resource].buffer.get(), rb.buffer.get(), 1, &copy);
    }
  }
  // A skipped pass or a history input finds its images where the last frame left them.
  record_barriers(cmd, back_from_transfer(p, to_transfer));
  vk_.end_label(cmd);
}

}  // namespace caustica::graph
