#include "core/engine_identity.h"

#include "caustica_commit.h"

namespace caustica {

const std::string& engine_identity() {
  static const std::string identity = std::string("caustica ") + CAUSTICA_VERSION + " (" + CAUSTICA_COMMIT + ")";
  return identity;
}

}  // namespace caustica
