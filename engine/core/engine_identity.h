#pragma once
#include <string>

namespace caustica {

// "caustica VERSION (COMMIT)": what made an output, where outputs of two builds must not be mixed
// (photon shards). COMMIT is git's describe of the source tree at build time, "-dirty" with local
// changes, "unknown" without git.
const std::string& engine_identity();

}  // namespace caustica
