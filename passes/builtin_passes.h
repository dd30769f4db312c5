#pragma once
#include "graph/pass_type.h"

namespace caustica::passes {

// One line per pass type; each comes from its own file pair in passes/.
graph::PassTypeDecl pattern_pass_type();
graph::PassTypeDecl box_blur_pass_type();
graph::PassTypeDecl tonemap_pass_type();
graph::PassTypeDecl gbuffer_pass_type();
graph::PassTypeDecl shadow_map_pass_type();
graph::PassTypeDecl lighting_pass_type();
graph::PassTypeDecl refractor_buffers_pass_type();
graph::PassTypeDecl deferred_refraction_pass_type();
graph::PassTypeDecl forward_refraction_pass_type();
graph::PassTypeDecl refraction_layers_pass_type();
graph::PassTypeDecl caustic_map_pass_type();
graph::PassTypeDecl adaptive_caustic_map_pass_type();
graph::PassTypeDecl hierarchical_caustic_map_pass_type();
graph::PassTypeDecl accumulate_pass_type();
graph::PassTypeDecl temporal_mean_pass_type();
graph::PassTypeDecl user_compute_pass_type();
graph::PassTypeDecl user_fullscreen_pass_type();

// Every pass type the engine ships, registered under its type name.
const graph::PassRegistry& builtin_registry();

}  // namespace caustica::passes
