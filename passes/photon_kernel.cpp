#include "photon_kernel.h"

#include <cstddef>
#include <glm/gtc/packing.hpp>
#include "refractor_buffers.h"

namespace caustica::passes {

std::vector<graph::ParamDecl> photon_path_params() {
  auto params = exact_path_params("a photon");
  params.push_back({"seed",
                    graph::ParamType::int_,
                    1,
                    0.0,
                    1e9,
                    {},
                    "exact paths: seed of the Fresnel choices (reflect or transmit), deterministic per photon"});
  params.push_back({"hybrid_reflections",
                    graph::ParamType::float_,
                    0.25,
                    0.0,
                    1.0,
                    {},
                    "hybrid with fresnel: the share of photons on a trusted path whose Fresnel reflection (off the entry, or back "
                    "inside at the exit) is traced exactly from there, its power divided by the share; 0 weights the reflections "
                    "away as image space does (faster, and loses their light)"});
  return params;
}

void ExactPaths::setup(graph::PassSetup& setup) {
  TracedScene::setup(setup);
  using Kind = graph::PassSetup::CounterKind;
  // The order of caustics/photon.glsl's EXACT_* constants (the retraced ones in refraction.glsl's EXIT_* order, then
  // RETRACED_NO_LANDING, RETRACED_REFRACTOR_AHEAD and RETRACED_REFLECTION).
  first_counter_ = add_consecutive_counters(setup, {{"photons.exact", Kind::count},
                                                    {"photons.escaped", Kind::count},
                                                    {"photons.trapped", Kind::count},
                                                    {"photons.off_map", Kind::count},
                                                    {"photons.reflected_outside", Kind::count},
                                                    {"photons.retraced.tir", Kind::count},
                                                    {"photons.retraced.empty_back", Kind::count},
                                                    {"photons.retraced.off_surface", Kind::count},
                                                    {"photons.retraced.multiple_refractors", Kind::count},
                                                    {"photons.retraced.no_landing", Kind::count},
                                                    {"photons.retraced.refractor_ahead", Kind::count},
                                                    {"photons.retraced.reflection", Kind::count},
                                                    {"caustic.flux_escaped", Kind::sum},
                                                    {"caustic.flux_trapped", Kind::sum},
                                                    {"caustic.flux_off_map", Kind::sum},
                                                    {"caustic.flux_absorbed", Kind::sum}});
}

std::vector<shader::MirroredMember> exact_path_push_members(size_t at) {
  return {{"exact_max_interfaces", at + offsetof(ExactPathPush, max_interfaces)},
          {"exact_seed", at + offsetof(ExactPathPush, seed)},
          {"exact_counters", at + offsetof(ExactPathPush, counters)},
          {"exact_epsilon", at + offsetof(ExactPathPush, epsilon)},
          {"hybrid_packed", at + offsetof(ExactPathPush, hybrid_packed)}};
}

ExactPathPush ExactPaths::push(const graph::PassContext& ctx) const {
  const auto& p = ctx.params();
  return {p["max_interfaces"].get<uint32_t>(), p["seed"].get<uint32_t>(), first_counter_, ctx.scene().scene().ray_epsilon(),
          glm::packHalf2x16(glm::vec2(p["hybrid_tolerance"].get<float>(), p["hybrid_reflections"].get<float>()))};
}

std::vector<graph::PortDecl> photon_ports() {
  using namespace graph;
  auto surfaces = [](const char* name, const char* what) {
    return PortDecl{name, PortAccess::read, ResourceKind::image, PortUsage::sampled, {Format::rgba32f}, false, "light", what};
  };
  return {surfaces("front", "refractor front surfaces from the light (refractor_buffers, view = light)"),
          surfaces("back", "refractor back surfaces from the light"),
          {"receiver_depth",
           PortAccess::read,
           ResourceKind::image,
           PortUsage::sampled,
           {Format::d32f},
           false,
           "light",
           "opaque geometry's depth from the light (shadow_map without refractors)"},
          {"caustic_map",
           PortAccess::write,
           ResourceKind::image,
           PortUsage::storage,
           {Format::r32f},
           false,
           "",
           "flux per texel, in the light's image plane: r32f with a layer per colour channel (\"layers\": 3)",
           false,
           3},
          RefractorSurfaces::front_tint_port(PortAccess::read, PortUsage::sampled, "light"),
          RefractorSurfaces::front_layers_port(PortAccess::read, PortUsage::sampled, "light")};
}

void require_photon_features(const graph::PassSetup& setup, const std::string& pass_type) {
  const vk::Context& vk = setup.vk();
  if (!vk.float_atomics()) {
    throw DeviceError(vk.device_name() +
                      " lacks shaderImageFloat32AtomicAdd / shaderBufferFloat32AtomicAdd (VK_EXT_shader_atomic_float), which " + pass_type +
                      " splats photons with");
  }
  if (!vk.subgroup_arithmetic()) {
    throw DeviceError(vk.device_name() + " lacks subgroup arithmetic in compute shaders (VK_SUBGROUP_FEATURE_ARITHMETIC_BIT), which " +
                      pass_type + " adds its counters up with");
  }
}

vk::DescriptorWriter photon_descriptors(const graph::PassContext& ctx, const vk::Pipeline& pipeline, const ExactPaths& exact) {
  vk::DescriptorWriter writer = scene_descriptors(ctx, pipeline);
  writer.image("front_tex", ctx.view("front"), ctx.nearest_sampler())
      .image("back_tex", ctx.view("back"), ctx.nearest_sampler())
      .image("receiver_depth", ctx.view("receiver_depth"), ctx.nearest_sampler())
      .image("caustic_map", ctx.view("caustic_map"))
      .buffer("CounterBlock", ctx.counter_buffer())
      .buffer("SumBlock", ctx.counter_buffer());
  exact.bind(ctx, writer);
  bind_front_texels(ctx, writer);
  return writer;
}

vk::Pipeline make_caustic_clear_pipeline(graph::PassSetup& setup) {
  return setup.compute_pipeline("caustic_clear", {"caustics/clear.comp", {}});
}

void record_caustic_clear(const graph::PassContext& ctx, const vk::Pipeline& clear) {
  VkCommandBuffer cmd = ctx.cmd();
  const VkExtent2D map = ctx.extent("caustic_map");
  vk::dispatch_over_image(ctx.vk(), cmd, clear, vk::DescriptorWriter().image("target", ctx.view("caustic_map")), {}, map);
  memory_barrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                 VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
}

void PhotonKernel::build(graph::PassSetup& setup, const vk::PipelineDesc& layout, const std::string& shader, const shader::Defines& defines,
                         bool band_loop) {
  white_ = setup.compute_pipeline(layout, {shader, defines});
  band_loop_ = {};
  if (band_loop) {
    shader::Defines loop = defines;
    loop["PHOTON_BAND_LOOP"] = "1";
    band_loop_ = setup.compute_pipeline(layout, {shader, loop});
  }
}

PhotonKernel::Passes PhotonKernel::passes(const scene::Scene& scene) const {
  if (!scene.disperses()) return {white_, {kWhiteBand}};
  if (band_loop_.pipeline) return {band_loop_, {kWhiteBand}};  // the kernel loops over the bands
  return {white_, {0, 1, 2}};
}

}  // namespace caustica::passes
