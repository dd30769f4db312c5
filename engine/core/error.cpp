#include "core/error.h"

#include <algorithm>
#include <cstdint>
#include <utility>

namespace caustica {

std::string format_location(const std::string& file, SourceLocation where) {
  std::string text = file.empty() ? std::string("<input>") : file;
  if (where.line > 0) {
    text += ":" + std::to_string(where.line);
    if (where.column > 0) text += ":" + std::to_string(where.column);
  }
  return text;
}

void ErrorList::throw_if_any() {
  if (errors_.empty()) return;
  // A stable sort: messages without a place keep their order after the placed ones.
  std::stable_sort(errors_.begin(), errors_.end(), [](const Entry& a, const Entry& b) {
    const auto key = [](const Entry& e) { return std::pair(e.where.line == 0 ? INT32_MAX : e.where.line, e.where.column); };
    return key(a) < key(b);
  });
  std::string message;
  for (size_t i = 0; i < errors_.size() && i < kMaxReported; ++i) message += (i ? "\n" : "") + errors_[i].message;
  if (errors_.size() > kMaxReported) message += "\n(and " + std::to_string(errors_.size() - kMaxReported) + " more errors)";
  errors_.clear();
  throw InputError(message);
}

}  // namespace caustica
