// adaptive_caustic_map (Wyman and Nichols 2009) and hierarchical_caustic_map (Wyman 2008): a 64 x 64
// photon grid refined cluster by cluster (2 x 2 photons) towards the effective grid, entirely on
// the device: each level appends the clusters it refines to a list, a one-thread kernel turns the
// count into an indirect dispatch, and the next level runs; the CPU never reads anything back.
// Adaptive decides by tracing each level's photons; hierarchical by a coverage pyramid of the
// light-view refractor buffer, tracing photons only at the last level. Start clusters are split
// into batches so that the lists stay within `memory_mib` even if every cluster refined to the last
// level, and the batches run one after another.
#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstddef>
#include <functional>

#include "builtin_passes.h"
#include "core/error.h"
#include "core/low_discrepancy.h"
#include "graph/plan.h"
#include "photon_kernel.h"
#include "scene_draw.h"

namespace caustica::passes {
namespace {

constexpr uint32_t kStartSide = 32;  // start clusters per side: a 64 x 64 photon grid
constexpr uint32_t kStartClusters = kStartSide * kStartSide;
constexpr uint32_t kGroup = 64;
constexpr uint32_t kMaxLevels = 16;
constexpr VkAccessFlags2 kAdaptiveStorage = VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;
constexpr VkPipelineStageFlags2 kAdaptiveCompute = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
constexpr VkPipelineStageFlags2 kAdaptiveTransfer = VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT;

struct AdaptivePush {
  uint32_t distance_mode;
  uint32_t search;
  float search_distance;
  uint32_t light;
  uint32_t fresnel;
  uint32_t level;
  uint32_t max_level;
  uint32_t converge_level;
  uint32_t batch;  // this batch's start clusters: the first in the low 16 bits, the count in the high 16
  uint32_t light_size_log2;
  uint32_t splat_levels;
  uint32_t coverage_seeded;
  float converge_spread;
  uint32_t counter_slot[11];
  ExactPathPush exact;
  uint32_t band;
  uint32_t jitter;     // where in its cell each photon starts, in 1/65536 of the cell: x in the low 16 bits, y in the high
  float kernel_scale;  // Knaus and Zwicker's r_i / r_0 for this frame's coarse splats
};
// 128 bytes: the push-constant size every device allows; hence the packed fields, and the lists'
// capacity is the shaders' to read from their buffer's size.
static_assert(sizeof(AdaptivePush) <= 128);

constexpr uint32_t kCoverageBlockLog2 = 2;  // the coverage pyramid's finest texel: 4 x 4 light-view texels

uint32_t log2_exact(uint32_t v) {
  uint32_t l = 0;
  while ((1u << l) < v) ++l;
  return l;
}

// Knaus and Zwicker 2011: the radius of pass i follows r_{i+1}^2 = r_i^2 (i + alpha) / (i + 1), so
// (r_i / r_0)^2 is the product of (k + alpha) / (k + 1) over k < i, Gamma(i + alpha) / (Gamma(alpha)
// Gamma(i + 1)): in closed form, since a viewer left still counts frames without end. Exactly 1 for
// i = 0 and for alpha = 1.
double shrunk_radius(uint64_t i, double alpha) {
  const double n = static_cast<double>(i);
  return std::exp(0.5 * (std::lgamma(n + alpha) - std::lgamma(alpha) - std::lgamma(n + 1.0)));
}

class AdaptiveCausticMapPass final : public graph::Pass {
 public:
  explicit AdaptiveCausticMapPass(bool hierarchical) : hierarchical_(hierarchical) {}

  void setup(graph::PassSetup& setup) override {
    require_photon_features(setup, setup.pass().type);
    const auto& p = setup.pass().params;
    const uint32_t grid = p["grid"].get<uint32_t>();
    max_level_ = log2_exact(grid / 64);
    const std::string criterion = hierarchical_ ? "max_level" : p["criterion"].get<std::string>();
    const uint32_t converge_from = hierarchical_ ? 0 : p["converge_from"].get<uint32_t>();
    converge_level_ = criterion == "max_level"   ? max_level_ + 1
                      : criterion == "max_error" ? 0
                                                 : log2_exact(std::max(64u, converge_from) / 64);
    converge_spread_ = !hierarchical_ && p["converge_test"].get<std::string>() == "within_texel" ? p["converge_spread"].get<float>() : 0.0f;
    const uint32_t light_size = setup.resource("front").width;
    // The pyramid's finest level has one texel per 4 x 4 light-view texels (a sixteenth of the
    // threads on lavapipe), or per photon of the effective grid when that is coarser. A cluster
    // finer than a texel looks up the texel that holds it, which is conservative: it keeps a few
    // more clusters along silhouettes, never drops one.
    light_size_log2_ =
        std::min(log2_exact(light_size) > kCoverageBlockLog2 ? log2_exact(light_size) - kCoverageBlockLog2 : 0, log2_exact(grid));
    uses_coverage_ = hierarchical_ || p["coverage_seeding"].get<bool>();
    assert(!uses_coverage_ || (1u << log2_exact(light_size)) == light_size);  // check_traversal
    // Two lists of 4-byte entries. A start cluster can grow to 4^max_level clusters at the last level.
    capacity_ = static_cast<uint32_t>(std::min<uint64_t>((p["memory_mib"].get<uint64_t>() << 20) / 8, UINT32_MAX / 2));
    const uint64_t per_start = uint64_t{1} << (2 * max_level_);
    assert(per_start <= capacity_);  // check_traversal
    starts_per_batch_ = static_cast<uint32_t>(std::min<uint64_t>(kStartClusters, capacity_ / per_start));

    using Kind = graph::PassSetup::CounterKind;
    const char* counts[] = {"photons.processed",   "photons.splatted",  "photons.dropped_miss",
                            "photons.dropped_tir", "photons.converged", "photons.overflow"};
    for (int i = 0; i < 6; ++i) slots_[i] = setup.add_counter(counts[i]);
    for (uint32_t l = 0; l <= max_level_; ++l) level_slots_.push_back(setup.add_counter("photons.processed.level" + std::to_string(l)));
    peak_slot_ = setup.add_counter("photons.peak_bytes");
    batches_slot_ = setup.add_counter("photons.batches");
    const char* sums[] = {"caustic.flux", "caustic.flux_entering", "caustic.flux_dropped"};
    for (int i = 0; i < 3; ++i) sum_slots_[i] = setup.add_counter(sums[i], Kind::sum);
    exact_.setup(setup);

    vk::Context& vk = setup.vk();
    lists_ = vk::make_buffer(vk, uint64_t{capacity_} * 2 * sizeof(uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, 0,
                             setup.pass().name + " cluster lists");
    control_ = vk::make_buffer(vk, (kMaxLevels + kMaxLevels * 3) * sizeof(uint32_t),
                               VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                               0, setup.pass().name + " level control");
    uint64_t coverage_words = 1;
    for (uint32_t l = 0; uses_coverage_ && l <= light_size_log2_; ++l) coverage_words += uint64_t{1} << (2 * (light_size_log2_ - l));
    coverage_ =
        vk::make_buffer(vk, coverage_words * sizeof(uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, 0, setup.pass().name + " coverage");
    splat_levels_ = p["splat_levels"].get<uint32_t>();
    uint64_t pyramid_words = 0;
    const auto& map = setup.resource("caustic_map");
    for (uint32_t l = 0; l < splat_levels_; ++l) pyramid_words += uint64_t{std::max(1u, map.width >> l)} * std::max(1u, map.height >> l);
    pyramid_ = vk::make_buffer(vk, pyramid_words * 3 * sizeof(float), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                               0, setup.pass().name + " multi-resolution caustic map");
    shader::Defines defines;
    if (hierarchical_) defines["HIERARCHICAL"] = "1";
    defines = refraction_defines(setup, exact_.defines(defines));
    // One layout for the family: every kernel is bound with the photon kernel's resources.
    std::vector<graph::PassSetup::ShaderFile> family{
        {"caustics/adaptive_photons.comp", defines}, {"caustics/adaptive_args.comp", {}}, {"caustics/combine.comp", {}}};
    if (uses_coverage_) family.push_back({"caustics/coverage.comp", {}});
    if (setup.bound("caustic_levels")) family.push_back({"caustics/levels.comp", {}});
    const vk::PipelineDesc layout = setup.shared_layout(hierarchical_ ? "hierarchical_photons" : "adaptive_photons", family);
    check_push(*layout.interface);
    // The hierarchical traversal does not look at its photons, so in image space its last level can
    // trace every colour band in one pass; the adaptive one follows each band's photons.
    photons_.build(setup, layout, family[0].path, defines, hierarchical_ && !exact_.traced());
    args_ = setup.compute_pipeline(layout, family[1]);
    combine_ = setup.compute_pipeline(layout, family[2]);
    if (uses_coverage_) coverage_pipeline_ = setup.compute_pipeline(layout, {"caustics/coverage.comp", {}});
    if (setup.bound("caustic_levels")) levels_ = setup.compute_pipeline(layout, {"caustics/levels.comp", {}});
    clear_ = make_caustic_clear_pipeline(setup);
  }

  void execute(graph::PassContext& ctx) override {
    VkCommandBuffer cmd = ctx.cmd();
    const PhotonKernel::Passes passes = photons_.passes(ctx.scene().scene());
    const uint32_t batches = (kStartClusters + starts_per_batch_ - 1) / starts_per_batch_;
    ctx.set_counter(batches_slot_, batches * static_cast<uint32_t>(passes.bands.size()));
    // The caustic map (level 0) and the coarser levels start at zero, after the previous frame's
    // combine read them.
    record_caustic_clear(ctx, clear_);
    memory_barrier(cmd, kAdaptiveCompute, kAdaptiveStorage, kAdaptiveTransfer, VK_ACCESS_2_TRANSFER_WRITE_BIT);
    vkCmdFillBuffer(cmd, pyramid_.get(), 0, VK_WHOLE_SIZE, 0);
    AdaptivePush push = frame_push(ctx);
    // Every kernel of the family shares the layout, so one set of descriptors binds each.
    vk::DescriptorWriter writer = photon_descriptors(ctx, passes.pipeline, exact_);
    writer.buffer("ListBlock", lists_.get())
        .buffer("ControlBlock", control_.get())
        .buffer("CoverageBlock", coverage_.get())
        .buffer("PyramidBlock", pyramid_.get());
    if (levels_.pipeline) writer.image("caustic_levels", ctx.view("caustic_levels"));
    const auto bind = [&](const vk::Pipeline& pipeline) {
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.pipeline.get());
      writer.push(ctx.vk(), cmd, pipeline);
      exact_.bind_textures(ctx, pipeline);
    };
    if (uses_coverage_) record_coverage(cmd, bind, push);
    for (uint32_t batch = 0; batch < batches * passes.bands.size(); ++batch) {  // every batch once per colour band
      push.band = passes.bands[batch / batches];
      record_batch(cmd, bind, passes.pipeline, batch % batches, push);
    }
    record_levels(ctx, bind, push);
  }

 private:
  using Bind = std::function<void(const vk::Pipeline&)>;

  AdaptivePush frame_push(const graph::PassContext& ctx) const {
    const RefractionPush shared = refraction_push(ctx, 0);
    const auto& p = ctx.params();
    AdaptivePush push{shared.distance_mode,
                      shared.search,
                      shared.search_distance,
                      p["light"].get<uint32_t>(),
                      p["fresnel"].get<bool>() ? 1u : 0u,
                      0,
                      max_level_,
                      converge_level_,
                      0,
                      light_size_log2_,
                      splat_levels_,
                      uses_coverage_ ? 1u : 0u,
                      converge_spread_,
                      {},
                      exact_.push(ctx),
                      kWhiteBand};
    for (int i = 0; i < 6; ++i) push.counter_slot[i] = slots_[i];
    push.counter_slot[7] = peak_slot_;
    for (int i = 0; i < 3; ++i) push.counter_slot[8 + i] = sum_slots_[i];
    // With jitter, each frame since the reset moves the start grid and every subdivision of it by the
    // same offset within their cells: the cell's centre first, then the R2 sequence (as caustic_map's
    // photons), so that the mean of successive maps (accumulate) converges to the map of a finer
    // traversal. Its coarse splats shrink as the frames add up (Knaus and Zwicker), so that the
    // mean's blur fades too; a frame's splats keep the photons' power whatever their size.
    const uint64_t since_reset = p["jitter"].get<bool>() ? ctx.frame().since_reset : 0;
    const glm::vec2 offset = r2_point(since_reset);
    push.jitter = static_cast<uint32_t>(offset.x * 65536.0f) | static_cast<uint32_t>(offset.y * 65536.0f) << 16;
    push.kernel_scale = static_cast<float>(shrunk_radius(since_reset, p["kernel_alpha"].get<double>()));
    return push;
  }

  // The coverage pyramid, finest level first; each level reads the one before.
  void record_coverage(VkCommandBuffer cmd, const Bind& bind, AdaptivePush& push) const {
    for (uint32_t level = 0; level <= light_size_log2_; ++level) {
      if (level > 0) memory_barrier(cmd, kAdaptiveCompute, kAdaptiveStorage, kAdaptiveCompute, kAdaptiveStorage);
      push.level = level;
      bind(coverage_pipeline_);
      vkCmdPushConstants(cmd, coverage_pipeline_.layout.get(), coverage_pipeline_.stages, 0, sizeof(push), &push);
      const uint32_t side = 1u << (light_size_log2_ - level);
      vkCmdDispatch(cmd, (side + 7) / 8, (side + 7) / 8, 1);
    }
  }

  // Batch `b`'s traversal, level by level: each level after the first dispatched as many groups as
  // the level before appended clusters (adaptive_args).
  void record_batch(VkCommandBuffer cmd, const Bind& bind, const vk::Pipeline& photons, uint32_t b, AdaptivePush& push) const {
    // Everything the previous batch (or the clear, the counter fill) wrote is visible, and the
    // control block starts at zero.
    memory_barrier(cmd, kAdaptiveCompute | VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT | kAdaptiveTransfer,
                   kAdaptiveStorage | VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_2_TRANSFER_WRITE_BIT, kAdaptiveTransfer,
                   VK_ACCESS_2_TRANSFER_WRITE_BIT);
    vkCmdFillBuffer(cmd, control_.get(), 0, VK_WHOLE_SIZE, 0);
    memory_barrier(cmd, kAdaptiveTransfer, VK_ACCESS_2_TRANSFER_WRITE_BIT, kAdaptiveCompute | VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT,
                   kAdaptiveStorage | VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT);
    const uint32_t first = b * starts_per_batch_;
    const uint32_t count = std::min(starts_per_batch_, kStartClusters - first);
    push.batch = first | count << 16;
    for (uint32_t level = 0; level <= max_level_; ++level) {
      push.level = level;
      push.counter_slot[6] = level_slots_[level];
      if (level > 0) {
        memory_barrier(cmd, kAdaptiveCompute, kAdaptiveStorage, kAdaptiveCompute, kAdaptiveStorage);
        bind(args_);
        vkCmdPushConstants(cmd, args_.layout.get(), args_.stages, 0, sizeof(push), &push);
        vkCmdDispatch(cmd, 1, 1, 1);
        memory_barrier(cmd, kAdaptiveCompute, kAdaptiveStorage, kAdaptiveCompute | VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT,
                       kAdaptiveStorage | VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT);
      }
      bind(photons);
      vkCmdPushConstants(cmd, photons.layout.get(), photons.stages, 0, sizeof(push), &push);
      if (level == 0)
        vkCmdDispatch(cmd, (count + kGroup - 1) / kGroup, 1, 1);
      else
        vkCmdDispatchIndirect(cmd, control_.get(), (kMaxLevels + level * 3) * sizeof(uint32_t));
    }
  }

  // The levels as splatted where caustic_levels is bound, then the coarser levels added into the
  // map, which holds level 0.
  void record_levels(const graph::PassContext& ctx, const Bind& bind, AdaptivePush& push) const {
    VkCommandBuffer cmd = ctx.cmd();
    if (levels_.pipeline) {
      memory_barrier(cmd, kAdaptiveCompute, kAdaptiveStorage, kAdaptiveCompute, kAdaptiveStorage);
      bind(levels_);
      vkCmdPushConstants(cmd, levels_.layout.get(), levels_.stages, 0, sizeof(push), &push);
      const VkExtent2D extent = ctx.extent("caustic_levels");
      vkCmdDispatch(cmd, (extent.width + 7) / 8, (extent.height + 7) / 8, 1);
    }
    // Atomic adds, so the levels need no order among themselves.
    if (splat_levels_ > 1) {
      memory_barrier(cmd, kAdaptiveCompute, kAdaptiveStorage, kAdaptiveCompute, kAdaptiveStorage);
      bind(combine_);
    }
    const VkExtent2D map = ctx.extent("caustic_map");
    for (uint32_t level = 1; level < splat_levels_; ++level) {
      push.level = level;
      vkCmdPushConstants(cmd, combine_.layout.get(), combine_.stages, 0, sizeof(push), &push);
      const uint32_t width = std::max(1u, map.width >> level), height = std::max(1u, map.height >> level);
      vkCmdDispatch(cmd, (width + 7) / 8, (height + 7) / 8, 1);
    }
  }

  static void check_push(const shader::ShaderInterface& interface) {
    std::vector<shader::MirroredMember> members{CAUSTICA_MIRRORED(AdaptivePush, distance_mode),
                                                CAUSTICA_MIRRORED(AdaptivePush, search),
                                                CAUSTICA_MIRRORED(AdaptivePush, search_distance),
                                                CAUSTICA_MIRRORED(AdaptivePush, light),
                                                CAUSTICA_MIRRORED(AdaptivePush, fresnel),
                                                CAUSTICA_MIRRORED(AdaptivePush, level),
                                                CAUSTICA_MIRRORED(AdaptivePush, max_level),
                                                CAUSTICA_MIRRORED(AdaptivePush, converge_level),
                                                CAUSTICA_MIRRORED(AdaptivePush, batch),
                                                CAUSTICA_MIRRORED(AdaptivePush, light_size_log2),
                                                CAUSTICA_MIRRORED(AdaptivePush, splat_levels),
                                                CAUSTICA_MIRRORED(AdaptivePush, coverage_seeded),
                                                CAUSTICA_MIRRORED(AdaptivePush, converge_spread),
                                                CAUSTICA_MIRRORED(AdaptivePush, counter_slot),
                                                CAUSTICA_MIRRORED(AdaptivePush, band),
                                                CAUSTICA_MIRRORED(AdaptivePush, jitter),
                                                CAUSTICA_MIRRORED(AdaptivePush, kernel_scale)};
    for (const auto& member : exact_path_push_members(offsetof(AdaptivePush, exact))) members.push_back(member);
    interface.check_push("AdaptivePush", sizeof(AdaptivePush), members);
  }

  bool hierarchical_;
  bool uses_coverage_ = false;
  float converge_spread_ = 0.0f;
  vk::Pipeline args_, combine_, coverage_pipeline_, levels_, clear_;
  PhotonKernel photons_;
  vk::Buffer lists_, control_, coverage_, pyramid_;
  ExactPaths exact_;
  uint32_t max_level_ = 0, converge_level_ = 0, capacity_ = 0, starts_per_batch_ = 1, light_size_log2_ = 0, splat_levels_ = 1;
  uint32_t slots_[6] = {}, sum_slots_[3] = {}, peak_slot_ = 0, batches_slot_ = 0;
  std::vector<uint32_t> level_slots_;
};

std::vector<graph::ParamDecl> traversal_params(bool adaptive) {
  using namespace graph;
  auto params = photon_path_params();
  params.push_back({"grid",
                    ParamType::int_,
                    2048,
                    64.0,
                    65536.0,
                    {},
                    "effective photon grid per side: the traversal's last level, each level doubling the 64 x 64 start grid",
                    false,
                    true});
  if (adaptive) {
    params.push_back({"criterion",
                      ParamType::choice,
                      "hybrid",
                      {},
                      {},
                      {"max_level", "max_error", "hybrid"},
                      "max_level: refine to the last level; max_error: output a cluster whose photons land in one caustic-map texel; "
                      "hybrid: max_level below converge_from, max_error from there"});
    params.push_back(
        {"converge_from", ParamType::int_, 512, 64.0, 65536.0, {}, "hybrid: the photon grid from which clusters may converge"});
    params.push_back({"converge_test",
                      ParamType::choice,
                      "within_texel",
                      {},
                      {},
                      {"same_texel", "within_texel"},
                      "max_error and hybrid: same_texel (the paper) converges a cluster whose four photons land in one caustic-map "
                      "texel; within_texel one whose landing points lie less than converge_spread texels apart on both axes. Either "
                      "way its power is spread over its footprint: a box around their centroid twice their spread wide (at least a "
                      "texel)"});
    params.push_back({"converge_spread",
                      ParamType::float_,
                      1.5,
                      0.25,
                      4.0,
                      {},
                      "within_texel: how far apart (caustic-map texels, on both axes) a cluster's landing points may lie to converge"});
    params.push_back({"coverage_seeding",
                      ParamType::bool_,
                      true,
                      {},
                      {},
                      {},
                      "keep a cluster whose four photons all miss when the light-view coverage pyramid shows a refractor under it, "
                      "so refractors smaller than the 64 x 64 start grid's spacing are found; false: the paper's traversal"});
  }
  params.push_back({"memory_mib", ParamType::int_, 64, 1.0, 120.0, {}, "bound on the cluster lists; batches keep the traversal within it"});
  params.push_back({"splat_levels",
                    ParamType::int_,
                    4,
                    1.0,
                    8.0,
                    {},
                    "levels of the multi-resolution caustic map: a photon whose cluster's landing points spread n texels splats "
                    "into the level with texels n wide; 1: everything into the finest"});
  params.push_back({"fresnel", ParamType::bool_, true, {}, {}, {}, "weight photons by the Fresnel transmittance of both interfaces"});
  params.push_back(caustic_view_param());
  params.push_back({"jitter",
                    ParamType::bool_,
                    false,
                    {},
                    {},
                    {},
                    "move the start grid and its subdivisions within their cells from frame to frame (an R2 sequence, the centre "
                    "first, as caustic_map's jitter) and shrink the coarse splats by kernel_alpha: an accumulate pass averages "
                    "successive maps into the map of a finer traversal"});
  params.push_back({"kernel_alpha",
                    ParamType::float_,
                    2.0 / 3.0,
                    0.01,
                    1.0,
                    {},
                    "with jitter: Knaus and Zwicker's alpha; on the i-th frame since the reset the footprint of a splat that stands "
                    "for a coarse cluster (its multi-resolution level, a converged cluster's box) is scaled by r_i / r_0, where "
                    "r_{i+1}^2 = r_i^2 (i + alpha) / (i + 1), down to one texel, keeping its power (1: no shrinking)"});
  return params;
}

const char* kTraversalCounters =
    "Counters photons.processed(.level<L>), photons.splatted, photons.dropped_miss, photons.dropped_tir, photons.converged, "
    "photons.batches, photons.peak_bytes, photons.overflow, caustic.flux, caustic.flux_entering, caustic.flux_dropped.";

std::vector<graph::PortDecl> traversal_ports() {
  using namespace graph;
  auto ports = photon_ports();
  ports.push_back({"caustic_levels",
                   PortAccess::write,
                   ResourceKind::image,
                   PortUsage::storage,
                   {Format::r32f},
                   true,
                   "",
                   "optional, for inspection: the multi-resolution map's levels as splatted, side by side (level 0 at the left, "
                   "each next level half as large to the right of the one before), as flux per level-0 texel; twice as wide "
                   "as caustic_map and as high, a layer per colour channel; written only when a pass reads it, it is a graph output "
                   "or it is kept",
                   false,
                   3});
  return ports;
}

// What the traversal needs that its declarations cannot state, checked by the compiler so that
// `validate` refuses it too.
graph::PassCheck check_traversal(bool hierarchical, const nlohmann::json& p, const graph::PortResources& resource) {
  graph::PassCheck check;
  const uint32_t grid = p["grid"].get<uint32_t>();
  const uint64_t per_start = uint64_t{1} << (2 * log2_exact(grid / 64));  // a start cluster's clusters at the last level
  const uint64_t capacity = std::min<uint64_t>((p["memory_mib"].get<uint64_t>() << 20) / 8, UINT32_MAX / 2);
  const uint32_t light_size = resource("front")->width;
  const graph::PlannedResource* levels = resource("caustic_levels");
  const graph::PlannedResource& map = *resource("caustic_map");
  if ((hierarchical || p["coverage_seeding"].get<bool>()) && (1u << log2_exact(light_size)) != light_size) {
    check.error = "the light-view buffers are " + std::to_string(light_size) + " wide; the coverage pyramid needs a power of two" +
                  (hierarchical ? "" : " (or set coverage_seeding to false)");
  } else if (per_start > capacity) {
    check.error =
        "grid " + std::to_string(grid) + " needs memory_mib of at least " + std::to_string((per_start * 8 + (1u << 20) - 1) >> 20);
  } else if (levels && (levels->width != 2 * map.width || levels->height != map.height)) {
    check.error =
        "output 'caustic_levels' ('" + levels->name + "', " + std::to_string(levels->width) + " x " + std::to_string(levels->height) +
        ") must be twice as wide as 'caustic_map' and as high: " + std::to_string(2 * map.width) + " x " + std::to_string(map.height);
  }
  return check;
}

graph::PassTypeDecl traversal_pass_type(bool hierarchical, std::string type, std::string description) {
  using namespace graph;
  PassTypeDecl decl{std::move(type),
                    std::move(description) + kTraversalCounters,
                    PassQueue::compute,
                    traversal_ports(),
                    traversal_params(!hierarchical),
                    false,
                    [hierarchical] { return std::make_unique<AdaptiveCausticMapPass>(hierarchical); }};
  decl.needs_scene = true;
  decl.uses_light_view = [](const nlohmann::json&) { return true; };
  // A jittered grid moves every frame (a progressive graph).
  decl.depends_on = [](const nlohmann::json& resolved) {
    return kDependsOnGeometry | kDependsOnLights | (resolved.value("jitter", false) ? kDependsOnFrame : 0u);
  };
  decl.traces_scene = traces_exact_paths;
  decl.check = [hierarchical](const nlohmann::json& params, const PortResources& resource) {
    return check_traversal(hierarchical, params, resource);
  };
  return decl;
}

}  // namespace

graph::PassTypeDecl adaptive_caustic_map_pass_type() {
  return traversal_pass_type(false, "adaptive_caustic_map",
                             "Adaptive caustic map (Wyman and Nichols 2009): a 64 x 64 photon grid refined by 2 x 2 clusters towards the "
                             "effective grid on the device (atomic append, indirect dispatch, no read-back), with the max-level, "
                             "max-error or hybrid termination and batching within a memory bound. ");
}

graph::PassTypeDecl hierarchical_caustic_map_pass_type() {
  return traversal_pass_type(true, "hierarchical_caustic_map",
                             "Hierarchical caustic map (Wyman 2008): a max pyramid of the light-view refractor coverage is traversed top "
                             "down by 2 x 2 clusters, skipping regions without refractor; only the effective grid's photons under "
                             "refractors are traced (light-view buffers must be a power of two wide). ");
}

}  // namespace caustica::passes
