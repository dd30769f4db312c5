// tonemap: a compute pass from linear HDR to 8-bit sRGB, reporting how many pixels exceeded white.
#include "builtin_passes.h"
#include "graph/pass.h"
#include "vk/pipeline.h"

namespace caustica::passes {
namespace {

struct TonemapParams {
  int32_t size[2];
  float exposure;
  uint32_t bright_counter;
};

class TonemapPass final : public graph::Pass {
 public:
  void setup(graph::PassSetup& setup) override {
    bright_counter_ = setup.add_counter("tonemap.bright_pixels");
    pipeline_ = setup.compute_pipeline("tonemap", {"core/tonemap.comp", {}});
    pipeline_.interface->check_push("TonemapParams", sizeof(TonemapParams),
                                    {CAUSTICA_MIRRORED(TonemapParams, size), CAUSTICA_MIRRORED(TonemapParams, exposure),
                                     CAUSTICA_MIRRORED(TonemapParams, bright_counter)});
  }

  void execute(graph::PassContext& ctx) override {
    const VkExtent2D extent = ctx.extent("target");
    TonemapParams params{
        {static_cast<int32_t>(extent.width), static_cast<int32_t>(extent.height)}, ctx.params()["exposure"].get<float>(), bright_counter_};
    vk::dispatch_over_image(ctx.vk(), ctx.cmd(), pipeline_,
                            vk::DescriptorWriter()
                                .image("source", ctx.view("source"), ctx.nearest_sampler())
                                .image("target", ctx.view("target"))
                                .buffer("Counters", ctx.counter_buffer()),
                            vk::bytes_of(params), extent);
  }

 private:
  vk::Pipeline pipeline_;
  uint32_t bright_counter_ = 0;
};

}  // namespace

graph::PassTypeDecl tonemap_pass_type() {
  using namespace graph;
  PassTypeDecl decl{
      "tonemap",
      "Compute pass: exposure, 1 - exp(-x) tonemap, sRGB encode into an 8-bit image. Counter tonemap.bright_pixels.",
      PassQueue::compute,
      {{"source", PortAccess::read, ResourceKind::image, PortUsage::sampled, {}, false, "frame", "linear HDR"},
       {"target", PortAccess::write, ResourceKind::image, PortUsage::storage, {Format::rgba8}, false, "frame", "display-ready"}},
      {{"exposure", ParamType::float_, 1.0, 0.0, 1000.0, {}, "multiplies the HDR input", true}},
      false,
      [] { return std::make_unique<TonemapPass>(); }};
  decl.depends_on = [](const nlohmann::json&) { return 0u; };  // its input and parameters alone
  return decl;
}

}  // namespace caustica::passes
