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

}  // namespace caustica::passes
