#include "refraction.h"

namespace caustica::passes {

std::vector<graph::ParamDecl> refraction_params() {
  using graph::ParamType;
  return {{"distance", ParamType::choice, "dv_dn", {}, {}, {"dv", "dv_dn"},
           "distance to the back surface: d_V (along the view ray) or Wyman's d_V/d_N blend by refraction angle"},
          {"search_steps", ParamType::int_, 48, 4.0, 512.0, {}, "linear steps of the background search along the exit ray"},
          {"search_distance", ParamType::float_, 8.0, 0.01, 1000.0, {}, "how far the background search goes, in scene units"}};
}

RefractionPush refraction_push(const graph::PassContext& ctx, uint32_t tir_counter) {
  const auto& p = ctx.params();
  return {p["distance"].get<std::string>() == "dv" ? 0u : 1u, p["search_steps"].get<uint32_t>(), p["search_distance"].get<float>(),
          tir_counter};
}

std::vector<graph::PortDecl> refraction_inputs() {
  using namespace graph;
  return {{"background", PortAccess::read, ResourceKind::image, PortUsage::sampled, {}, false, "frame", "radiance behind the refractors"},
          {"depth", PortAccess::read, ResourceKind::image, PortUsage::sampled, {Format::d32f}, false, "frame", "depth of the background"}};
}

vk::Pipeline make_deferred_refraction_pipeline(graph::PassSetup& setup, VkFormat color) {
  return vk::make_fullscreen_pipeline(
      setup.vk(),
      {"deferred_refraction",
       {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
        VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
        VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
       sizeof(RefractionPush)},
      setup.shaders().compile("common/fullscreen.vert"), setup.shaders().compile("refraction/deferred_refraction.frag"), {color});
}

vk::Pipeline make_copy_pipeline(graph::PassSetup& setup, VkFormat color) {
  return vk::make_fullscreen_pipeline(setup.vk(), {"copy_background", {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER}, 0},
                                      setup.shaders().compile("common/fullscreen.vert"), setup.shaders().compile("common/copy.frag"), {color});
}

void record_copy(const graph::PassContext& ctx, const vk::Pipeline& copy, VkImageView source, VkImageView target, VkExtent2D extent) {
  VkCommandBuffer cmd = ctx.cmd();
  begin_rendering(cmd, extent, {{target, VK_ATTACHMENT_LOAD_OP_DONT_CARE}}, std::nullopt);
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, copy.pipeline.get());
  vk::DescriptorWriter().sampled_image(0, source, ctx.nearest_sampler()).push(ctx.vk(), cmd, copy);
  vkCmdDraw(cmd, 3, 1, 0, 0);
  vkCmdEndRendering(cmd);
}

void push_refraction_descriptors(const graph::PassContext& ctx, const vk::Pipeline& pipeline, VkImageView background, VkImageView front,
                                 VkImageView back) {
  scene_descriptors(ctx)
      .sampled_image(3, background, ctx.linear_sampler())
      .sampled_image(4, ctx.view("depth"), ctx.nearest_sampler())
      .sampled_image(5, front, ctx.nearest_sampler())
      .sampled_image(6, back, ctx.nearest_sampler())
      .storage_buffer(7, ctx.counter_buffer())
      .push(ctx.vk(), ctx.cmd(), pipeline);
}

}  // namespace caustica::passes
