#include "builtin_passes.h"

namespace caustica::passes {

const graph::PassRegistry& builtin_registry() {
  static const graph::PassRegistry registry = [] {
    graph::PassRegistry r;
    r.add(pattern_pass_type());
    r.add(box_blur_pass_type());
    r.add(tonemap_pass_type());
    return r;
  }();
  return registry;
}

}  // namespace caustica::passes
