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

// The full-screen deferred refraction pipeline (shaders/refraction/deferred_refraction.frag).
vk::Pipeline make_deferred_refraction_pipeline(graph::PassSetup& setup, VkFormat color);
// A full-screen copy of a sampled image into a colour attachment.
vk::Pipeline make_copy_pipeline(graph::PassSetup& setup, VkFormat color);
// Draws `source` into `target` with a pipeline from make_copy_pipeline().
void record_copy(const graph::PassContext& ctx, const vk::Pipeline& copy, VkImageView source, VkImageView target, VkExtent2D extent);
// Scene bindings plus the refraction shader's: background, depth, front, back, counters.
void push_refraction_descriptors(const graph::PassContext& ctx, const vk::Pipeline& pipeline, VkImageView background, VkImageView front,
                                 VkImageView back);

}  // namespace caustica::passes
