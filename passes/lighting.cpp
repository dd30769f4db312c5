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
  uint32_t caustic_lights;  // bit i: caustic view i's map is bound (and the view is present)
  uint32_t caustic_depths;  // bit i: and its receiver depth
};

// The elements of a per-light (or per-view) port that are bound, of the first `count`.
std::vector<uint32_t> bound_elements(const graph::PassSetup& setup, std::string_view port, uint32_t count) {
  std::vector<uint32_t> elements;
  for (uint32_t element = 0; element < count; ++element) {
    if (setup.bound(graph::port_element(port, element))) elements.push_back(element);
  }
  return elements;
}

bool holds(const std::vector<uint32_t>& lights, uint32_t light) {
  return std::find(lights.begin(), lights.end(), light) != lights.end();
}

class LightingPass final : public graph::Pass {
 public:
  void setup(graph::PassSetup& setup) override {
    shadow_maps_ = bound_elements(setup, "shadow", CAUSTICA_MAX_LIGHTS);
    caustic_maps_ = bound_elements(setup, "caustics", CAUSTICA_MAX_CAUSTIC_VIEWS);
    caustic_depths_ = bound_elements(setup, "caustic_depth", CAUSTICA_MAX_CAUSTIC_VIEWS);
    has_emission_ = setup.bound("emission");
    has_material_ = setup.bound("material") && setup.scene_value("scene.surface_layers") > 0.0;  // as gbuffer writes them
    has_layers_ = has_material_ && setup.bound("layers") && setup.scene_value("scene.surface_textures") > 0.0;
    // The samplers' arrays as long as the elements bound, so that the pushed set stays within the
    // device's limit (32 descriptors on lavapipe: eight lights' shadows and 32 views' maps and
    // depths would be 77).
    shadow_count_ = shadow_maps_.empty() ? 0 : shadow_maps_.back() + 1;
    caustic_count_ = caustic_maps_.empty() ? 0 : std::max(caustic_maps_.back(), caustic_depths_.empty() ? 0 : caustic_depths_.back()) + 1;
    const uint32_t descriptors = 5 + (has_material_ ? 3 : 0) + (has_layers_ ? 1 : 0) + shadow_count_ + 2 * caustic_count_,
                   limit = setup.vk().max_push_descriptors();
    if (descriptors > limit) {
      throw InputError("pass '" + setup.pass().name + "' reads " + std::to_string(shadow_count_) + " lights' shadow maps and " +
                       std::to_string(caustic_count_) + " caustic views' maps and receiver depths: " + std::to_string(descriptors) +
                       " descriptors, and this device pushes at most " + std::to_string(limit) + " to a pipeline (VkPhysicalDevice" +
                       "PushDescriptorPropertiesKHR::maxPushDescriptors); the scene has more lights or cube faces than lighting takes");
    }
    shader::Defines defines;
    if (!shadow_maps_.empty()) defines["SHADOWS"] = std::to_string(shadow_count_);
    if (!caustic_maps_.empty()) defines["CAUSTICS"] = std::to_string(caustic_count_);
    if (has_emission_) defines["EMISSION"] = "1";
    if (has_material_) defines["MATERIAL"] = "1";
    if (has_layers_) defines["LAYERS"] = "1";
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
    if (has_material_) {
      writer.image("material_tex", ctx.view("material"), ctx.nearest_sampler());
      writer.buffer("ObjectBlock", ctx.scene().objects());
      writer.buffer("TranslucentBlock", ctx.scene().translucent_samples());
    }
    if (has_layers_) writer.image("layers_tex", ctx.view("layers"), ctx.nearest_sampler());
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
    for (uint32_t light = 0; light < shadow_count_; ++light) {
      const bool bound = holds(shadow_maps_, light);
      const std::string port = graph::port_element("shadow", bound ? light : shadow_maps_.front());
      writer.image_element("shadow_maps", light, ctx.array_view(port), ctx.nearest_sampler());
      const bool point = light < lights.size() && lights[light].type == scene::LightType::point;
      if (bound && light < lights.size() && (!point || ctx.resource(port).layers == 6)) shadowed |= 1u << light;
    }
    return shadowed;
  }

  // Every element of the caustic maps' and receiver depths' arrays (one per caustic view), as the
  // shadow maps'; a view counts only where it is present (a point light may have none).
  void write_caustic_maps(const graph::PassContext& ctx, vk::DescriptorWriter& writer, LightingParams& params) const {
    if (caustic_maps_.empty()) return;
    const auto& views = ctx.scene().caustic_views();
    for (uint32_t view = 0; view < caustic_count_; ++view) {
      const bool mapped = holds(caustic_maps_, view), tested = holds(caustic_depths_, view);
      writer.image_element("caustic_maps", view, ctx.view(graph::port_element("caustics", mapped ? view : caustic_maps_.front())),
                           ctx.linear_sampler());
      const std::string depth =
          caustic_depths_.empty() ? "depth" : graph::port_element("caustic_depth", tested ? view : caustic_depths_.front());
      writer.image_element("caustic_depths", view, ctx.view(depth), ctx.nearest_sampler());
      if (!mapped || view >= views.size() || !views[view].present) continue;
      params.caustic_lights |= 1u << view;
      if (tested) params.caustic_depths |= 1u << view;
    }
  }

  vk::Pipeline pipeline_;
  std::vector<uint32_t> shadow_maps_, caustic_maps_, caustic_depths_;  // the lights (views) whose element of each is bound
  uint32_t shadow_count_ = 0, caustic_count_ = 0;                      // the arrays' lengths: the last bound element and those before
  bool has_emission_ = false, has_material_ = false, has_layers_ = false;
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
       {"material",
        PortAccess::read,
        ResourceKind::image,
        PortUsage::sampled,
        {Format::rgba32f},
        true,
        "frame",
        "the surface's anisotropy, clear coat normal and object (gbuffer's material): glTF's material extensions on opaque surfaces "
        "are drawn where bound, ignored where not"},
       {"layers",
        PortAccess::read,
        ResourceKind::image,
        PortUsage::sampled,
        {Format::rgba32ui},
        true,
        "frame",
        "the texels of those extensions' textures (gbuffer's layers): read per texel where bound, by their means where not"},
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
        "each caustic view's map (a per-view port: element K is caustic view K's, light K's own for K below the lights; one "
        "map bound alone is light 0's): flux per texel of its image plane, a layer per colour channel (caustic_map)",
        false,
        3},
       {"caustic_depth",
        PortAccess::read,
        ResourceKind::image,
        PortUsage::sampled,
        {Format::d32f},
        true,
        "",
        "each caustic view's depth of opaque geometry (a per-view port, as caustics), for its caustic map's receiver test "
        "(without it the caustic also lands on surfaces that the light does not see first)"},
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
