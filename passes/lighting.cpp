// lighting: direct light on the G-buffer (all lights, the first one shadowed), ambient, sky.
#include "builtin_passes.h"
#include "core/error.h"
#include "scene_draw.h"

namespace caustica::passes {
namespace {

struct LightingParams {
  float shadow_bias;
  uint32_t has_shadow;
};

class LightingPass final : public graph::Pass {
 public:
  void setup(graph::PassSetup& setup) override {
    has_shadow_ = setup.bound("shadow");
    has_caustics_ = setup.bound("caustics");
    has_caustic_depth_ = has_caustics_ && setup.bound("caustic_depth");
    has_emission_ = setup.bound("emission");
    shader::Defines defines;
    if (has_caustics_) defines["CAUSTICS"] = "1";
    if (has_caustic_depth_) defines["CAUSTIC_DEPTH"] = "1";
    if (has_emission_) defines["EMISSION"] = "1";
    vk::RasterState state;
    state.color_formats = {graph::format_info(setup.resource("color").format).vk};
    pipeline_ = setup.graphics_pipeline("lighting", {"common/fullscreen.vert", {}}, {"scene/lighting.frag", defines}, state);
    pipeline_.interface->check_push("LightingParams", sizeof(LightingParams),
                                    {CAUSTICA_MIRRORED(LightingParams, shadow_bias), CAUSTICA_MIRRORED(LightingParams, has_shadow)});
  }

  void execute(graph::PassContext& ctx) override {
    const VkExtent2D extent = ctx.extent("color");
    VkCommandBuffer cmd = ctx.cmd();
    begin_rendering(cmd, extent, {{ctx.view("color"), VK_ATTACHMENT_LOAD_OP_DONT_CARE}}, std::nullopt);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_.pipeline.get());
    vk::DescriptorWriter writer;
    writer.buffer("FrameBlock", ctx.scene().frame())
        .image("depth_tex", ctx.view("depth"), ctx.nearest_sampler())
        .image("normal_tex", ctx.view("normal"), ctx.nearest_sampler())
        .image("albedo_tex", ctx.view("albedo"), ctx.nearest_sampler())
        .image("shadow_tex", ctx.view(has_shadow_ ? "shadow" : "depth"), ctx.nearest_sampler())  // unread without a shadow map
        .image("caustic_depth_tex", ctx.view(has_caustic_depth_ ? "caustic_depth" : "depth"), ctx.nearest_sampler());  // unread without it
    if (has_caustics_) writer.image("caustics_tex", ctx.view("caustics"), ctx.linear_sampler());
    if (has_emission_) writer.image("emission_tex", ctx.view("emission"), ctx.nearest_sampler());
    writer.push(ctx.vk(), cmd, pipeline_);
    const LightingParams params{ctx.params()["shadow_bias"].get<float>(), has_shadow_ ? 1u : 0u};
    vkCmdPushConstants(cmd, pipeline_.layout.get(), pipeline_.stages, 0, sizeof(params), &params);
    vkCmdDraw(cmd, 3, 1, 0, 0);
    vkCmdEndRendering(cmd);
  }

 private:
  vk::Pipeline pipeline_;
  bool has_shadow_ = false;
  bool has_caustics_ = false;
  bool has_caustic_depth_ = false;
  bool has_emission_ = false;
};

}  // namespace

graph::PassTypeDecl lighting_pass_type() {
  using namespace graph;
  PassTypeDecl decl{
      "lighting",
      "Full-screen pass: direct light from every scene light on the G-buffer (inverse square, spot cone; the first light shadowed "
      "when a shadow map is bound) through each surface's BRDF (Lambertian, or glTF's metallic-roughness), ambient sky light, "
      "emitted light when bound, the sky where there is no geometry. Linear HDR radiance out.",
      PassQueue::graphics,
      {{"depth", PortAccess::read, ResourceKind::image, PortUsage::sampled, {Format::d32f}, false, "frame", "camera depth"},
       {"normal", PortAccess::read, ResourceKind::image, PortUsage::sampled, {}, false, "frame", "world normal"},
       {"albedo", PortAccess::read, ResourceKind::image, PortUsage::sampled, {}, false, "frame", "base colour; alpha: metallic"},
       {"emission",
        PortAccess::read,
        ResourceKind::image,
        PortUsage::sampled,
        {},
        true,
        "frame",
        "emitted radiance, added as it is; alpha: ambient occlusion, which scales the sky light"},
       {"shadow", PortAccess::read, ResourceKind::image, PortUsage::sampled, {Format::d32f}, true, "", "shadow map of the first light"},
       {"caustics",
        PortAccess::read,
        ResourceKind::image,
        PortUsage::sampled,
        {Format::r32f},
        true,
        "",
        "caustic map of the first light: flux per texel of its image plane, a layer per colour channel (caustic_map)",
        false,
        3},
       {"caustic_depth",
        PortAccess::read,
        ResourceKind::image,
        PortUsage::sampled,
        {Format::d32f},
        true,
        "",
        "the first light's depth of opaque geometry, for the caustic map's receiver test (without it the caustic also lands "
        "on surfaces that the light does not see first)"},
       {"color",
        PortAccess::write,
        ResourceKind::image,
        PortUsage::color_attachment,
        {Format::rgba16f, Format::rgba32f},
        false,
        "frame",
        "lit radiance"}},
      {{"shadow_bias", ParamType::float_, 0.02, 0.0, 10.0, {}, "bias of the shadow test, in scene units along the light's axis", true}},
      false,
      [] { return std::make_unique<LightingPass>(); }};
  decl.needs_scene = true;
  decl.depends_on = [](const nlohmann::json&) { return kDependsOnScene; };
  // Either half of the caustic pair alone renders (one port at a time is how the editor connects
  // them), but is rarely what the graph means.
  decl.check = [](const nlohmann::json&, const PortResources& resource) {
    PassCheck check;
    if (resource("caustics") && !resource("caustic_depth")) {
      check.warning =
          "'caustics' is bound without 'caustic_depth': the caustic map is applied without its receiver test, also on "
          "surfaces its light does not see first";
    } else if (!resource("caustics") && resource("caustic_depth")) {
      check.warning = "'caustic_depth' is bound without 'caustics': it is not read";
    }
    return check;
  };
  return decl;
}

}  // namespace caustica::passes
