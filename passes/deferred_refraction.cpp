// deferred_refraction: one full-screen pass over refractor_buffers' front and back surfaces.
#include "builtin_passes.h"
#include "refraction.h"

namespace caustica::passes {
namespace {

class DeferredRefractionPass final : public graph::Pass {
 public:
  void setup(graph::PassSetup& setup) override {
    tir_counter_ = setup.add_counter(setup.pass().name + ".tir_pixels");
    shading_.setup(setup, graph::format_info(setup.resource("color").format).vk);
  }

  void execute(graph::PassContext& ctx) override {
    const VkExtent2D extent = ctx.extent("color");
    const auto& scene = ctx.scene();
    const VkRect2D rect = screen_rect(scene.scene(), camera_view(ctx, extent).view_proj,
                                      scene.refractors_back_to_front(scene.scene().camera.position), extent);
    shading_.record(ctx, refraction_push(ctx, tir_counter_), ctx.view("background"), ctx.view("front"), ctx.view("back"), ctx.view("color"),
                    extent, rect);
  }

 private:
  DeferredRefractionShading shading_;
  uint32_t tir_counter_ = 0;
};

}  // namespace

graph::PassTypeDecl deferred_refraction_pass_type() {
  using namespace graph;
  auto ports = refraction_inputs();
  ports.push_back({"front", PortAccess::read, ResourceKind::image, PortUsage::sampled, {Format::rgba32f}, false, "frame",
                   "refractor front surfaces (refractor_buffers)"});
  ports.push_back({"back", PortAccess::read, ResourceKind::image, PortUsage::sampled, {Format::rgba32f}, false, "frame",
                   "refractor back surfaces (refractor_buffers)"});
  ports.push_back({"color", PortAccess::write, ResourceKind::image, PortUsage::color_attachment, {Format::rgba16f, Format::rgba32f}, false,
                   "frame", "the background with the refractors composited"});
  PassTypeDecl decl{"deferred_refraction",
                    "Full-screen image-space refraction through two interfaces (Wyman 2005) from G-buffer-like refractor surfaces: every "
                    "pixel shaded once. Counter <pass>.tir_pixels: pixels that met total internal reflection at the back surface.",
                    PassQueue::graphics,
                    ports,
                    refraction_params(),
                    false,
                    [] { return std::make_unique<DeferredRefractionPass>(); }};
  decl.needs_scene = true;
  return decl;
}

}  // namespace caustica::passes
