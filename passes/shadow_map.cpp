// shadow_map: depth of the scene from a light, for shadowed direct lighting.
#include "builtin_passes.h"
#include "scene_draw.h"

namespace caustica::passes {
namespace {

class ShadowMapPass final : public graph::Pass {
 public:
  void setup(graph::PassSetup& setup) override {
    vk::RasterState state;
    state.depth_format = graph::format_info(setup.resource("depth").format).vk;
    pipeline_ = make_scene_pipeline(setup, "shadow_map", "scene/depth.frag", state);
  }

  void execute(graph::PassContext& ctx) override {
    const VkExtent2D extent = ctx.extent("depth");
    const SceneView view = light_view(ctx, ctx.params()["light"].get<uint32_t>());
    VkCommandBuffer cmd = ctx.cmd();
    begin_rendering(cmd, extent, {}, Attachment{ctx.view("depth")});
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_.pipeline.get());
    scene_descriptors(ctx, pipeline_).push(ctx.vk(), cmd, pipeline_);
    bind_scene_textures(ctx, cmd, pipeline_);
    const DrawPush push(view);
    vkCmdPushConstants(cmd, pipeline_.layout.get(), pipeline_.stages, 0, sizeof(push), &push);
    draw_range(cmd, ctx.scene(), ctx.scene().opaque());
    if (ctx.params()["refractors_cast_shadows"].get<bool>()) draw_range(cmd, ctx.scene(), ctx.scene().refractors());
    vkCmdEndRendering(cmd);
  }

 private:
  vk::Pipeline pipeline_;
};

}  // namespace

graph::PassTypeDecl shadow_map_pass_type() {
  using namespace graph;
  PassTypeDecl decl{"shadow_map",
                    "Depth of the scene from a spot light's frustum.",
                    PassQueue::graphics,
                    {{"depth", PortAccess::write, ResourceKind::image, PortUsage::depth_attachment, {Format::d32f}, false, "", "light-view depth"}},
                    {{"light", ParamType::int_, 0, 0.0, 7.0, {}, "which light (the last one if fewer)"},
                     {"refractors_cast_shadows", ParamType::bool_, true, {}, {}, {},
                      "refractors block direct light (caustics then bring the refracted light back)"}},
                    false,
                    [] { return std::make_unique<ShadowMapPass>(); }};
  decl.needs_scene = true;
  decl.uses_light_view = [](const nlohmann::json&) { return true; };
  decl.depends_on = [](const nlohmann::json&) { return kDependsOnGeometry | kDependsOnLights; };
  return decl;
}

}  // namespace caustica::passes
