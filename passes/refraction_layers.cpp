// refraction_layers: multi-layer deferred refraction. One layer per refractor, sorted back to front
// from the camera every frame; each layer draws that refractor's surfaces, then refracts the
// previous layer's result (the background for the farthest) in a compute pass. `color` and the
// background ping-pong so that the last layer lands in `color`: the background is only read by the
// farthest layer, so reusing it saves a frame-sized image at the graph's peak of memory.
#include <algorithm>
#include <array>
#include <map>

#include "builtin_passes.h"
#include "refraction.h"
#include "refractor_buffers.h"

namespace caustica::passes {
namespace {

// How the pass uses an image at a point in its recording: the layout, and the stage and access that
// a transition out of it waits for, or into it makes wait.
struct Use {
  VkImageLayout layout;
  VkPipelineStageFlags2 stage;
  VkAccessFlags2 access;
};
constexpr Use kAttachmentWrite{VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                               VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT};
constexpr Use kSampledRead{VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                           VK_ACCESS_2_SHADER_SAMPLED_READ_BIT};
constexpr Use kStorageWrite{VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT};

class RefractionLayersPass final : public graph::Pass {
 public:
  void setup(graph::PassSetup& setup) override {
    tir_counter_ = setup.add_counter(setup.pass().name + ".tir_pixels");
    layers_counter_ = setup.add_counter(setup.pass().name + ".layers");
    drawn_counter_ = setup.add_counter(setup.pass().name + ".surfaces_drawn");
    surfaces_.setup(setup, "front", "front_depth");
    shading_.setup(setup, setup.resource("color").format);
  }

  void execute(graph::PassContext& ctx) override {
    VkCommandBuffer cmd = ctx.cmd();
    const VkExtent2D extent = ctx.extent("color");
    const auto& scene = ctx.scene();
    const std::vector<uint32_t> order = scene.refractors_back_to_front(scene.camera().position);
    ctx.set_counter(layers_counter_, static_cast<double>(order.size()));
    const SceneView view = camera_view(ctx, extent);
    const RefractionPush push = refraction_push(ctx, tir_counter_);
    // Every port starts and ends in the plan's layout for it; in between each is wherever the last
    // layer left it.
    std::map<std::string, Use> state{{"color", kStorageWrite}, {"background", kStorageWrite}};
    for (const char* surface : {"front", "back", "front_tint", "front_layers"}) state[surface] = kAttachmentWrite;
    auto make = [&](const std::string& name, const Use& wanted) {
      Use& current = state.at(name);
      if (current.layout == wanted.layout) return;
      image_barrier(cmd, ctx.image(name), VK_IMAGE_ASPECT_COLOR_BIT, current.layout, wanted.layout, current.stage, current.access,
                    wanted.stage, wanted.access);
      current = wanted;
    };
    auto make_surfaces = [&](const Use& wanted) {
      for (const char* surface : {"front", "back", "front_tint", "front_layers"}) {
        if (ctx.bound(surface)) make(surface, wanted);
      }
    };
    const std::string ping_pong[2] = {"color", "background"};
    const auto layers = static_cast<uint32_t>(order.size());
    // A single layer's surfaces follow the camera and the geometry alone: at rest, where only the
    // background changed (a converging caustic), and while only a light moves, the ones drawn last
    // time are still there. Several
    // layers share the images, which then hold the nearest layer's.
    const bool one_layer_kept = layers == 1 && one_layer_drawn_ &&
                                ctx.scene_unchanged_since_last_run(graph::kDependsOnCamera | graph::kDependsOnGeometry) &&
                                std::all_of(kSurfacePorts.begin(), kSurfacePorts.end(),
                                            [&](const char* port) { return !ctx.bound(port) || ctx.kept_since_last_run(port); });
    one_layer_drawn_ = layers == 1;
    ctx.set_counter(drawn_counter_, one_layer_kept ? 0.0 : static_cast<double>(layers));
    // Layer i writes ping_pong[(layers - 1 - i) % 2], so the last writes color. With an even count
    // the farthest layer would write the background it reads: it reads a copy in color instead
    // (with no refractor at all, that copy is the result).
    if (layers % 2 == 0) {
      make("background", kSampledRead);
      shading_.copy(ctx, ctx.view("background"), ctx.view("color"), extent);
    }
    for (uint32_t i = 0; i < layers; ++i) {
      if (i > 0) {
        // The previous layer's surfaces were sampled and its depth written: both are reused.
        make_surfaces(kAttachmentWrite);
        for (const char* depth : {"front_depth", "back_depth"}) {
          if (ctx.bound(depth)) wait_for_depth_writes(cmd, ctx.image(depth));
        }
      }
      if (!one_layer_kept) surfaces_.record(ctx, view, scene.object(order[i]), RefractorSurfaces::targets(ctx));
      make_surfaces(kSampledRead);

      const std::string& target = ping_pong[(layers - 1 - i) % 2];
      const std::string& previous = ping_pong[(layers - i) % 2];
      make(previous, kSampledRead);
      make(target, kStorageWrite);
      shading_.record(ctx, push, ctx.view(previous), ctx.view("front"), ctx.view("back"), ctx.view(target), extent,
                      screen_rect(scene.scene(), view.view_proj, {order[i]}, extent));
    }
    make_surfaces(kAttachmentWrite);
    make("background", kStorageWrite);
  }

 private:
  RefractorSurfaces surfaces_;
  DeferredRefractionShading shading_;
  static constexpr std::array<const char*, 6> kSurfacePorts{"front", "back", "front_tint", "front_layers", "front_depth", "back_depth"};
  uint32_t tir_counter_ = 0, layers_counter_ = 0, drawn_counter_ = 0;
  bool one_layer_drawn_ = false;  // the last run drew one layer's surfaces
};

}  // namespace

graph::PassTypeDecl refraction_layers_pass_type() {
  using namespace graph;
  auto ports = refraction_inputs();
  ports[0] = {"background",
              PortAccess::read_write,
              ResourceKind::image,
              PortUsage::storage,
              {Format::rgba16f},
              false,
              "frame",
              "radiance behind the refractors (an output: with two or more layers it is also color's ping-pong partner, and "
              "afterwards holds an intermediate layer)"};
  auto scratch = [](const char* name, Format format, PortUsage usage, const char* what) {
    return PortDecl{name, PortAccess::write, ResourceKind::image, usage, {format}, false, "frame", what};
  };
  ports.push_back({"color",
                   PortAccess::write,
                   ResourceKind::image,
                   PortUsage::storage,
                   {Format::rgba16f},
                   false,
                   "frame",
                   "the background with every refractor composited, back to front"});
  ports.push_back(scratch("front", Format::rgba32f, PortUsage::color_attachment, "one refractor's front surface, reused per layer"));
  ports.push_back(scratch("back", Format::rgba32f, PortUsage::color_attachment, "one refractor's back surface, reused per layer"));
  ports.push_back(RefractorSurfaces::front_tint_port(PortAccess::write, PortUsage::color_attachment, "frame"));
  ports.push_back(RefractorSurfaces::front_layers_port(PortAccess::write, PortUsage::color_attachment, "frame"));
  for (auto& port : ports)
    port.also_sampled = port.name == "background" || port.name == "front" || port.name == "back" || port.name == "color" ||
                        port.name == "front_tint" || port.name == "front_layers";
  ports.push_back(scratch("front_depth", Format::d32f, PortUsage::depth_attachment, "depth for the front-surface draw"));
  ports.push_back(RefractorSurfaces::back_depth_port("frame"));
  PassTypeDecl decl{"refraction_layers",
                    "Multi-layer deferred refraction: one layer per refractor, sorted back to front from the camera each frame; each "
                    "layer refracts the result of the layers behind it. Counters <pass>.layers, <pass>.tir_pixels and "
                    "<pass>.surfaces_drawn (the layers whose surfaces were drawn: 0 where one layer's, kept from the last run, "
                    "still hold for the camera and geometry).",
                    // Every shader access to its ports is in its compute dispatches; the surfaces
                    // are drawn into attachments.
                    PassQueue::compute, ports, with_search_bounces(refraction_params()), false,
                    [] { return std::make_unique<RefractionLayersPass>(); }};
  decl.needs_scene = true;
  decl.depends_on = [](const nlohmann::json&) { return kDependsOnScene; };
  return decl;
}

}  // namespace caustica::passes
