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

// The photon passes' ladder of ways to find where a photon leaves a refractor (their `distance`):
// dv and dv_dn estimate in image space; ray_query traces every photon exactly; hybrid estimates and
// re-traces exactly only the photons whose estimate cannot be trusted. Adds max_interfaces, seed
// and hybrid_tolerance to refraction_params().
std::vector<graph::ParamDecl> photon_path_params();
// Whether photons with these parameters trace with ray queries (PassTypeDecl::uses_ray_queries).
bool photon_paths_use_ray_queries(const nlohmann::json& params);
extern const char* const kPhotonRayQueryAlternative;

// Mirrors the exact-path fields at the end of the photon shaders' push constants.
struct ExactPathPush {
  uint32_t max_interfaces;
  uint32_t seed;
  uint32_t counters;  // first of the consecutive exact-path counter slots
  float epsilon;      // ray offset off a surface, scaled to the scene
  float hybrid_tolerance;
};

// What a photon pass needs for exact paths: the counters (always, so that every method reports the
// same names), and where it traces with ray queries, the shader variant and the bindings 14
// (the scene's top-level acceleration structure) and 15 (its triangles).
class ExactPaths {
 public:
  void setup(graph::PassSetup& setup);
  bool traced() const { return traced_; }
  // CAUSTICA_RAY_QUERY when traced.
  shader::Defines defines(shader::Defines defines = {}) const;
  // Pads `bindings` to 14 and appends the two ray-query bindings when traced.
  std::vector<VkDescriptorType> bindings(std::vector<VkDescriptorType> bindings) const;
  ExactPathPush push(const graph::PassContext& ctx) const;
  void bind(const graph::PassContext& ctx, vk::DescriptorWriter& writer) const;

 private:
  bool traced_ = false;
  uint32_t first_counter_ = 0;
};
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
