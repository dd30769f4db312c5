// deferred_refraction: one compute pass over refractor_buffers' front and back surfaces.
#include "builtin_passes.h"
#include "refraction.h"
#include "refractor_buffers.h"

namespace caustica::passes {
namespace {

class DeferredRefractionPass final : public graph::Pass {
 public:
  void setup(graph::PassSetup& setup) override {
    const std::string& name = setup.pass().name;
    tir_counter_ = setup.add_counter(name + ".tir_pixels");
    // The order of refraction.glsl's CAMERA_* and EXIT_* constants.
    using Kind = graph::PassSetup::CounterKind;
    exact_counters_ = add_consecutive_counters(setup, {{name + ".exact_pixels", Kind::count},
                                                       {name + ".retraced.tir", Kind::count},
                                                       {name + ".retraced.empty_back", Kind::count},
                                                       {name + ".retraced.off_surface", Kind::count},
                                                       {name + ".retraced.multiple_refractors", Kind::count},
                                                       {name + ".retraced.off_screen", Kind::count},
                                                       {name + ".retraced.refractor_ahead", Kind::count},
                                                       {name + ".trapped_pixels", Kind::count}});
    exact_.setup(setup);
    shading_.setup(setup, setup.resource("color").format, &exact_);
  }

  void execute(graph::PassContext& ctx) override {
    const VkExtent2D extent = ctx.extent("color");
    const auto& scene = ctx.scene();
    const VkRect2D rect =
        screen_rect(scene.scene(), camera_view(ctx, extent).view_proj, scene.refractors_back_to_front(scene.camera().position), extent);
    shading_.record(ctx, refraction_push(ctx, tir_counter_, exact_counters_), ctx.view("background"), ctx.view("front"), ctx.view("back"),
                    ctx.view("color"), extent, rect);
  }

 private:
  TracedScene exact_;
  DeferredRefractionShading shading_;
  uint32_t tir_counter_ = 0, exact_counters_ = 0;
};

}  // namespace

graph::PassTypeDecl deferred_refraction_pass_type() {
  using namespace graph;
  auto ports = refraction_inputs();
  auto surfaces = [](const char* name, const char* what) {
    return PortDecl{name, PortAccess::read, ResourceKind::image, PortUsage::sampled, {Format::rgba32f}, false, "frame", what};
  };
  ports.push_back(surfaces("front", "refractor front surfaces (refractor_buffers)"));
  ports.push_back(surfaces("back", "refractor back surfaces (refractor_buffers)"));
  ports.push_back(RefractorSurfaces::front_tint_port(PortAccess::read, PortUsage::sampled, "frame"));
  ports.push_back(RefractorSurfaces::front_layers_port(PortAccess::read, PortUsage::sampled, "frame"));
  ports.push_back({"color",
                   PortAccess::write,
                   ResourceKind::image,
                   PortUsage::storage,
                   {Format::rgba16f, Format::rgba32f},
                   false,
                   "frame",
                   "the background with the refractors composited"});
  PassTypeDecl decl{
      "deferred_refraction",
      "Compute pass: refraction from G-buffer-like refractor surfaces, every pixel shaded once: in image space through two "
      "interfaces (Wyman 2005; distance dv, dv_dn, search), or exact (ray_query: every interface of every refractor, by "
      "either tracer; hybrid: the search, traced exactly where it cannot be trusted). Counters <pass>.tir_pixels (total internal "
      "reflection at the back surface), <pass>.exact_pixels (traced exactly), <pass>.retraced.<reason> (hybrid), "
      "<pass>.trapped_pixels (still inside after max_interfaces).",
      PassQueue::compute,
      ports,
      exact_path_params("a camera ray"),
      false,
      [] { return std::make_unique<DeferredRefractionPass>(); }};
  decl.needs_scene = true;
  decl.depends_on = [](const nlohmann::json&) { return kDependsOnScene; };
  decl.traces_scene = traces_exact_paths;
  return decl;
}

}  // namespace caustica::passes
