#pragma once
#include <filesystem>
#include <string>

namespace caustica {

// Where shaders/ and graphs/ live: $CAUSTICA_DATA_DIR; else share/caustica beside the running
// executable when it is an installed copy (PREFIX/bin/caustica, found through /proc/self/exe, so
// that an installed tree runs wherever it is moved); else the source tree this binary was built
// from (so a build runs without installing); else the install prefix it was configured with.
std::filesystem::path data_dir();

// A graph or scene named on the command line, found wherever one runs from: the file as given where
// it exists; else the same relative path in the data folder ("graphs/caustics_regular.json"); else
// a bundled file of `folder` ("graphs", "scenes") by its name, with or without ".json"
// ("caustics_regular", "stability/close_light"). A file found nowhere comes back as given (a bare
// name as the bundled file it stood for), for the loader to say it cannot open it. Not for files
// that are written (graph set, edit).
std::string find_data_file(const std::string& given, const char* folder);

}  // namespace caustica
