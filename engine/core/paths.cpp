#include "core/paths.h"

#include <cstdlib>

namespace caustica {
namespace {

bool has_shaders(const std::filesystem::path& dir) {
  std::error_code ec;
  return !dir.empty() && std::filesystem::is_directory(dir / "shaders", ec);
}

// PREFIX/share/caustica for an executable at PREFIX/bin; empty when the executable's path is unknown.
std::filesystem::path beside_executable() {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) return {};
  std::filesystem::path prefix = exe.parent_path();
  for (const auto& part : std::filesystem::path(CAUSTICA_INSTALL_BINDIR)) {
    if (!part.empty()) prefix = prefix.parent_path();
  }
  return prefix / CAUSTICA_INSTALL_DATADIR;
}

}  // namespace

std::filesystem::path data_dir() {
  if (const char* env = std::getenv("CAUSTICA_DATA_DIR"); env && *env) return env;
  if (const auto installed = beside_executable(); has_shaders(installed)) return installed;
  if (has_shaders(CAUSTICA_SOURCE_DATA_DIR)) return CAUSTICA_SOURCE_DATA_DIR;
  return CAUSTICA_INSTALL_DATA_DIR;
}

}  // namespace caustica
