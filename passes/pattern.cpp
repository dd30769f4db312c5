// pattern: a full-screen graphics pass drawing an analytic HDR test pattern into a colour attachment.
#include "builtin_passes.h"
#include "graph/pass.h"
#include "vk/pipeline.h"

namespace caustica::passes {
namespace {

struct PatternParams {
  float size[2];
  float sun[2];
  float frequency;
  float sun_intensity;
  float sun_radius;
};

class PatternPass final : public graph::Pass {
 public:
  void setup(graph::PassSetup& setup) override {
    const auto& target = setup.resource("color");
    vk::RasterState state;
    state.color_formats = {graph::format_info(target.format).vk};
    pipeline_ = setup.graphics_pipeline("pattern", {"common/fullscreen.vert", {}}, {"core/pattern.frag", {}}, state);
    pipeline_.interface->check_push(
        "PatternParams", sizeof(PatternParams),
        {CAUSTICA_MIRRORED(PatternParams, size), CAUSTICA_MIRRORED(PatternParams, sun), CAUSTICA_MIRRORED(PatternParams, frequency),
         CAUSTICA_MIRRORED(PatternParams, sun_intensity), CAUSTICA_MIRRORED(PatternParams, sun_radius)});
  }

  void execute(graph::PassContext& ctx) override {
    const VkExtent2D extent = ctx.extent("color");
    const auto& p = ctx.params();
    PatternParams params{{static_cast<float>(extent.width), static_cast<float>(extent.height)},
                         {p["sun_x"].get<float>(), p["sun_y"].get<float>()},
                         p["frequency"].get<float>(),
                         p["sun_intensity"].get<float>(),
                         p["sun_radius"].get<float>()};
    VkRenderingAttachmentInfo color{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    color.imageView = ctx.view("color");
    color.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    color.loadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    VkRenderingInfo rendering{VK_STRUCTURE_TYPE_RENDERING_INFO};
    rendering.renderArea = {{0, 0}, extent};
    rendering.layerCount = 1;
    rendering.colorAttachmentCount = 1;
    rendering.pColorAttachments = &color;
    VkCommandBuffer cmd = ctx.cmd();
    vkCmdBeginRendering(cmd, &rendering);
    VkViewport viewport{0, 0, static_cast<float>(extent.width), static_cast<float>(extent.height), 0, 1};
    VkRect2D scissor{{0, 0}, extent};
    vkCmdSetViewport(cmd, 0, 1, &viewport);
    vkCmdSetScissor(cmd, 0, 1, &scissor);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_.pipeline.get());
    vkCmdPushConstants(cmd, pipeline_.layout.get(), pipeline_.stages, 0, sizeof(params), &params);
    vkCmdDraw(cmd, 3, 1, 0, 0);
    vkCmdEndRendering(cmd);
  }

 private:
  vk::Pipeline pipeline_;
};

}  // namespace

graph::PassTypeDecl pattern_pass_type() {
  using namespace graph;
  PassTypeDecl decl{"pattern",
                    "Full-screen pass: an analytic HDR test pattern (stripes and a Gaussian sun brighter than 1).",
                    PassQueue::graphics,
                    {{"color",
                      PortAccess::write,
                      ResourceKind::image,
                      PortUsage::color_attachment,
                      {Format::rgba16f, Format::rgba32f},
                      false,
                      "",
                      "the pattern, linear HDR"}},
                    {{"frequency", ParamType::float_, 4.0, 0.0, 256.0, {}, "stripes across the image"},
                     {"sun_x", ParamType::float_, 0.7, -1.0, 2.0, {}, "sun centre, 0..1 across"},
                     {"sun_y", ParamType::float_, 0.3, -1.0, 2.0, {}, "sun centre, 0..1 down"},
                     {"sun_intensity", ParamType::float_, 6.0, 0.0, 1000.0, {}, "peak added radiance of the sun"},
                     {"sun_radius", ParamType::float_, 0.08, 0.001, 10.0, {}, "Gaussian radius of the sun, in image widths"}},
                    false,
                    [] { return std::make_unique<PatternPass>(); }};
  decl.depends_on = [](const nlohmann::json&) { return 0u; };  // its input and parameters alone
  return decl;
}

}  // namespace caustica::passes
