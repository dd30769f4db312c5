#include "io/files.h"

#include <unistd.h>

#include <fstream>

#include "core/error.h"

namespace caustica::io {

void check_output_file(const std::string& path) {
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  std::error_code ec;
  if (!folder.empty() && !std::filesystem::is_directory(folder, ec)) {
    throw InputError(path + ": cannot write: folder '" + folder.string() + "' does not exist");
  }
}

std::filesystem::path temporary_name(const std::filesystem::path& target) {
  return target.parent_path() / ("." + target.stem().string() + ".partial-" + std::to_string(::getpid()) + target.extension().string());
}

void commit(const std::filesystem::path& temp, const std::filesystem::path& target) {
  std::error_code ec;
  std::filesystem::rename(temp, target, ec);
  if (ec) {
    std::filesystem::remove(temp, ec);
    throw InputError(target.string() + ": cannot write: " + ec.message());
  }
}

void write_text_atomically(const std::string& path, const std::string& text) {
  check_output_file(path);
  std::filesystem::path target(path);
  std::filesystem::path temp = temporary_name(target);
  {
    std::ofstream out(temp, std::ios::binary);
    out << text;
    out.flush();
    if (!out) {
      std::error_code ec;
      std::filesystem::remove(temp, ec);
      throw InputError(path + ": cannot write");
    }
  }
  commit(temp, target);
}

}  // namespace caustica::io
