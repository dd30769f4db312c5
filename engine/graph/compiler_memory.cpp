// The graph compiler's memory phases (compiler_internal.h): each resource's lifetime over the
// execution order and the usage flags its ports need, the extent groups checked, and the transient
// resources placed in shared blocks where their lifetimes are disjoint (aliasing).
#include <algorithm>
#include <cassert>

#include "graph/compiler_internal.h"

namespace caustica::graph::compiler_internal {

namespace {

void add_usage(PlannedResource& r, PortUsage usage) {
  if (r.kind == ResourceKind::image) {
    switch (usage) {
      case PortUsage::sampled: r.image_usage |= VK_IMAGE_USAGE_SAMPLED_BIT; break;
      case PortUsage::storage: r.image_usage |= VK_IMAGE_USAGE_STORAGE_BIT; break;
      case PortUsage::color_attachment: r.image_usage |= VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT; break;
      case PortUsage::depth_attachment: r.image_usage |= VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT; break;
      case PortUsage::transfer_src: r.image_usage |= VK_IMAGE_USAGE_TRANSFER_SRC_BIT; break;
      case PortUsage::transfer_dst: r.image_usage |= VK_IMAGE_USAGE_TRANSFER_DST_BIT; break;
      case PortUsage::uniform:
      case PortUsage::indirect: break;
    }
  } else {
    switch (usage) {
      case PortUsage::storage: r.buffer_usage |= VK_BUFFER_USAGE_STORAGE_BUFFER_BIT; break;
      case PortUsage::uniform: r.buffer_usage |= VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT; break;
      case PortUsage::indirect: r.buffer_usage |= VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT; break;
      case PortUsage::transfer_src: r.buffer_usage |= VK_BUFFER_USAGE_TRANSFER_SRC_BIT; break;
      case PortUsage::transfer_dst: r.buffer_usage |= VK_BUFFER_USAGE_TRANSFER_DST_BIT; break;
      case PortUsage::sampled:
      case PortUsage::color_attachment:
      case PortUsage::depth_attachment: break;
    }
  }
}

}  // namespace

void Compiler::compute_lifetimes_and_usage() {
  for (uint32_t i = 0; i < order_.size(); ++i) {
    for (const auto& b : nodes_[order_[i]].bindings) {
      PlannedResource& r = plan_.resources[b.resource];
      if (r.first_use == kNoPass) r.first_use = i;
      r.last_use = i;
      add_usage(r, b.port->usage);
      if (b.port->also_sampled) add_usage(r, PortUsage::sampled);
      if (r.kind == ResourceKind::buffer && b.port->usage == PortUsage::storage &&
          r.buffer_size > options_.limits.max_storage_buffer_range) {
        throw graph_.error(b.pointer, "buffer '" + r.name + "' is " + mib(r.buffer_size) + ", above this device's maxStorageBufferRange (" +
                                          mib(options_.limits.max_storage_buffer_range) + ") for storage port '" + b.port->name + "'");
      }
    }
  }
  for (auto& r : plan_.resources) {
    if (r.transient) continue;
    add_usage(r, PortUsage::transfer_src);  // read back after the frame
    // A history resource is copied into from its source, or cleared, before each frame.
    if (r.previous_of != kNoResource) add_usage(r, PortUsage::transfer_dst);
    // A result that the next plan carries over is copied from here into its own (Executor::carry_results).
    if (plan_.reuses_unchanged_passes && r.kind == ResourceKind::image) add_usage(r, PortUsage::transfer_dst);
  }
}

void Compiler::check_pass_rules() {
  for (uint32_t n : order_) {
    const Node& node = nodes_[n];
    if (!node.decl->check) continue;
    const PassCheck result = node.decl->check(node.params, [&](std::string_view port) -> const PlannedResource* {
      for (const auto& b : node.bindings) {
        if (b.port->name == port || b.key == port) return &plan_.resources[b.resource];
      }
      return nullptr;
    });
    const std::string pass = "pass '" + node.desc->name + "' (" + node.decl->type + "): ";
    if (!result.warning.empty()) plan_.warnings.push_back(graph_.error(node.desc->pointer, pass + result.warning).what());
    if (!result.error.empty()) errors_.attempt([&] { throw graph_.error(node.desc->pointer, pass + result.error); });
  }
  errors_.throw_if_any();
}

void Compiler::check_extent_groups() const {
  for (uint32_t n : order_) {
    const auto& bindings = nodes_[n].bindings;
    for (size_t a = 0; a < bindings.size(); ++a) {
      for (size_t b = a + 1; b < bindings.size(); ++b) {
        const auto& pa = *bindings[a].port;
        const auto& pb = *bindings[b].port;
        if (pa.extent_group.empty() || pa.extent_group != pb.extent_group) continue;
        const auto& ra = plan_.resources[bindings[a].resource];
        const auto& rb = plan_.resources[bindings[b].resource];
        if (ra.width == rb.width && ra.height == rb.height) continue;
        throw graph_.error(bindings[b].pointer, "extent mismatch in pass '" + nodes_[n].desc->name + "': '" + rb.name + "' (port '" +
                                                    pb.name + "') is " + std::to_string(rb.width) + "x" + std::to_string(rb.height) +
                                                    " but '" + ra.name + "' (port '" + pa.name + "') is " + std::to_string(ra.width) + "x" +
                                                    std::to_string(ra.height));
      }
    }
  }
}

// ---- memory --------------------------------------------------------------------------------

// Places the transient resources in `order`, each at the first gap between its live neighbours
// that fits (or the tightest such gap); returns the blocks' total size.
uint64_t Compiler::place_in_order(const std::vector<uint32_t>& order, bool tightest) {
  plan_.blocks.clear();
  std::vector<uint32_t> placed;
  for (uint32_t index : order) {
    PlannedResource& r = plan_.resources[index];
    uint32_t block = kNoBlock;
    // One block per memory type and alignment: with equal alignments and sizes rounded to them,
    // every gap search lands at or below the sum of the live neighbours' sizes, so aliasing can
    // never cost more memory than separate allocations.
    for (uint32_t b = 0; b < plan_.blocks.size(); ++b) {
      if (plan_.blocks[b].type_bits == r.memory.type_bits && plan_.blocks[b].alignment == r.memory.alignment) block = b;
    }
    if (block == kNoBlock || !options_.alias) {
      block = static_cast<uint32_t>(plan_.blocks.size());
      plan_.blocks.push_back({0, r.memory.alignment, r.memory.type_bits});
    }
    std::vector<std::pair<uint64_t, uint64_t>> busy;  // [begin, end) of live neighbours in this block
    for (uint32_t other : placed) {
      const PlannedResource& o = plan_.resources[other];
      if (o.block != block) continue;
      if (o.first_use <= r.last_use && r.first_use <= o.last_use) busy.emplace_back(o.offset, o.offset + o.memory.size);
    }
    std::sort(busy.begin(), busy.end());
    auto align = [&](uint64_t v) { return (v + r.memory.alignment - 1) / r.memory.alignment * r.memory.alignment; };
    constexpr uint64_t kNoOffset = ~uint64_t{0};
    uint64_t offset = kNoOffset, free_from = 0, best_gap = ~uint64_t{0};
    for (const auto& [begin, end] : busy) {
      if (begin >= free_from + r.memory.size && (!tightest || begin - free_from < best_gap)) {
        best_gap = begin - free_from;
        offset = free_from;
        if (!tightest) break;
      }
      free_from = std::max(free_from, align(end));
    }
    if (offset == kNoOffset) offset = free_from;
    r.block = block;
    r.offset = offset;
    plan_.blocks[block].size = std::max(plan_.blocks[block].size, offset + r.memory.size);
    placed.push_back(index);
  }
  uint64_t total = 0;
  for (const auto& b : plan_.blocks) total += b.size;
  return total;
}

void Compiler::place_memory() {
  std::vector<uint32_t> transient;
  for (uint32_t i = 0; i < plan_.resources.size(); ++i) {
    PlannedResource& r = plan_.resources[i];
    if (!r.used()) continue;
    r.memory = options_.memory_requirements(r);
    assert(r.memory.alignment > 0 && (r.memory.alignment & (r.memory.alignment - 1)) == 0);
    r.memory.size = (r.memory.size + r.memory.alignment - 1) & ~(r.memory.alignment - 1);
    if (r.transient) {
      transient.push_back(i);
      plan_.transient_bytes_unaliased += r.memory.size;
    } else {
      plan_.persistent_bytes += r.memory.size;
    }
  }
  for (uint32_t at = 0; at < order_.size(); ++at) {
    uint64_t live = 0;
    for (uint32_t index : transient) {
      const PlannedResource& r = plan_.resources[index];
      live += r.first_use <= at && at <= r.last_use ? r.memory.size : 0;
    }
    plan_.transient_bytes_lifetime_bound = std::max(plan_.transient_bytes_lifetime_bound, live);
  }
  // Greedy placement is not optimal, so a few orders and both gap rules are tried and the least
  // memory kept: largest first (big resources claim offset 0 and smaller ones fill the gaps
  // between lifetimes), longest-lived first, earliest first; the first gap that fits or the
  // tightest one.
  auto by = [&](auto key) {
    std::vector<uint32_t> order = transient;
    std::stable_sort(order.begin(), order.end(), [&](uint32_t x, uint32_t y) { return key(plan_.resources[x]) > key(plan_.resources[y]); });
    return order;
  };
  const std::vector<std::vector<uint32_t>> orders{
      by([](const PlannedResource& r) { return r.memory.size; }),
      by([](const PlannedResource& r) { return std::make_pair(r.last_use - r.first_use, r.memory.size); }),
      by([](const PlannedResource& r) { return std::make_pair(r.memory.size * (r.last_use - r.first_use + 1), r.memory.size); }),
      by([](const PlannedResource& r) { return std::make_pair(-static_cast<int64_t>(r.first_use), r.memory.size); }),
  };
  uint64_t least = ~uint64_t{0};
  size_t best_order = 0;
  bool best_tightest = false;
  for (size_t o = 0; o < orders.size(); ++o) {
    for (bool tightest : {false, true}) {
      const uint64_t bytes = place_in_order(orders[o], tightest);
      if (bytes < least) {
        least = bytes;
        best_order = o;
        best_tightest = tightest;
      }
    }
  }
  place_in_order(orders[best_order], best_tightest);
  for (const auto& b : plan_.blocks) plan_.transient_bytes_aliased += b.size;

  uint64_t total = plan_.transient_bytes_aliased + plan_.persistent_bytes;
  if (total > options_.memory_limit_bytes) {
    std::vector<const PlannedResource*> largest;
    for (const auto& r : plan_.resources) {
      if (r.used()) largest.push_back(&r);
    }
    // Ties in the plan's (name) order, so that the message does not depend on the sort.
    std::stable_sort(largest.begin(), largest.end(), [](auto* a, auto* b) { return a->memory.size > b->memory.size; });
    std::string names;
    for (size_t i = 0; i < std::min<size_t>(3, largest.size()); ++i) {
      names += std::string(i ? ", " : "") + "'" + largest[i]->name + "' " + mib(largest[i]->memory.size);
    }
    throw graph_.error(largest.empty() ? "" : largest.front()->pointer,
                       "graph needs " + mib(total) + " of device memory (" + mib(plan_.transient_bytes_aliased) +
                           " transient after aliasing, " + mib(plan_.persistent_bytes) + " persistent), above the limit of " +
                           mib(options_.memory_limit_bytes) + "; largest: " + names);
  }
}

}  // namespace caustica::graph::compiler_internal
