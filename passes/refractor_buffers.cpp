// refractor_buffers: front and back surfaces of the refractors from the camera or a light, in one
// pass (two draws with opposite culling). Each texel: packed outward normal, distance from the eye,
// d_N, object index; distance 0 where there is no refractor. Optionally the front surfaces' tint
// and transmission (front_tint) and interface layers (front_layers).
#include "refractor_buffers.h"

#include "builtin_passes.h"

namespace caustica::passes {

void RefractorSurfaces::setup(graph::PassSetup& setup, const std::string& front, const std::string& front_depth) {
  for (int kind = 0; kind < 3; ++kind) {
    vk::RasterState state;
    state.color_formats = {graph::format_info(setup.resource(front).format).vk};
    state.depth_format = graph::format_info(setup.resource(front_depth).format).vk;
    state.cull = kind == 0 ? VK_CULL_MODE_BACK_BIT : kind == 1 ? VK_CULL_MODE_FRONT_BIT : VK_CULL_MODE_NONE;
    const char* names[] = {"refractor_front", "refractor_back", "refractor_thin"};
    pipelines_[kind] = make_scene_pipeline(setup, names[kind], "scene/refractor.frag", state);
    if (kind == 1 || (!setup.bound("front_tint") && !setup.bound("front_layers"))) continue;
    shader::Defines defines;
    for (const char* port : kTexelPorts) {
      if (!setup.bound(port)) continue;
      state.color_formats.push_back(graph::format_info(setup.resource(port).format).vk);
      defines[port == kTexelPorts[0] ? "REFRACTOR_TINT" : "REFRACTOR_LAYERS"] = "1";
    }
    per_texel_[kind / 2] =
        make_scene_pipeline(setup, kind ? "refractor_thin_per_texel" : "refractor_front_per_texel", "scene/refractor.frag", state, defines);
  }
}

RefractorSurfaces::Targets RefractorSurfaces::targets(graph::PassContext& ctx) {
  return {ctx.extent("front"),
          ctx.view("front"),
          ctx.view("back"),
          ctx.view("front_depth"),
          ctx.image("front_depth"),
          ctx.bound("back_depth") ? ctx.view("back_depth") : VK_NULL_HANDLE,
          ctx.bound("front_tint") ? ctx.view("front_tint") : VK_NULL_HANDLE,
          ctx.bound("front_layers") ? ctx.view("front_layers") : VK_NULL_HANDLE};
}

namespace {

// An optional port of the front surfaces' texels: what image space reads per texel where it meets a
// refractor's front surface, and without which it takes each material's means.
graph::PortDecl front_texels_port(const char* name, std::vector<graph::Format> formats, graph::PortAccess access, graph::PortUsage usage,
                                  const char* extent_group, const std::string& what) {
  return graph::PortDecl{name,
                         access,
                         graph::ResourceKind::image,
                         usage,
                         std::move(formats),
                         true,
                         extent_group,
                         "optional: " + what + ", from the refractors' textures; without it image space takes each material's means"};
}

}  // namespace

graph::PortDecl RefractorSurfaces::front_tint_port(graph::PortAccess access, graph::PortUsage usage, const char* extent_group) {
  using graph::Format;
  return front_texels_port("front_tint", {Format::rgba8_srgb, Format::rgba8, Format::rgba16f}, access, usage, extent_group,
                           "the front surfaces' tint (rgb) and transmission (a) per texel");
}

graph::PortDecl RefractorSurfaces::front_layers_port(graph::PortAccess access, graph::PortUsage usage, const char* extent_group) {
  return front_texels_port("front_layers", {graph::Format::rgba32ui, graph::Format::rg32ui}, access, usage, extent_group,
                           "the front surfaces' interface layers per texel (the texels of KHR_materials_specular's, _clearcoat's and "
                           "_iridescence's textures, packed as the G-buffer's layers target's z and w, "
                           "shaders/scene/material_targets.glsl; rgba32ui: and the coat's normal where its own map bends it)");
}

graph::PortDecl RefractorSurfaces::back_depth_port(const char* extent_group) {
  using namespace graph;
  return PortDecl{
      "back_depth",        PortAccess::write,
      ResourceKind::image, PortUsage::depth_attachment,
      {Format::d32f},      true,
      extent_group,        "depth for the back-surface draw; without it the front's depth image is cleared and reused (one image less)"};
}

void RefractorSurfaces::record(graph::PassContext& ctx, const SceneView& view, scene::DrawRange range, const Targets& targets,
                               bool back_only) {
  VkCommandBuffer cmd = ctx.cmd();
  const DrawPush push(view);
  // front_tint and front_layers are drawn only where a refractor's tint or interface layers vary:
  // nothing reads them elsewhere, and drawing the tint cost the untextured bunny's light view 13%
  // (45 -> 51 ms at 1024^2 on lavapipe).
  const scene::Scene& scene = ctx.scene().scene();
  const bool per_texel = (targets.front_tint != VK_NULL_HANDLE && scene.tints_per_texel()) ||
                         (targets.front_layers != VK_NULL_HANDLE && scene.has_layer_textures());
  for (int back = 0; back < 2; ++back) {
    const scene::DrawRange drawn = back || !back_only ? range : scene::DrawRange{};  // back_only: the front is only cleared
    const bool shared_depth = back && targets.back_depth == VK_NULL_HANDLE;
    if (shared_depth) wait_for_depth_writes(cmd, targets.front_depth_image);
    std::vector<Attachment> colors{{back ? targets.back : targets.front}};
    for (VkImageView texels : {targets.front_tint, targets.front_layers}) {
      if (!back && per_texel && texels != VK_NULL_HANDLE) colors.push_back({texels});
    }
    begin_rendering(cmd, targets.extent, colors, Attachment{back && !shared_depth ? targets.back_depth : targets.front_depth});
    // A thin wall is one surface, seen from either side: the front draw takes its nearest face
    // whichever way it faces; the back draw, as for solids, the nearest back face (a closed thin
    // object's far wall, or a one-sided pane seen from behind, again).
    const auto [solid, thin] = ctx.scene().split_thin(drawn);
    const scene::DrawRange parts[2] = {solid, thin};
    for (int part = 0; part < 2; ++part) {
      if (parts[part].index_count == 0) continue;
      const vk::Pipeline& pipeline = back ? pipelines_[1] : per_texel ? per_texel_[part] : pipelines_[part ? 2 : 0];
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline.pipeline.get());
      scene_descriptors(ctx, pipeline).push(ctx.vk(), cmd, pipeline);
      bind_scene_textures(ctx, cmd, pipeline);
      vkCmdPushConstants(cmd, pipeline.layout.get(), pipeline.stages, 0, sizeof(push), &push);
      draw_range(cmd, ctx.scene(), parts[part]);
    }
    vkCmdEndRendering(cmd);
  }
}

namespace {

class RefractorBuffersPass final : public graph::Pass {
 public:
  void setup(graph::PassSetup& setup) override { surfaces_.setup(setup, "front", "front_depth"); }

  void execute(graph::PassContext& ctx) override {
    const VkExtent2D extent = ctx.extent("front");
    surfaces_.record(ctx, chosen_view(ctx, extent), ctx.scene().refractors(), RefractorSurfaces::targets(ctx),
                     ctx.params()["faces"].get<std::string>() == "back");
  }

 private:
  RefractorSurfaces surfaces_;
};

}  // namespace

graph::PassTypeDecl refractor_buffers_pass_type() {
  using namespace graph;
  auto surface = [](const char* name, const char* what) {
    return PortDecl{name, PortAccess::write, ResourceKind::image, PortUsage::color_attachment, {Format::rgba32f}, false, "view", what};
  };
  auto depth = [](const char* name) {
    return PortDecl{name,   PortAccess::write,           ResourceKind::image, PortUsage::depth_attachment, {Format::d32f}, false,
                    "view", "depth for the surface draw"};
  };
  PassTypeDecl decl{
      "refractor_buffers",
      "Nearest front and nearest back surfaces of all refractors from the camera or a light: packed outward normal, "
      "distance from the eye, d_N and object index per texel (distance 0: no refractor).",
      PassQueue::graphics,
      {surface("front", "front faces"), surface("back", "back faces"), depth("front_depth"), RefractorSurfaces::back_depth_port("view"),
       RefractorSurfaces::front_tint_port(PortAccess::write, PortUsage::color_attachment, "view"),
       RefractorSurfaces::front_layers_port(PortAccess::write, PortUsage::color_attachment, "view")},
      [] {
        auto params = view_params();
        params.push_back({"faces",
                          ParamType::choice,
                          "both",
                          {},
                          {},
                          {"both", "back"},
                          "draw both surfaces, or only the back ones (the front is then cleared: forward refraction)"});
        return params;
      }(),
      false,
      [] { return std::make_unique<RefractorBuffersPass>(); }};
  decl.needs_scene = true;
  decl.uses_light_view = [](const nlohmann::json& params) { return params.value("view", "camera") == "light"; };
  decl.depends_on = [](const nlohmann::json& params) {
    return kDependsOnGeometry | (params.value("view", "camera") == "light" ? kDependsOnLights : kDependsOnCamera);
  };
  return decl;
}

}  // namespace caustica::passes
