// gbuffer: opaque geometry from the camera into depth, world normal and albedo.
#include "builtin_passes.h"
#include "scene_draw.h"

namespace caustica::passes {
namespace {

class GBufferPass final : public graph::Pass {
 public:
  void setup(graph::PassSetup& setup) override {
    vk::RasterState state;
    state.color_formats = {graph::format_info(setup.resource("normal").format).vk, graph::format_info(setup.resource("albedo").format).vk};
    has_emission_ = setup.bound("emission");
    if (has_emission_) state.color_formats.push_back(graph::format_info(setup.resource("emission").format).vk);
    // Written only where the scene has a surface that needs it (16 bytes a pixel of bandwidth).
    has_material_ = setup.bound("material") && setup.scene_value("scene.surface_layers") > 0.0;
    if (has_material_) state.color_formats.push_back(graph::format_info(setup.resource("material").format).vk);
    // The extensions' texels only where a texture sets them (16 bytes a pixel more).
    has_layers_ = has_material_ && setup.bound("layers") && setup.scene_value("scene.surface_textures") > 0.0;
    if (has_layers_) state.color_formats.push_back(graph::format_info(setup.resource("layers").format).vk);
    state.depth_format = graph::format_info(setup.resource("depth").format).vk;
    shader::Defines defines;
    if (has_emission_) defines["EMISSION"] = "1";
    // The attachments' locations.
    if (has_material_) defines["MATERIAL"] = has_emission_ ? "3" : "2";
    if (has_layers_) defines["LAYERS"] = has_emission_ ? "4" : "3";
    pipeline_ = make_scene_pipeline(setup, "gbuffer", "scene/gbuffer.frag", state, defines);
  }

  void execute(graph::PassContext& ctx) override {
    const VkExtent2D extent = ctx.extent("depth");
    const SceneView view = camera_view(ctx, extent);
    VkCommandBuffer cmd = ctx.cmd();
    std::vector<Attachment> targets{{ctx.view("normal")}, {ctx.view("albedo")}};
    if (has_emission_) targets.push_back({ctx.view("emission")});
    if (has_material_) targets.push_back({ctx.view("material")});
    if (has_layers_) targets.push_back({ctx.view("layers")});
    begin_rendering(cmd, extent, targets, Attachment{ctx.view("depth")});
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_.pipeline.get());
    scene_descriptors(ctx, pipeline_).push(ctx.vk(), cmd, pipeline_);
    bind_scene_textures(ctx, cmd, pipeline_);
    const DrawPush push(view);
    vkCmdPushConstants(cmd, pipeline_.layout.get(), pipeline_.stages, 0, sizeof(push), &push);
    draw_range(cmd, ctx.scene(), ctx.scene().opaque());
    vkCmdEndRendering(cmd);
  }

 private:
  vk::Pipeline pipeline_;
  bool has_emission_ = false, has_material_ = false, has_layers_ = false;
};

}  // namespace

graph::PassTypeDecl gbuffer_pass_type() {
  using namespace graph;
  PassTypeDecl decl{
      "gbuffer",
      "Opaque geometry seen from the camera: depth, shading normal (facing the viewer; normal maps applied) with "
      "roughness, base colour with metallic, emitted radiance, and the material's extensions. MASK materials cut out. Refractors are left "
      "out.",
      PassQueue::graphics,
      {{"depth", PortAccess::write, ResourceKind::image, PortUsage::depth_attachment, {Format::d32f}, false, "frame", "camera depth"},
       {"normal",
        PortAccess::write,
        ResourceKind::image,
        PortUsage::color_attachment,
        {Format::rgba16f, Format::rgba32f},
        false,
        "frame",
        "world-space shading normal; w: roughness (below 0: Lambertian)"},
       {"albedo",
        PortAccess::write,
        ResourceKind::image,
        PortUsage::color_attachment,
        {Format::rgba8, Format::rgba16f},
        false,
        "frame",
        "base colour; alpha: metallic"},
       {"emission",
        PortAccess::write,
        ResourceKind::image,
        PortUsage::color_attachment,
        {Format::rgba16f, Format::rgba32f},
        true,
        "frame",
        "emitted radiance (glTF emissive); alpha: ambient occlusion (glTF occlusionTexture); unbound, nothing emits or is occluded"},
       {"material",
        PortAccess::write,
        ResourceKind::image,
        PortUsage::color_attachment,
        {Format::rgba32f},
        true,
        "frame",
        "x: the direction of glTF's anisotropy in the surface, y: its strength, z: the clear coat's normal (directions packed as "
        "scene/material_targets.glsl says; per texel); w: the object's index, whose extensions lighting reads; unbound, those "
        "extensions are not drawn"},
       {"layers",
        PortAccess::write,
        ResourceKind::image,
        PortUsage::color_attachment,
        {Format::rgba32ui},
        true,
        "frame",
        "the texels of glTF's sheen, diffuse transmission, specular, clear coat and iridescence textures on opaque surfaces (with "
        "material; scene/material_targets.glsl); unbound, lighting takes each texture's mean"}},
      {},
      false,
      [] { return std::make_unique<GBufferPass>(); }};
  decl.needs_scene = true;
  decl.depends_on = [](const nlohmann::json&) { return kDependsOnGeometry | kDependsOnCamera; };
  return decl;
}

}  // namespace caustica::passes
