#include "refraction.h"

namespace caustica::passes {

std::vector<graph::ParamDecl> refraction_params() {
  using graph::ParamType;
  return {{"distance", ParamType::choice, "dv_dn", {}, {}, {"dv", "dv_dn"},
           "distance to the back surface: d_V (along the view ray) or Wyman's d_V/d_N blend by refraction angle"},
          {"search_steps", ParamType::int_, 48, 4.0, 512.0, {}, "linear steps of the background search along the exit ray"},
          {"search_distance", ParamType::float_, 8.0, 0.01, 1000.0, {}, "how far the background search goes, in scene units"}};
}

RefractionPush refraction_push(const graph::PassContext& ctx, uint32_t tir_counter) {
  const auto& p = ctx.params();
  return {p["distance"].get<std::string>() == "dv" ? 0u : 1u, p["search_steps"].get<uint32_t>(), p["search_distance"].get<float>(),
          tir_counter};
}

std::vector<graph::PortDecl> refraction_inputs() {
  using namespace graph;
  return {{"background", PortAccess::read, ResourceKind::image, PortUsage::sampled, {}, false, "frame", "radiance behind the refractors"},
          {"depth", PortAccess::read, ResourceKind::image, PortUsage::sampled, {Format::d32f}, false, "frame", "depth of the background"}};
}

}  // namespace caustica::passes
