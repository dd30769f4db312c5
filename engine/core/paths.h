#pragma once
#include <filesystem>

namespace caustica {

// Where shaders/ and graphs/ live: $CAUSTICA_DATA_DIR; else share/caustica beside the running
// executable when it is an installed copy (PREFIX/bin/caustica, found through /proc/self/exe, so
// that an installed tree runs wherever it is moved); else the source tree this binary was built
// from (so a build runs without installing); else the install prefix it was configured with.
std::filesystem::path data_dir();

}  // namespace caustica
