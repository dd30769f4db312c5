#pragma once
#include <filesystem>

namespace caustica {

// Where shaders/ and graphs/ live: $CAUSTICA_DATA_DIR, else the source tree this binary was built
// from (so a build runs without installing), else the installed share/caustica.
std::filesystem::path data_dir();

}  // namespace caustica
