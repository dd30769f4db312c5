#pragma once
// The image-space refraction passes' shared parameters and push constants (the GLSL side is
// shaders/refraction/refraction.glsl).
#include "scene_draw.h"

namespace caustica::passes {

struct RefractionPush {
  uint32_t distance_mode;  // 0: d_V, 1: d_V/d_N blend
  uint32_t search_steps;
  float search_distance;
  uint32_t tir_counter;
};

std::vector<graph::ParamDecl> refraction_params();
RefractionPush refraction_push(const graph::PassContext& ctx, uint32_t tir_counter);
// The ports every refraction pass reads: the image behind the refractors and its depth.
std::vector<graph::PortDecl> refraction_inputs();

// The ports of every caustic method: the light-view refractor surfaces and receiver depth in, the
// caustic map (flux per texel) out.
std::vector<graph::PortDecl> photon_ports();
// Scene bindings plus the photon shaders' (caustics/photon.glsl): front, back, receiver depth,
// caustic map, counters as uint and as float.
vk::DescriptorWriter photon_descriptors(const graph::PassContext& ctx);
// Zeroes the pass's caustic_map before photons are splatted into it, and makes the zeros visible
// to the compute shaders that follow.
vk::Pipeline make_caustic_clear_pipeline(graph::PassSetup& setup);
void record_caustic_clear(const graph::PassContext& ctx, const vk::Pipeline& clear);

// A full-screen copy of a sampled image into a colour attachment.
vk::Pipeline make_copy_pipeline(graph::PassSetup& setup, VkFormat color);
// Draws `source` into `target` with a pipeline from make_copy_pipeline().
void record_copy(const graph::PassContext& ctx, const vk::Pipeline& copy, VkImageView source, VkImageView target, VkExtent2D extent);
// Scene bindings plus the refraction shader's: background, depth, front, back, counters.
void push_refraction_descriptors(const graph::PassContext& ctx, const vk::Pipeline& pipeline, VkImageView background, VkImageView front,
                                 VkImageView back);

// The screen rectangle, one pixel wider on each side, that covers the bounding boxes of `objects`
// seen by `view_proj`; the whole extent when any box reaches behind the eye.
VkRect2D screen_rect(const scene::Scene& scene, const glm::mat4& view_proj, const std::vector<uint32_t>& objects, VkExtent2D extent);

// Deferred refraction shading over a target: the refraction shader inside the refractors' screen
// rectangle, a plain copy of the background outside it, so that pixels that cannot show a
// refractor cost a copy and not a refraction lookup.
class DeferredRefractionShading {
 public:
  void setup(graph::PassSetup& setup, VkFormat color);
  void record(const graph::PassContext& ctx, const RefractionPush& push, VkImageView background, VkImageView front, VkImageView back,
              VkImageView target, VkExtent2D extent, VkRect2D rect) const;
  const vk::Pipeline& copy() const { return copy_; }

 private:
  vk::Pipeline refract_, copy_;
};

}  // namespace caustica::passes
