// shadow_map: depth of the scene from a light, for shadowed direct lighting: a spot light's frustum,
// a directional light's prism, or a point light's six cube faces into the layers of its image.
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
    const uint32_t light = ctx.params()["light"].get<uint32_t>();
    const auto& lights = ctx.scene().lights();
    const auto& views = ctx.scene().caustic_views();
    const scene::Light& l = lights[std::min<size_t>(light, lights.size() - 1)];
    // Without refractors the map is a caustic's receivers, drawn from caustic view `light`, as its
    // refractor buffers and photons are.
    const bool receivers = !ctx.params()["refractors_cast_shadows"].get<bool>();
    if (receivers && views[std::min<size_t>(light, views.size() - 1)].present) {
      draw(ctx, caustic_view(ctx, light), ctx.view("depth"));
    } else if (!receivers && l.type == scene::LightType::point && ctx.resource("depth").layers == 6) {
      for (uint32_t face = 0; face < 6; ++face)
        draw(ctx, SceneView{l.face_view_projection(face), l.view.position, scene::Light::face_axis(face), false},
             ctx.layer_view("depth", face));
    } else if (!receivers && l.type != scene::LightType::point) {
      draw(ctx, light_view(ctx, light), ctx.view("depth"));
    } else {
      // A point light's shadow in a map of one layer (a graph made for a spot light), or a point
      // light's receivers without a caustic view, is left cleared: lighting reads a point light's
      // shadow only where it has six faces, and its caustic passes are culled.
      begin_rendering(ctx.cmd(), ctx.extent("depth"), {}, Attachment{ctx.view("depth")});
      vkCmdEndRendering(ctx.cmd());
    }
  }

 private:
  void draw(graph::PassContext& ctx, const SceneView& view, VkImageView target) const {
    VkCommandBuffer cmd = ctx.cmd();
    begin_rendering(cmd, ctx.extent("depth"), {}, Attachment{target});
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_.pipeline.get());
    scene_descriptors(ctx, pipeline_).push(ctx.vk(), cmd, pipeline_);
    bind_scene_textures(ctx, cmd, pipeline_);
    const DrawPush push(view);
    vkCmdPushConstants(cmd, pipeline_.layout.get(), pipeline_.stages, 0, sizeof(push), &push);
    draw_range(cmd, ctx.scene(), ctx.scene().opaque());
    if (ctx.params()["refractors_cast_shadows"].get<bool>()) draw_range(cmd, ctx.scene(), ctx.scene().refractors());
    vkCmdEndRendering(cmd);
  }

  vk::Pipeline pipeline_;
};

}  // namespace

graph::PassTypeDecl shadow_map_pass_type() {
  using namespace graph;
  PassTypeDecl decl{
      "shadow_map",
      "Depth of the scene from a light: a spot light's frustum, a directional light's prism, a point light's six "
      "cube faces (the image then has six layers: \"layers\": \"1 + 5 * light.point\" in a per-light graph). Without "
      "refractors (refractors_cast_shadows false) it is a caustic's receiver depth, drawn from the light's caustic view "
      "(a frustum or prism fitted to its refractors) as the light-space refractor buffers and photons are.",
      PassQueue::graphics,
      {{"depth", PortAccess::write, ResourceKind::image, PortUsage::depth_attachment, {Format::d32f}, false, "", "light-view depth"}},
      {{"light",
        ParamType::int_,
        0,
        0.0,
        CAUSTICA_MAX_CAUSTIC_VIEWS - 1,
        {},
        "which light (the last one if fewer); with refractors_cast_shadows false, which caustic view (light K's is K, a point "
        "light's further cube faces follow the lights')"},
       {"refractors_cast_shadows",
        ParamType::bool_,
        true,
        {},
        {},
        {},
        "refractors block direct light (caustics then bring the refracted light back); false: the receivers of the light's "
        "caustic, from its caustic view"}},
      false,
      [] { return std::make_unique<ShadowMapPass>(); }};
  decl.ports.front().cube_layers = true;
  decl.needs_scene = true;
  decl.depends_on = [](const nlohmann::json&) { return kDependsOnGeometry | kDependsOnLights; };
  return decl;
}

}  // namespace caustica::passes
