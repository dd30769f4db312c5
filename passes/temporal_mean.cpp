// temporal_mean: the running mean of a colour image over the frames since its last reset, kept in
// the graph itself: the pass reads its own last result through a history input
// ("AVERAGE@previous", graph::PlannedResource::previous_of), so the compiler, not the pass, owns the
// memory, the barriers and the restart (all zeros, on a plan's first frame and whenever a scene
// part that the image depends on changes: for a camera image, the camera too).
#include "builtin_passes.h"
#include "graph/pass.h"
#include "vk/pipeline.h"

namespace caustica::passes {
namespace {

struct TemporalMeanPush {
  uint32_t size[2];
  float weight;  // of this frame: 1 / frames in the mean, 0 once it holds
};

class TemporalMeanPass final : public graph::Pass {
 public:
  void setup(graph::PassSetup& setup) override {
    pipeline_ = setup.compute_pipeline("temporal_mean", {"core/temporal_mean.comp", {}});
    pipeline_.interface->check_push("TemporalMeanPush", sizeof(TemporalMeanPush),
                                    {CAUSTICA_MIRRORED(TemporalMeanPush, size), CAUSTICA_MIRRORED(TemporalMeanPush, weight)});
    frames_slot_ = setup.add_counter(setup.pass().name + ".frames");
  }

  void execute(graph::PassContext& ctx) override {
    const uint64_t max_frames = ctx.params()["max_frames"].get<uint64_t>();
    const uint64_t frame = ctx.frame().since_reset + 1;  // this frame's place in the mean
    const bool holds = frame > max_frames;
    ctx.set_counter(frames_slot_, static_cast<double>(std::min(frame, max_frames)));
    if (frame < max_frames) ctx.still_converging();

    const VkExtent2D extent = ctx.extent("average");
    const TemporalMeanPush push{{extent.width, extent.height}, holds ? 0.0f : 1.0f / static_cast<float>(frame)};
    vk::dispatch_over_image(ctx.vk(), ctx.cmd(), pipeline_,
                            vk::DescriptorWriter()
                                .image("current", ctx.view("current"), ctx.nearest_sampler())
                                .image("previous", ctx.view("previous"), ctx.nearest_sampler())
                                .image("average", ctx.view("average")),
                            vk::bytes_of(push), extent);
  }

 private:
  vk::Pipeline pipeline_;
  uint32_t frames_slot_ = 0;
};

}  // namespace

graph::PassTypeDecl temporal_mean_pass_type() {
  using namespace graph;
  PassTypeDecl decl{"temporal_mean",
                    "Compute pass: the running mean of a colour image over the frames since the last reset, from this frame's image and "
                    "the mean as the last frame left it (bind 'previous' to the history of 'average': \"AVERAGE@previous\"). It restarts "
                    "wherever that history does: on a new plan and when a scene part its image depends on changes. Counter "
                    "<pass>.frames: the frames in the mean.",
                    PassQueue::compute,
                    {{"current",
                      PortAccess::read,
                      ResourceKind::image,
                      PortUsage::sampled,
                      {Format::rgba16f, Format::rgba32f},
                      false,
                      "frame",
                      "this frame's image"},
                     {"previous",
                      PortAccess::read,
                      ResourceKind::image,
                      PortUsage::sampled,
                      {Format::rgba32f},
                      false,
                      "frame",
                      "the mean as the last frame left it: the history of 'average' (\"AVERAGE@previous\"), all zeros after a reset"},
                     {"average",
                      PortAccess::write,
                      ResourceKind::image,
                      PortUsage::storage,
                      {Format::rgba32f},
                      false,
                      "frame",
                      "the mean of the frames since the last reset, same extent"}},
                    {{"max_frames", ParamType::int_, 64, 1.0, 1048576.0, {}, "frames averaged; after them the mean holds still", true},
                     {"jitter_camera",
                      ParamType::bool_,
                      false,
                      {},
                      {},
                      {},
                      "move the camera within its pixels from frame to frame while it stands still (every pass that sees the camera "
                      "then draws every frame), so that the mean of a camera image is antialiased; the first frame after a move is "
                      "unmoved"}},
                    false,
                    [] { return std::make_unique<TemporalMeanPass>(); }};
  // Nothing of its own: its inputs bring what it depends on, and the history input the frame.
  decl.depends_on = [](const nlohmann::json&) { return 0u; };
  decl.jitters_camera = [](const nlohmann::json& params) { return params.value("jitter_camera", false); };
  return decl;
}

}  // namespace caustica::passes
