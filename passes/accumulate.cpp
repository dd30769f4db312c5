// accumulate: the running mean of an image over frames (Falcor's AccumulatePass, for light-space
// maps): an image whose every frame is an independent estimate of the same answer, a jittered
// photon grid's caustic map, converges to the mean of many. The sum is history the pass keeps: reset
// on any change of a scene part its input depends on (graph::FrameInfo::since_reset): for a caustic
// map not a moving camera; and on a new plan in which it or what it reads changed (a plan that
// changed neither continues it: continue_from).
#include "builtin_passes.h"
#include "graph/pass.h"
#include "vk/buffer.h"
#include "vk/pipeline.h"

namespace caustica::passes {
namespace {

struct AccumulatePush {
  uint32_t size[2];
  uint32_t layers;
  uint32_t mode;  // shaders/core/accumulate.comp's MODE_*
  float weight;
  float total_weight;
};
constexpr uint32_t kModeStart = 0, kModeAdd = 1, kModeHold = 2;
constexpr uint32_t kLayers = 3;

class AccumulatePass final : public graph::Pass {
 public:
  void setup(graph::PassSetup& setup) override {
    const graph::PlannedResource& source = setup.resource("source");
    sums_ = vk::make_buffer(setup.vk(), uint64_t{source.width} * source.height * kLayers * 2 * sizeof(float),
                            VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, 0, setup.pass().name + " sums");
    pipeline_ = setup.compute_pipeline("accumulate", {"core/accumulate.comp", {}});
    pipeline_.interface->check_push(
        "AccumulatePush", sizeof(AccumulatePush),
        {CAUSTICA_MIRRORED(AccumulatePush, size), CAUSTICA_MIRRORED(AccumulatePush, layers), CAUSTICA_MIRRORED(AccumulatePush, mode),
         CAUSTICA_MIRRORED(AccumulatePush, weight), CAUSTICA_MIRRORED(AccumulatePush, total_weight)});
    frames_slot_ = setup.add_counter(setup.pass().name + ".frames");
  }

  void continue_from(graph::Pass& earlier) override {
    auto& was = static_cast<AccumulatePass&>(earlier);
    sums_ = std::move(was.sums_);
    frames_ = was.frames_;
    total_weight_ = was.total_weight_;
  }

  void execute(graph::PassContext& ctx) override {
    if (ctx.frame().since_reset == 0) frames_ = 0;
    const auto max_frames = ctx.params()["max_frames"].get<uint32_t>();
    const auto weight = ctx.params()["weight"].get<double>();
    const uint32_t mode = frames_ == 0 ? kModeStart : frames_ < max_frames ? kModeAdd : kModeHold;
    if (mode == kModeStart) total_weight_ = 0;
    if (mode != kModeHold) {
      ++frames_;
      total_weight_ += weight;
    }
    ctx.set_counter(frames_slot_, frames_);
    ctx.holds_frames(frames_);
    if (frames_ < max_frames) ctx.still_converging();

    const VkExtent2D extent = ctx.extent("source");
    const AccumulatePush push{{extent.width, extent.height}, kLayers, mode, static_cast<float>(weight), static_cast<float>(total_weight_)};
    VkCommandBuffer cmd = ctx.cmd();
    // The previous frame's sums, written in an earlier submission.
    vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                       VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    vk::dispatch_over_image(ctx.vk(), cmd, pipeline_,
                            vk::DescriptorWriter()
                                .image("source", ctx.view("source"), ctx.nearest_sampler())
                                .image("average", ctx.view("average"))
                                .buffer("SumBlock", sums_.get()),
                            vk::bytes_of(push), extent, kLayers);
  }

 private:
  vk::Pipeline pipeline_;
  vk::Buffer sums_;
  uint32_t frames_slot_ = 0;
  uint32_t frames_ = 0;      // in the sum
  double total_weight_ = 0;  // of the frames in the sum
};

}  // namespace

graph::PassTypeDecl accumulate_pass_type() {
  using namespace graph;
  PassTypeDecl decl{"accumulate",
                    "Compute pass: the running mean of a caustic map (r32f, a layer per colour channel) over the frames since the last "
                    "reset, each frame weighed by weight, summed in fp32 with Kahan's compensation. Resets when the lights, the geometry "
                    "or the materials change, not when the camera moves, and on a new plan that changed it or what it reads "
                    "(parameters other than sampling-only ones, sizes, its source's passes); where a viewer or editor's new plan "
                    "changed neither, the mean goes on. "
                    "Counter <pass>.frames: the frames in the mean.",
                    PassQueue::compute,
                    {{"source",
                      PortAccess::read,
                      ResourceKind::image,
                      PortUsage::sampled,
                      {Format::r32f},
                      false,
                      "maps",
                      "this frame's estimate, e.g. a caustic_map with jitter on",
                      false,
                      kLayers},
                     {"average",
                      PortAccess::write,
                      ResourceKind::image,
                      PortUsage::storage,
                      {Format::r32f},
                      false,
                      "maps",
                      "the mean of the frames since the last reset, same extent and layers",
                      false,
                      kLayers}},
                    {{"max_frames",
                      ParamType::int_,
                      1024,
                      1.0,
                      1048576.0,
                      {},
                      "frames averaged; after them the mean holds still (the sources still run every frame)",
                      true},
                     {"weight",
                      ParamType::float_,
                      1.0,
                      1e-6,
                      1e6,
                      {},
                      "how much this frame counts in the mean against the others: a frame that estimates from a part of the "
                      "samples counts that part (a caustic_map's slices: 1 / slice_side^2), so that the mean stays one over "
                      "samples when the part changes",
                      true,
                      false,
                      true}},
                    false,
                    [] { return std::make_unique<AccumulatePass>(); }};
  decl.accumulates = true;
  return decl;
}

}  // namespace caustica::passes
