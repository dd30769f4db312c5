#pragma once
// What the caustic passes (caustic_map, adaptive_caustic_map) share: the photon paths' parameters
// and exact-path counters, the ports and descriptors of the photon shaders (shaders/caustics/
// photon.glsl), the photon kernel and the caustic map's clear. The refraction helpers they build on
// are in refraction.h.
#include "refraction.h"

namespace caustica::passes {

// The photon passes': exact_path_params() and the seed of their Fresnel choices.
std::vector<graph::ParamDecl> photon_path_params();

// Mirrors the exact-path fields at the end of the photon shaders' push constants.
struct ExactPathPush {
  uint32_t max_interfaces;
  uint32_t seed;
  uint32_t counters;  // first of the consecutive exact-path counter slots
  float epsilon;      // ray offset off a surface, scaled to the scene
  // hybrid_tolerance and hybrid_reflections as two halves (glm::packHalf2x16): the adaptive pass's
  // push constants are at the 128 bytes every device allows.
  uint32_t hybrid_packed;
};

// ExactPathPush's members as the photon shaders' push blocks name them, `at` bytes into the C++
// struct that holds it.
std::vector<shader::MirroredMember> exact_path_push_members(size_t at);

// A photon pass's exact paths: the ray-query scene where traced, and the counters always, so that
// every method reports the same names.
class ExactPaths : public TracedScene {
 public:
  void setup(graph::PassSetup& setup);
  ExactPathPush push(const graph::PassContext& ctx) const;

 private:
  uint32_t first_counter_ = 0;
};

// The ports of every caustic method: the light-view refractor surfaces and receiver depth in, the
// caustic map (flux per texel) out.
std::vector<graph::PortDecl> photon_ports();

// Refuses a device without what every photon kernel needs, naming the pass type: float atomic adds
// (the splats and sums) and subgroup arithmetic (caustics/group_totals.glsl's counters).
void require_photon_features(const graph::PassSetup& setup, const std::string& pass_type);
// Scene bindings plus the photon shaders' (caustics/photon.glsl): front, back, receiver depth,
// caustic map, counters as uint and as float, the ray-query scene where `exact` traces, and the
// front tint where bound; for `pipeline`.
vk::DescriptorWriter photon_descriptors(const graph::PassContext& ctx, const vk::Pipeline& pipeline, const ExactPaths& exact);

// A photon pass's kernel. Photons are white (kWhiteBand: one path carries every channel), or, when
// a refractor disperses light (KHR_materials_dispersion), traced once per colour band, red, green
// and blue (0, 1, 2), each with its own index of refraction (caustics/photon.glsl, photon_band).
// Where `band_loop` is asked for (image space), a variant (PHOTON_BAND_LOOP) traces the three bands
// in one pass over the grid; the white kernel must not carry that loop, which slowed white photons
// on lavapipe (docs/caustics.md). Elsewhere each band is a dispatch of the white kernel.
inline constexpr uint32_t kWhiteBand = 3;
class PhotonKernel {
 public:
  void build(graph::PassSetup& setup, const vk::PipelineDesc& layout, const std::string& shader, const shader::Defines& defines,
             bool band_loop);
  // What to dispatch for `scene`: the pipeline, and the push constant `band` of each pass over the grid.
  struct Passes {
    const vk::Pipeline& pipeline;
    std::vector<uint32_t> bands;
  };
  Passes passes(const scene::Scene& scene) const;

 private:
  vk::Pipeline white_, band_loop_;
};
// Zeroes the pass's caustic_map before photons are splatted into it, and makes the zeros visible
// to the compute shaders that follow.
vk::Pipeline make_caustic_clear_pipeline(graph::PassSetup& setup);
void record_caustic_clear(const graph::PassContext& ctx, const vk::Pipeline& clear);

}  // namespace caustica::passes
