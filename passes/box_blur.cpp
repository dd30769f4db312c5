// box_blur: a compute pass that filters a sampled image along one axis into a storage image.
#include "builtin_passes.h"
#include "graph/pass.h"
#include "vk/pipeline.h"

namespace caustica::passes {
namespace {

struct BlurParams {
  int32_t size[2];
  int32_t axis[2];
  int32_t radius;
};

class BoxBlurPass final : public graph::Pass {
 public:
  void setup(graph::PassSetup& setup) override {
    const auto& target = setup.resource("target");
    pipeline_ =
        setup.compute_pipeline("box_blur", {"core/box_blur.comp", {{"OUT_FORMAT", graph::format_info(target.format).glsl_qualifier}}});
    pipeline_.interface->check_push(
        "BlurParams", sizeof(BlurParams),
        {CAUSTICA_MIRRORED(BlurParams, size), CAUSTICA_MIRRORED(BlurParams, axis), CAUSTICA_MIRRORED(BlurParams, radius)});
  }

  void execute(graph::PassContext& ctx) override {
    const VkExtent2D extent = ctx.extent("target");
    const bool vertical = ctx.params()["axis"].get<std::string>() == "y";
    BlurParams params{{static_cast<int32_t>(extent.width), static_cast<int32_t>(extent.height)},
                      {vertical ? 0 : 1, vertical ? 1 : 0},
                      ctx.params()["radius"].get<int32_t>()};
    vk::dispatch_over_image(
        ctx.vk(), ctx.cmd(), pipeline_,
        vk::DescriptorWriter().image("source", ctx.view("source"), ctx.nearest_sampler()).image("target", ctx.view("target")),
        vk::bytes_of(params), extent);
  }

 private:
  vk::Pipeline pipeline_;
};

}  // namespace

graph::PassTypeDecl box_blur_pass_type() {
  using namespace graph;
  PassTypeDecl decl{"box_blur",
                    "Compute pass: a box filter along one axis, edges clamped; two of them make a separable blur.",
                    PassQueue::compute,
                    {{"source", PortAccess::read, ResourceKind::image, PortUsage::sampled, {}, false, "frame", "image to filter"},
                     {"target",
                      PortAccess::write,
                      ResourceKind::image,
                      PortUsage::storage,
                      {Format::rgba16f, Format::rgba32f},
                      false,
                      "frame",
                      "filtered image, same extent"}},
                    {{"radius", ParamType::int_, 2, 0.0, 64.0, {}, "texels on each side", true},
                     {"axis", ParamType::choice, "x", {}, {}, {"x", "y"}, "filter direction"}},
                    false,
                    [] { return std::make_unique<BoxBlurPass>(); }};
  decl.depends_on = [](const nlohmann::json&) { return 0u; };  // its input and parameters alone
  return decl;
}

}  // namespace caustica::passes
