#pragma once
// What the scene passes share: the mesh pipeline layout (frame, vertices, objects, then the pass's
// own bindings), the per-draw push constants, choosing a view, and dynamic rendering set-up.
#include <glm/glm.hpp>
#include <optional>
#include <vector>

#include "graph/pass.h"
#include "vk/pipeline.h"

namespace caustica::passes {

// "camera", or "light" with a light index: where a scene pass looks from. A directional light
// looks along `axis` from the plane through `eye` (orthographic); the others from the point `eye`.
struct SceneView {
  glm::mat4 view_proj;
  glm::vec3 eye;
  glm::vec3 axis{0.0f};
  bool orthographic = false;
};

// What scene/mesh.vert and the scene fragment shaders take (layout in scene/scene.glsl's DRAW_PUSH).
struct DrawPush {
  glm::mat4 view_proj;
  glm::vec4 eye;   // xyz, w 1
  glm::vec4 axis;  // xyz, w: 1 when orthographic (distances are then along axis from the plane through eye)
  explicit DrawPush(const SceneView& view)
      : view_proj(view.view_proj), eye(view.eye, 1.0f), axis(view.axis, view.orthographic ? 1.0f : 0.0f) {}
};
SceneView camera_view(const graph::PassContext& ctx, VkExtent2D extent);
SceneView light_view(const graph::PassContext& ctx, uint32_t light);
// The view named by a pass's "view" and "light" parameters.
SceneView chosen_view(const graph::PassContext& ctx, VkExtent2D extent);

// Bindings 0..2 are the scene's (frame data, vertices, objects); `extra` follow from binding 3.
// Set 1 is the scene's texture array: a pass whose fragment shader samples it binds it with
// bind_scene_textures.
vk::Pipeline make_scene_pipeline(graph::PassSetup& setup, const char* name, const char* fragment_shader, const vk::RasterState& state,
                                 std::vector<VkDescriptorType> extra = {}, uint32_t push_bytes = sizeof(DrawPush),
                                 const shader::Defines& defines = {});
vk::DescriptorWriter scene_descriptors(const graph::PassContext& ctx);
void bind_scene_textures(const graph::PassContext& ctx, VkCommandBuffer cmd, const vk::Pipeline& pipeline);

struct Attachment {
  VkImageView view = VK_NULL_HANDLE;
  VkAttachmentLoadOp load = VK_ATTACHMENT_LOAD_OP_CLEAR;  // clears to zero (colour) or 1 (depth)
};
void begin_rendering(VkCommandBuffer cmd, VkExtent2D extent, const std::vector<Attachment>& colors, std::optional<Attachment> depth);
void draw_range(VkCommandBuffer cmd, const scene::GpuScene& scene, scene::DrawRange range);

// Inside one pass, before a depth image is cleared and drawn again: the earlier draw's depth
// writes finish first.
void wait_for_depth_writes(VkCommandBuffer cmd, VkImage depth);
using vk::image_barrier;
using vk::memory_barrier;

// Parameters every pass that shows a choice of view declares.
std::vector<graph::ParamDecl> view_params();

}  // namespace caustica::passes
