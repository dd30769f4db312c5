#include "scene_draw.h"

#include "common/scene_types.h"

namespace caustica::passes {

SceneView camera_view(const graph::PassContext& ctx, VkExtent2D extent) {
  const auto& camera = ctx.scene().camera();
  const glm::vec2 size(static_cast<float>(extent.width), static_cast<float>(extent.height));
  return {scene::shifted_by_pixels(camera.view_projection(size.x / size.y), ctx.frame().camera_jitter, size), camera.position};
}

namespace {
SceneView seen_from(const scene::Light& seen) {
  return {seen.view_projection(), seen.view.position, seen.axis(), seen.type == scene::LightType::directional};
}
}  // namespace

SceneView light_view(const graph::PassContext& ctx, uint32_t light) {
  const auto& lights = ctx.scene().lights();
  return seen_from(lights[std::min<size_t>(light, lights.size() - 1)]);  // the scene always has one light
}

SceneView caustic_view(const graph::PassContext& ctx, uint32_t view) {
  const auto& views = ctx.scene().caustic_views();
  return seen_from(views[std::min<size_t>(view, views.size() - 1)].seen);  // one per light at least
}

SceneView chosen_view(const graph::PassContext& ctx, VkExtent2D extent) {
  if (ctx.params()["view"].get<std::string>() == "light") return caustic_view(ctx, ctx.params()["light"].get<uint32_t>());
  return camera_view(ctx, extent);
}

graph::ParamDecl caustic_view_param(const char* what) {
  return {"light", graph::ParamType::int_, 0, 0.0, CAUSTICA_MAX_CAUSTIC_VIEWS - 1, {}, what};
}

std::vector<graph::ParamDecl> view_params() {
  return {
      {"view", graph::ParamType::choice, "camera", {}, {}, {"camera", "light"}, "look from the camera or from a light (its caustic view)"},
      caustic_view_param("which caustic view, for view = light: light K's is K, a point light's further cube faces follow the lights' "
                         "(a \"for_each\": \"caustic_view\" instance's $light); the last one if fewer")};
}

std::vector<shader::MirroredMember> draw_push_members(size_t at) {
  return {
      {"view_proj", at + offsetof(DrawPush, view_proj)}, {"eye", at + offsetof(DrawPush, eye)}, {"axis", at + offsetof(DrawPush, axis)}};
}

vk::Pipeline make_scene_pipeline(graph::PassSetup& setup, const char* name, const char* fragment_shader, const vk::RasterState& state,
                                 const shader::Defines& defines) {
  vk::Pipeline pipeline = setup.graphics_pipeline(name, {"scene/mesh.vert", {}}, {fragment_shader, defines}, state);
  pipeline.interface->check_push("DrawPush", sizeof(DrawPush), draw_push_members());
  return pipeline;
}

vk::DescriptorWriter scene_descriptors(const graph::PassContext& ctx, const vk::Pipeline& pipeline) {
  const auto& scene = ctx.scene();
  vk::DescriptorWriter writer;
  const std::pair<const char*, VkBuffer> blocks[] = {
      {"FrameBlock", scene.frame()}, {"VertexBlock", scene.vertices()}, {"ObjectBlock", scene.objects()}};
  for (const auto& [name, buffer] : blocks) {
    if (pipeline.interface->declares(name)) writer.buffer(name, buffer);
  }
  return writer;
}

void bind_scene_textures(const graph::PassContext& ctx, VkCommandBuffer cmd, const vk::Pipeline& pipeline) {
  if (!pipeline.texture_set_layout) return;
  const VkDescriptorSet set = ctx.scene().textures();
  vkCmdBindDescriptorSets(cmd, pipeline.bind_point, pipeline.layout.get(), 1, 1, &set, 0, nullptr);
}

void begin_rendering(VkCommandBuffer cmd, VkExtent2D extent, const std::vector<Attachment>& colors, std::optional<Attachment> depth) {
  std::vector<VkRenderingAttachmentInfo> color_infos;
  for (const auto& c : colors) {
    VkRenderingAttachmentInfo info{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    info.imageView = c.view;
    info.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    info.loadOp = c.load;
    info.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    color_infos.push_back(info);
  }
  VkRenderingAttachmentInfo depth_info{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  if (depth) {
    depth_info.imageView = depth->view;
    depth_info.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
    depth_info.loadOp = depth->load;
    depth_info.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    depth_info.clearValue.depthStencil = {1.0f, 0};
  }
  VkRenderingInfo rendering{VK_STRUCTURE_TYPE_RENDERING_INFO};
  rendering.renderArea = {{0, 0}, extent};
  rendering.layerCount = 1;
  rendering.colorAttachmentCount = static_cast<uint32_t>(color_infos.size());
  rendering.pColorAttachments = color_infos.data();
  rendering.pDepthAttachment = depth ? &depth_info : nullptr;
  vkCmdBeginRendering(cmd, &rendering);
  VkViewport viewport{0, 0, static_cast<float>(extent.width), static_cast<float>(extent.height), 0, 1};
  VkRect2D scissor{{0, 0}, extent};
  vkCmdSetViewport(cmd, 0, 1, &viewport);
  vkCmdSetScissor(cmd, 0, 1, &scissor);
}

void draw_range(VkCommandBuffer cmd, const scene::GpuScene& scene, scene::DrawRange range) {
  if (range.index_count == 0) return;
  vkCmdBindIndexBuffer(cmd, scene.indices(), 0, VK_INDEX_TYPE_UINT32);
  vkCmdDrawIndexed(cmd, range.index_count, 1, range.first_index, 0, 0);
}

void wait_for_depth_writes(VkCommandBuffer cmd, VkImage depth) {
  image_barrier(cmd, depth, VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT, VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
                VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
                VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT);
}

}  // namespace caustica::passes
