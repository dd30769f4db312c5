#pragma once
// The image-space refraction passes' shared parameters and push constants (the GLSL side is
// shaders/refraction/refraction.glsl).
#include "scene_draw.h"

namespace caustica::passes {

struct RefractionPush {
  uint32_t distance_mode;  // the order of refraction.glsl's DISTANCE_* constants
  // search_steps (at most 512) in the low 16 bits, search_bounces above (refraction.glsl's
  // search_steps() and search_tir_bounces()): a push constant, so a change reuses the pipeline.
  uint32_t search;
  float search_distance;
  uint32_t tir_counter;
  // Exact camera paths (deferred_refraction with distance ray_query or hybrid).
  uint32_t exact_max_interfaces;
  float exact_epsilon;
  float hybrid_tolerance;
  uint32_t exact_counters;  // first of the consecutive camera exact-path counter slots
};

// The image-space passes' `distance` (dv, dv_dn, search) and the background search's parameters.
std::vector<graph::ParamDecl> refraction_params();
// `params` with search_bounces, for the passes whose search follows total internal reflection
// inside (those that read the refractors' front surfaces too: refraction_defines).
std::vector<graph::ParamDecl> with_search_bounces(std::vector<graph::ParamDecl> params);
// The ladder of ways to find where a ray leaves a refractor, for the passes that also trace exact
// paths: refraction_params() with search_bounces, ray_query and hybrid, max_interfaces and
// hybrid_tolerance.
// `what` names the rays ("a photon", "a camera ray") in the description.
std::vector<graph::ParamDecl> exact_path_params(const std::string& what);
RefractionPush refraction_push(const graph::PassContext& ctx, uint32_t tir_counter, uint32_t exact_counters = 0);
// Whether a pass with these parameters traces exact paths (PassTypeDecl::traces_scene).
bool traces_exact_paths(const nlohmann::json& params);

// Registers `names` as consecutive counters of the pass and returns the first slot (the shaders
// address them from one base).
uint32_t add_consecutive_counters(graph::PassSetup& setup, const std::vector<std::pair<std::string, graph::PassSetup::CounterKind>>& names);

// RefractionPush's members as the shaders' push blocks name them, `at` bytes into the C++ struct
// that holds it.
std::vector<shader::MirroredMember> refraction_push_members(size_t at = 0);

// What a pass that traces exact paths needs where its parameters ask for them: the shader variant
// (CAUSTICA_RAY_QUERY, and CAUSTICA_HYBRID for distance hybrid; CAUSTICA_COMPUTE_TRACER where the
// plan traces with the compute tracer), which then declares the scene's structure (the top-level
// acceleration structure scene_tlas, or the BVH's BvhBlock) and its triangles (TriangleBlock), as
// shaders/scene/trace.glsl does.
class TracedScene {
 public:
  void setup(const graph::PassSetup& setup);
  bool traced() const { return traced_; }
  // CAUSTICA_RAY_QUERY and the pass's one mode (CAUSTICA_DISTANCE_MODE) when traced; CAUSTICA_HYBRID
  // too for the hybrid, whose checks, traced exit rays and side paths the other exact kernels must
  // not carry: lavapipe compiles a kernel within its first frame, and each inlined ray query, and each
  // mode's code that the kernel never runs, lengthens that (under AddressSanitizer the ray-query photon
  // kernel with the hybrid's code in it took a test's first frame past the 120 s limit).
  shader::Defines defines(shader::Defines defines = {}) const;
  void bind(const graph::PassContext& ctx, vk::DescriptorWriter& writer) const;
  // The texture array (MASK coverage) as set 1 when traced, bound after the pass's descriptors are pushed.
  void bind_textures(const graph::PassContext& ctx, const vk::Pipeline& pipeline) const;

 private:
  bool traced_ = false;
  graph::Tracer tracer_ = graph::Tracer::none;
  uint32_t mode_ = 0;            // refraction.glsl's DISTANCE_* constant
  bool layer_textures_ = false;  // the scene has interface layers with textures (scene.layer_textures)
};

// The optional front_tint and front_layers inputs (RefractorSurfaces::front_tint_port,
// front_layers_port), where a pass has them bound: front_tint_tex and front_layers_tex of its
// shaders (shaders/refraction/refraction.glsl, at_front_texel).
// The defines of a pass's refraction shaders that its setup decides: REFRACTOR_TINT where front_tint
// is bound, REFRACTOR_LAYERS where front_layers is.
shader::Defines refraction_defines(const graph::PassSetup& setup, shader::Defines defines = {});
void bind_front_texels(const graph::PassContext& ctx, vk::DescriptorWriter& writer);

// The ports every refraction pass reads: the image behind the refractors and its depth.
std::vector<graph::PortDecl> refraction_inputs();

// A full-screen copy of a sampled image into a colour attachment.
vk::Pipeline make_copy_pipeline(graph::PassSetup& setup, VkFormat color);
// Draws `source` into `target` with a pipeline from make_copy_pipeline().
void record_copy(const graph::PassContext& ctx, const vk::Pipeline& copy, VkImageView source, VkImageView target, VkExtent2D extent);
// Scene bindings plus the refraction shader's: background, depth, back, counters, the ray-query
// scene where `exact` traces, and the front tint where the pass has it bound; the caller adds its
// own and pushes them to `pipeline`.
vk::DescriptorWriter refraction_descriptors(const graph::PassContext& ctx, const vk::Pipeline& pipeline, VkImageView background,
                                            VkImageView back, const TracedScene* exact = nullptr);

// The screen rectangle, one pixel wider on each side, that covers the bounding boxes of `objects`
// seen by `view_proj`; the whole extent when any box reaches behind the eye.
VkRect2D screen_rect(const scene::Scene& scene, const glm::mat4& view_proj, const std::vector<uint32_t>& objects, VkExtent2D extent);

// Deferred refraction shading over a storage image (general layout), in compute: a plain copy of
// the background over the whole target, then the refraction shader over the refractors' screen
// rectangle alone, so that pixels that cannot show a refractor cost a copy and not a refraction
// lookup. With `exact` (which must outlive it) the shader traces exact camera paths where that
// pass's parameters ask for them.
class DeferredRefractionShading {
 public:
  void setup(graph::PassSetup& setup, graph::Format target, const TracedScene* exact = nullptr);
  void record(const graph::PassContext& ctx, const RefractionPush& push, VkImageView background, VkImageView front, VkImageView back,
              VkImageView target, VkExtent2D extent, VkRect2D rect) const;
  // `source` copied into `target` (general layout), the same extent.
  void copy(const graph::PassContext& ctx, VkImageView source, VkImageView target, VkExtent2D extent) const;

 private:
  vk::Pipeline refract_, copy_;
  const TracedScene* exact_ = nullptr;
};

}  // namespace caustica::passes
