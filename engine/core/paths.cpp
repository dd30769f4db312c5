#include "core/paths.h"

#include <cstdlib>

namespace caustica {

std::filesystem::path data_dir() {
  if (const char* env = std::getenv("CAUSTICA_DATA_DIR"); env && *env) return env;
  std::error_code ec;
  if (std::filesystem::exists(std::filesystem::path(CAUSTICA_SOURCE_DATA_DIR) / "shaders", ec)) return CAUSTICA_SOURCE_DATA_DIR;
  return CAUSTICA_INSTALL_DATA_DIR;
}

}  // namespace caustica
