// lighting: direct light on the G-buffer (every light, each shadowed by its map and adding its caustic map
// where bound), ambient, sky.
#include <algorithm>
#include <string_view>
#include <vector>

#include "builtin_passes.h"
#include "common/scene_types.h"
#include "core/error.h"
#include "graph/per_light.h"
#include "scene_draw.h"

namespace caustica::passes {
namespace {

struct LightingParams {
  float shadow_bias;
  uint32_t shadowed;        // bit i: light i's shadow map is bound
  uint32_t caustic_lights;  // bit i: light i's caustic map is bound (and the light has a view)
  uint32_t caustic_depths;  // bit i: and its receiver depth
};

// The lights whose element of a per-light port is bound.
std::vector<uint32_t> bound_lights(const graph::PassSetup& setup, std::string_view port) {
  std::vector<uint32_t> lights;
  for (uint32_t light = 0; light < CAUSTICA_MAX_LIGHTS; ++light) {
    if (setup.bound(graph::port_element(port, light))) lights.push_back(light);
  }
  return lights;
}

bool holds(const std::vector<uint32_t>& lights, uint32_t light) {
  return std::find(lights.begin(), lights.end(), light) != lights.end();
}

class LightingPass final : public graph::Pass {
 public:
  void setup(graph::PassSetup& setup) override {
    shadow_maps_ = bound_lights(setup, "shadow");
    caustic_maps_ = bound_lights(setup, "caustics");
    caustic_depths_ = bound_lights(setup, "caustic_depth");
    has_emission_ = setup.bound("emission");
    shader::Defines defines;
    if (!shadow_maps_.empty()) defines["SHADOWS"] = "1";
    if (!caustic_maps_.empty()) defines["CAUSTICS"] = "1";
    if (has_emission_) defines["EMISSION"] = "1";
    vk::RasterState state;
    state.color_formats = {graph::format_info(setup.resource("color").format).vk};
    pipeline_ = setup.graphics_pipeline("lighting", {"common/fullscreen.vert", {}}, {"scene/lighting.frag", defines}, state);
    pipeline_.interface->check_push("LightingParams", sizeof(LightingParams),
                                    {CAUSTICA_MIRRORED(LightingParams, shadow_bias), CAUSTICA_MIRRORED(LightingParams, shadowed),
                                     CAUSTICA_MIRRORED(LightingParams, caustic_lights), CAUSTICA_MIRRORED(LightingParams, caustic_depths)});
  }

  void execute(graph::PassContext& ctx) override {
    const VkExtent2D extent = ctx.extent("color");
    VkCommandBuffer cmd = ctx.cmd();
    begin_rendering(cmd, extent, {{ctx.view("color"), VK_ATTACHMENT_LOAD_OP_DONT_CARE}}, std::nullopt);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_.pipeline.get());
    vk::DescriptorWriter writer;
    writer.buffer("FrameBlock", ctx.scene().frame())
        .image("depth_tex", ctx.view("depth"), ctx.nearest_sampler())
        .image("normal_tex", ctx.view("normal"), ctx.nearest_sampler())
        .image("albedo_tex", ctx.view("albedo"), ctx.nearest_sampler());
    if (has_emission_) writer.image("emission_tex", ctx.view("emission"), ctx.nearest_sampler());
    LightingParams params{ctx.params()["shadow_bias"].get<float>(), write_shadow_maps(ctx, writer), 0, 0};
    write_caustic_maps(ctx, writer, params);
    writer.push(ctx.vk(), cmd, pipeline_);
    vkCmdPushConstants(cmd, pipeline_.layout.get(), pipeline_.stages, 0, sizeof(params), &params);
    vkCmdDraw(cmd, 3, 1, 0, 0);
    vkCmdEndRendering(cmd);
  }

 private:
  // Every element of the shadow maps' array: a light's own where it has one (a point light's only
  // with its six faces), the first bound one elsewhere (unread). Returns the lights shadowed.
  uint32_t write_shadow_maps(const graph::PassContext& ctx, vk::DescriptorWriter& writer) const {
    if (shadow_maps_.empty()) return 0;
    const auto& lights = ctx.scene().lights();
    uint32_t shadowed = 0;
    for (uint32_t light = 0; light < CAUSTICA_MAX_LIGHTS; ++light) {
      const bool bound = holds(shadow_maps_, light);
      const std::string port = graph::port_element("shadow", bound ? light : shadow_maps_.front());
      writer.image_element("shadow_maps", light, ctx.array_view(port), ctx.nearest_sampler());
      const bool point = light < lights.size() && lights[light].type == scene::LightType::point;
      if (bound && light < lights.size() && (!point || ctx.resource(port).layers == 6)) shadowed |= 1u << light;
    }
    return shadowed;
  }

  // Every element of the caustic maps' and receiver depths' arrays, as the shadow maps'; a light
  // counts only with a view (a point light's is fitted to its refractors, or it has none).
  void write_caustic_maps(const graph::PassContext& ctx, vk::DescriptorWriter& writer, LightingParams& params) const {
    if (caustic_maps_.empty()) return;
    const auto& lights = ctx.scene().lights();
    for (uint32_t light = 0; light < CAUSTICA_MAX_LIGHTS; ++light) {
      const bool mapped = holds(caustic_maps_, light), tested = holds(caustic_depths_, light);
      writer.image_element("caustic_maps", light, ctx.view(graph::port_element("caustics", mapped ? light : caustic_maps_.front())),
                           ctx.linear_sampler());
      const std::string depth =
          caustic_depths_.empty() ? "depth" : graph::port_element("caustic_depth", tested ? light : caustic_depths_.front());
      writer.image_element("caustic_depths", light, ctx.view(depth), ctx.nearest_sampler());
      if (!mapped || light >= lights.size() || !lights[light].has_caustic_view) continue;
      params.caustic_lights |= 1u << light;
      if (tested) params.caustic_depths |= 1u << light;
    }
  }

  vk::Pipeline pipeline_;
  std::vector<uint32_t> shadow_maps_, caustic_maps_, caustic_depths_;  // the lights whose element of each is bound
  bool has_emission_ = false;
};

}  // namespace

graph::PassTypeDecl lighting_pass_type() {
  using namespace graph;
  PassTypeDecl decl{
      "lighting",
      "Full-screen pass: direct light from every scene light on the G-buffer (inverse square, spot cone; each light shadowed "
      "by its shadow map where one is bound) through each surface's BRDF (Lambertian, or glTF's metallic-roughness), ambient sky light, "
      "emitted light when bound, the sky where there is no geometry. Linear HDR radiance out.",
      PassQueue::graphics,
      {{"depth", PortAccess::read, ResourceKind::image, PortUsage::sampled, {Format::d32f}, false, "frame", "camera depth"},
       {"normal", PortAccess::read, ResourceKind::image, PortUsage::sampled, {}, false, "frame", "world normal"},
       {"albedo", PortAccess::read, ResourceKind::image, PortUsage::sampled, {}, false, "frame", "base colour; alpha: metallic"},
       {"emission",
        PortAccess::read,
        ResourceKind::image,
        PortUsage::sampled,
        {},
        true,
        "frame",
        "emitted radiance, added as it is; alpha: ambient occlusion, which scales the sky light"},
       {"shadow",
        PortAccess::read,
        ResourceKind::image,
        PortUsage::sampled,
        {Format::d32f},
        true,
        "",
        "each light's shadow map (a per-light port: element K is light K's; one map bound alone is light 0's); a point light's "
        "has six layers, its cube faces"},
       {"caustics",
        PortAccess::read,
        ResourceKind::image,
        PortUsage::sampled,
        {Format::r32f},
        true,
        "",
        "each light's caustic map (a per-light port, as shadow): flux per texel of its image plane, a layer per colour channel "
        "(caustic_map)",
        false,
        3},
       {"caustic_depth",
        PortAccess::read,
        ResourceKind::image,
        PortUsage::sampled,
        {Format::d32f},
        true,
        "",
        "each light's depth of opaque geometry (a per-light port), for its caustic map's receiver test (without it the "
        "caustic also lands on surfaces that the light does not see first)"},
       {"color",
        PortAccess::write,
        ResourceKind::image,
        PortUsage::color_attachment,
        {Format::rgba16f, Format::rgba32f},
        false,
        "frame",
        "lit radiance"}},
      {{"shadow_bias", ParamType::float_, 0.02, 0.0, 10.0, {}, "bias of the shadow test, in scene units along the light's axis", true}},
      false,
      [] { return std::make_unique<LightingPass>(); }};
  for (PortDecl& port : decl.ports) {
    if (port.name == "shadow") port.per_light = port.cube_layers = true;
    if (port.name == "caustics" || port.name == "caustic_depth") port.per_light = true;
  }
  decl.needs_scene = true;
  decl.depends_on = [](const nlohmann::json&) { return kDependsOnScene; };
  // Either half of the caustic pair alone renders (one port at a time is how the editor connects
  // them), but is rarely what the graph means.
  decl.check = [](const nlohmann::json&, const PortResources& resource) {
    PassCheck check;
    if (resource("caustics") && !resource("caustic_depth")) {
      check.warning =
          "'caustics' is bound without 'caustic_depth': the caustic map is applied without its receiver test, also on "
          "surfaces its light does not see first";
    } else if (!resource("caustics") && resource("caustic_depth")) {
      check.warning = "'caustic_depth' is bound without 'caustics': it is not read";
    }
    return check;
  };
  return decl;
}

}  // namespace caustica::passes
