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
// A light's shadow map's view (spot and directional).
SceneView light_view(const graph::PassContext& ctx, uint32_t light);
// Caustic view `view` (scene::caustic_views), which light-space refractor buffers and receiver
// depths are drawn from.
SceneView caustic_view(const graph::PassContext& ctx, uint32_t view);
// A caustic pass's "light" parameter: which caustic view it draws from and emits photons into.
graph::ParamDecl caustic_view_param(
    const char* what =
        "the caustic view whose light emits the photons (light K's is K; a point light's further cube faces follow the lights')");
// The view named by a pass's "view" and "light" parameters.
SceneView chosen_view(const graph::PassContext& ctx, VkExtent2D extent);

// DrawPush's members as the shaders' push blocks name them, `at` bytes into the C++ struct that holds it.
std::vector<shader::MirroredMember> draw_push_members(size_t at = 0);
// scene/mesh.vert and `fragment_shader`, their push constants a DrawPush (checked).
vk::Pipeline make_scene_pipeline(graph::PassSetup& setup, const char* name, const char* fragment_shader, const vk::RasterState& state,
                                 const shader::Defines& defines = {});
// The scene's blocks (scene/scene.glsl: FrameBlock, VertexBlock, ObjectBlock) that `pipeline`'s
// shaders declare: each includes the ones it reads.
vk::DescriptorWriter scene_descriptors(const graph::PassContext& ctx, const vk::Pipeline& pipeline);
// Set 1, the scene's texture array, where `pipeline`'s shaders sample it (scene/textures.glsl).
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
