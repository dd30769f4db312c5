#pragma once
#include <nlohmann/json.hpp>

#include "graph/pass_type.h"

namespace caustica::graph {

// JSON Schema (draft-07) for graph files, with each registered pass type's parameters and ports,
// so an editor completes and checks them. graphs/schema.json is this output; a test keeps it so.
nlohmann::ordered_json graph_schema_json(const PassRegistry& registry);

}  // namespace caustica::graph
