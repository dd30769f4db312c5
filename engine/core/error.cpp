#include "core/error.h"

namespace caustica {

std::string format_location(const std::string& file, SourceLocation where) {
  std::string text = file.empty() ? std::string("<input>") : file;
  if (where.line > 0) {
    text += ":" + std::to_string(where.line);
    if (where.column > 0) text += ":" + std::to_string(where.column);
  }
  return text;
}

}  // namespace caustica
