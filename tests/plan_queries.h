#pragma once
// What the compiler tests look up in a plan.
#include <stdexcept>
#include <string>

#include "graph/plan.h"

namespace caustica::test {

inline const graph::PlannedPass& pass_named(const graph::Plan& plan, const std::string& name) {
  for (const auto& p : plan.passes) {
    if (p.name == name) return p;
  }
  throw std::runtime_error("no pass " + name);
}

}  // namespace caustica::test
