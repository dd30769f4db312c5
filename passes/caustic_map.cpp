// caustic_map: the regular caustic map. One photon per texel of an N x N grid in the light's view,
// refracted through two interfaces, landed on the receivers and splatted into a light-space map of
// flux per texel, which lighting projects back onto the receivers.
#include <cstddef>

#include "builtin_passes.h"
#include "core/error.h"
#include "core/low_discrepancy.h"
#include "photon_kernel.h"
#include "scene_draw.h"

namespace caustica::passes {
namespace {

struct PhotonPush {
  uint32_t distance_mode;
  uint32_t search;
  float search_distance;
  uint32_t light;
  uint32_t grid;
  uint32_t fresnel;
  uint32_t counter_slot[8];
  ExactPathPush exact;
  uint32_t band;
  float jitter[2];           // where in its grid cell each photon starts
  uint32_t slice_offset[2];  // this frame's slice: the cells at slice_offset + slice_side * (i, j)
  uint32_t slice_side;
};

class CausticMapPass final : public graph::Pass {
 public:
  void setup(graph::PassSetup& setup) override {
    require_photon_features(setup, "caustic_map");
    using Kind = graph::PassSetup::CounterKind;
    const char* counts[] = {"photons.processed", "photons.splatted", "photons.dropped_miss", "photons.dropped_tir",
                            "photons.processed.level0"};
    const char* sums[] = {"caustic.flux", "caustic.flux_entering", "caustic.flux_dropped"};
    for (int i = 0; i < 5; ++i) slots_[i] = setup.add_counter(counts[i]);
    for (int i = 0; i < 3; ++i) slots_[5 + i] = setup.add_counter(sums[i], Kind::sum);
    // Reported by every caustic method; the regular map is one batch of one level, converges
    // nothing and keeps no photon lists.
    setup.add_counter("photons.converged");
    setup.add_counter("photons.peak_bytes");
    batches_slot_ = setup.add_counter("photons.batches");
    exact_.setup(setup);
    clear_ = make_caustic_clear_pipeline(setup);
    const shader::Defines defines = refraction_defines(setup, exact_.defines());
    const vk::PipelineDesc layout = setup.shared_layout("regular_photons", {{"caustics/regular_photons.comp", defines}});
    std::vector<shader::MirroredMember> members{CAUSTICA_MIRRORED(PhotonPush, distance_mode),
                                                CAUSTICA_MIRRORED(PhotonPush, search),
                                                CAUSTICA_MIRRORED(PhotonPush, search_distance),
                                                CAUSTICA_MIRRORED(PhotonPush, light),
                                                CAUSTICA_MIRRORED(PhotonPush, grid),
                                                CAUSTICA_MIRRORED(PhotonPush, fresnel),
                                                CAUSTICA_MIRRORED(PhotonPush, counter_slot),
                                                CAUSTICA_MIRRORED(PhotonPush, band),
                                                CAUSTICA_MIRRORED(PhotonPush, jitter),
                                                CAUSTICA_MIRRORED(PhotonPush, slice_offset),
                                                CAUSTICA_MIRRORED(PhotonPush, slice_side)};
    for (const auto& member : exact_path_push_members(offsetof(PhotonPush, exact))) members.push_back(member);
    layout.interface->check_push("PhotonPush", sizeof(PhotonPush), members);
    photons_.build(setup, layout, "caustics/regular_photons.comp", defines, !exact_.traced());
  }

  // slice_side is sampling-only: a plan that changes it goes on with this one's runs of the grid.
  void continue_from(graph::Pass& earlier) override { runs_ = static_cast<CausticMapPass&>(earlier).runs_; }

  void execute(graph::PassContext& ctx) override {
    VkCommandBuffer cmd = ctx.cmd();
    record_caustic_clear(ctx, clear_);

    const auto& p = ctx.params();
    const RefractionPush shared = refraction_push(ctx, 0);
    PhotonPush push{shared.distance_mode,
                    shared.search,
                    shared.search_distance,
                    p["light"].get<uint32_t>(),
                    p["grid"].get<uint32_t>(),
                    p["fresnel"].get<bool>() ? 1u : 0u,
                    {},
                    exact_.push(ctx),
                    kWhiteBand};
    for (int i = 0; i < 8; ++i) push.counter_slot[i] = slots_[i];
    // One cell in slice_side x slice_side a frame, another each frame since the reset (or since
    // slice_side changed), so that each run of slice_side^2 frames traces the whole grid once
    // (column k mod n, each column's rows in a turned order, so that successive slices lie apart).
    const uint32_t side = p["slice_side"].get<uint32_t>();
    const uint64_t slices = uint64_t{side} * side, since_reset = ctx.frame().since_reset;
    if (since_reset == 0 || runs_.side == 0) {
      runs_ = {side, 0, 0, 0};
    } else if (side != runs_.side) {
      // A new side starts a run of its own at the next point of the sequence: at the old run's
      // point its slices would trace photons the old side's slices had traced. Where the old run
      // was cut short, its cells keep one sample more than the others until the mean outgrows it.
      const uint64_t old_slices = uint64_t{runs_.side} * runs_.side;
      runs_ = {side, since_reset, runs_.first_run + (runs_.last - runs_.from) / old_slices + 1, 0};
    }
    runs_.last = since_reset;
    const uint64_t at_side = since_reset - runs_.from, slice = at_side % slices;
    push.slice_offset[0] = static_cast<uint32_t>(slice % side);
    push.slice_offset[1] = static_cast<uint32_t>((slice / side + slice) % side);
    push.slice_side = side;
    // Where in its grid cell each photon starts: the cell's centre on the first run of the grid after
    // a reset, then points that cover the cell evenly, so that the mean of successive maps
    // (accumulate) converges to the map of a finer grid. One point per run of the grid: a run of
    // slices is the whole grid's frame, and a cell's successive points are the sequence's own
    // (every n^2-th point of it would cover the cell poorly: 4 R2 steps move x by 0.02).
    const glm::vec2 jitter = r2_point(p["jitter"].get<bool>() ? runs_.first_run + at_side / slices : 0);
    push.jitter[0] = jitter.x;
    push.jitter[1] = jitter.y;
    const uint32_t traced_side = (push.grid + side - 1) / side;
    const PhotonKernel::Passes passes = photons_.passes(ctx.scene().scene());
    const vk::Pipeline& photons = passes.pipeline;
    ctx.set_counter(batches_slot_, static_cast<uint32_t>(passes.bands.size()));
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, photons.pipeline.get());
    photon_descriptors(ctx, photons, exact_).push(ctx.vk(), cmd, photons);
    exact_.bind_textures(ctx, photons);
    for (uint32_t band : passes.bands) {  // the bands add into one map; atomics need no order between them
      push.band = band;
      vkCmdPushConstants(cmd, photons.layout.get(), photons.stages, 0, sizeof(push), &push);
      vkCmdDispatch(cmd, (traced_side + 7) / 8, (traced_side + 7) / 8, 1);
    }
  }

 private:
  vk::Pipeline clear_;
  PhotonKernel photons_;
  ExactPaths exact_;
  uint32_t slots_[8] = {};
  uint32_t batches_slot_ = 0;
  // The runs of the grid at the current slice_side: since which frame since the reset, the jitter
  // point of the first, and the frame last traced.
  struct Runs {
    uint32_t side = 0;
    uint64_t from = 0, first_run = 0, last = 0;
  } runs_;
};

}  // namespace

graph::PassTypeDecl caustic_map_pass_type() {
  using namespace graph;
  auto params = photon_path_params();
  params.push_back({"grid", ParamType::int_, 512, 16.0, 16384.0, {}, "photons per side of the grid over the light's image plane", true});
  params.push_back({"fresnel", ParamType::bool_, true, {}, {}, {}, "weight photons by the Fresnel transmittance of both interfaces"});
  params.push_back(caustic_view_param());
  params.push_back({"jitter",
                    ParamType::bool_,
                    false,
                    {},
                    {},
                    {},
                    "move each photon within its grid cell from frame to frame (an R2 sequence, the centre first) instead of "
                    "starting it at the centre: successive maps sample different photons, and an accumulate pass averages them "
                    "into the map of a finer grid"});
  params.push_back({"slice_side",
                    ParamType::int_,
                    1,
                    1.0,
                    16.0,
                    {},
                    "trace one photon in slice_side x slice_side of the grid each frame, its power times slice_side^2, a different "
                    "one each frame since the reset: each map costs 1/slice_side^2 of the grid's and is noisier, and the mean of "
                    "slice_side^2 successive maps (accumulate) is the whole grid's (1: every photon every frame); a mean goes on "
                    "when it changes",
                    true,
                    false,
                    true});
  PassTypeDecl decl{
      "caustic_map",
      "Regular caustic map: an N x N photon grid over the light's image plane, each photon refracted through two interfaces and "
      "splatted (nearest texel) into a light-space map of flux per texel. Counters photons.processed, photons.splatted, "
      "photons.dropped_miss, photons.dropped_tir, caustic.flux, caustic.flux_entering, caustic.flux_dropped.",
      PassQueue::compute,
      photon_ports(),
      params,
      false,
      [] { return std::make_unique<CausticMapPass>(); }};
  decl.needs_scene = true;
  decl.uses_light_view = [](const nlohmann::json&) { return true; };
  // A jittered grid moves every frame (the progressive graph).
  decl.depends_on = [](const nlohmann::json& resolved) {
    return kDependsOnGeometry | kDependsOnLights |
           (resolved.value("jitter", false) || resolved.value("slice_side", 1) > 1 ? kDependsOnFrame : 0u);
  };
  decl.traces_scene = traces_exact_paths;
  return decl;
}

}  // namespace caustica::passes
