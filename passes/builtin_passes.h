#pragma once
#include "graph/pass_type.h"

namespace caustica::passes {

// One line per pass type; each comes from its own file pair in passes/.
graph::PassTypeDecl pattern_pass_type();
graph::PassTypeDecl box_blur_pass_type();
graph::PassTypeDecl tonemap_pass_type();

// Every pass type the engine ships, registered under its type name.
const graph::PassRegistry& builtin_registry();

}  // namespace caustica::passes
