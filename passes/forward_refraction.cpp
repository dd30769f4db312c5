// forward_refraction: the paper's baseline. The background is copied into the target, then every
// refractor front face is rasterized with the refraction shader, hidden fragments included.
#include <cstddef>

#include "builtin_passes.h"
#include "refraction.h"

namespace caustica::passes {
namespace {

struct ForwardPush {
  DrawPush draw;
  RefractionPush refraction;
};

class ForwardRefractionPass final : public graph::Pass {
 public:
  void setup(graph::PassSetup& setup) override {
    tir_counter_ = setup.add_counter(setup.pass().name + ".tir_pixels");
    const VkFormat color = graph::format_info(setup.resource("color").format).vk;
    copy_ = make_copy_pipeline(setup, color);
    vk::RasterState state;
    state.color_formats = {color};
    state.depth_format = graph::format_info(setup.resource("refractor_depth").format).vk;
    // A thin-walled refractor is one surface seen from either side: drawn without culling.
    for (int thin = 0; thin < 2; ++thin) {
      state.cull = thin ? VK_CULL_MODE_NONE : VK_CULL_MODE_BACK_BIT;
      refract_[thin] = setup.graphics_pipeline(thin ? "forward_refraction_thin" : "forward_refraction", {"scene/mesh.vert", {}},
                                               {"refraction/forward_refraction.frag", {}}, state);
    }
    std::vector<shader::MirroredMember> members = draw_push_members(offsetof(ForwardPush, draw));
    for (const auto& member : refraction_push_members(offsetof(ForwardPush, refraction))) members.push_back(member);
    refract_[0].interface->check_push("ForwardPush", sizeof(ForwardPush), members);
  }

  void execute(graph::PassContext& ctx) override {
    const VkExtent2D extent = ctx.extent("color");
    VkCommandBuffer cmd = ctx.cmd();
    record_copy(ctx, copy_, ctx.view("background"), ctx.view("color"), extent);
    image_barrier(cmd, ctx.image("color"), VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                  VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                  VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                  VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);

    begin_rendering(cmd, extent, {{ctx.view("color"), VK_ATTACHMENT_LOAD_OP_LOAD}}, Attachment{ctx.view("refractor_depth")});
    const SceneView view = camera_view(ctx, extent);
    const ForwardPush push{DrawPush(view), refraction_push(ctx, tir_counter_)};
    const auto [solid, thin] = ctx.scene().split_thin(ctx.scene().refractors());
    const scene::DrawRange parts[2] = {solid, thin};
    for (int part = 0; part < 2; ++part) {
      if (parts[part].index_count == 0) continue;
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, refract_[part].pipeline.get());
      refraction_descriptors(ctx, refract_[part], ctx.view("background"), ctx.view("back")).push(ctx.vk(), cmd, refract_[part]);
      bind_scene_textures(ctx, cmd, refract_[part]);
      vkCmdPushConstants(cmd, refract_[part].layout.get(), refract_[part].stages, 0, sizeof(push), &push);
      draw_range(cmd, ctx.scene(), parts[part]);
    }
    vkCmdEndRendering(cmd);
  }

 private:
  vk::Pipeline copy_, refract_[2];  // solid refractors (back faces culled), thin-walled ones
  uint32_t tir_counter_ = 0;
};

}  // namespace

graph::PassTypeDecl forward_refraction_pass_type() {
  using namespace graph;
  auto ports = refraction_inputs();
  ports.push_back({"back",
                   PortAccess::read,
                   ResourceKind::image,
                   PortUsage::sampled,
                   {Format::rgba32f},
                   false,
                   "frame",
                   "refractor back surfaces (refractor_buffers)"});
  ports.push_back({"color",
                   PortAccess::write,
                   ResourceKind::image,
                   PortUsage::color_attachment,
                   {Format::rgba16f, Format::rgba32f},
                   false,
                   "frame",
                   "the background with the refractors composited"});
  ports.push_back({"refractor_depth",
                   PortAccess::write,
                   ResourceKind::image,
                   PortUsage::depth_attachment,
                   {Format::d32f},
                   false,
                   "frame",
                   "depth test among refractor front faces"});
  PassTypeDecl decl{"forward_refraction",
                    "Image-space refraction through two interfaces (Wyman 2005) shaded while rasterizing refractor front faces: the "
                    "paper's forward baseline, where hidden fragments are shaded too. Counter <pass>.tir_pixels.",
                    PassQueue::graphics,
                    ports,
                    refraction_params(),
                    false,
                    [] { return std::make_unique<ForwardRefractionPass>(); }};
  decl.needs_scene = true;
  decl.depends_on = [](const nlohmann::json&) { return kDependsOnScene; };
  return decl;
}

}  // namespace caustica::passes
