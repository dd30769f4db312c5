#include "core/paths.h"

#include <cstdlib>
#include <vector>

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

std::string find_data_file(const std::string& given, const char* folder) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path path(given);
  if (given.empty() || fs::exists(path, ec) || path.is_absolute()) return given;
  const fs::path data = data_dir();
  std::vector<fs::path> candidates{data / path, data / folder / path};
  if (!path.has_extension()) candidates.push_back(data / folder / (given + ".json"));
  for (const auto& candidate : candidates) {
    if (fs::is_regular_file(candidate, ec)) return candidate.string();
  }
  // A bare name stood for a bundled file: the loader's message names the file it would have been.
  return path.has_extension() ? given : candidates.back().string();
}

}  // namespace caustica
