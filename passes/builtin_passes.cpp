#include "builtin_passes.h"

namespace caustica::passes {

const graph::PassRegistry& builtin_registry() {
  static const graph::PassRegistry registry = [] {
    graph::PassRegistry r;
    r.add(pattern_pass_type());
    r.add(box_blur_pass_type());
    r.add(accumulate_pass_type());
    r.add(temporal_mean_pass_type());
    r.add(tonemap_pass_type());
    r.add(gbuffer_pass_type());
    r.add(shadow_map_pass_type());
    r.add(lighting_pass_type());
    r.add(refractor_buffers_pass_type());
    r.add(deferred_refraction_pass_type());
    r.add(forward_refraction_pass_type());
    r.add(refraction_layers_pass_type());
    r.add(caustic_map_pass_type());
    r.add(adaptive_caustic_map_pass_type());
    r.add(hierarchical_caustic_map_pass_type());
    r.add(user_compute_pass_type());
    r.add(user_fullscreen_pass_type());
    return r;
  }();
  return registry;
}

}  // namespace caustica::passes
