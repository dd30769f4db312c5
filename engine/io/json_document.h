#pragma once
// A JSON document that remembers where every value came from, so that every message about a graph
// or a scene can name the file, the line and the JSON pointer. nlohmann::json keeps no positions;
// this parser builds the same nlohmann::json value and a pointer -> position table beside it, and
// is strict where nlohmann is lenient (duplicate keys, unbounded nesting, numbers out of range).
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <unordered_map>

#include "core/error.h"

namespace caustica {

class JsonDocument {
 public:
  static constexpr int kMaxDepth = 128;
  static constexpr size_t kMaxBytes = 64u << 20;

  // Throws InputError naming the file, line and column of the first syntax error.
  static JsonDocument parse(std::string_view text, std::string path);
  // Throws InputError when the file is missing, unreadable, not a regular file or too large.
  static JsonDocument load(const std::string& path);

  const nlohmann::json& root() const { return root_; }
  const std::string& path() const { return path_; }

  // Position of the value at `pointer`, or of its nearest ancestor that exists.
  SourceLocation locate(std::string_view pointer) const;

  // An InputError whose message starts with "file:line:col:" and ends with "(at pointer)".
  LocatedError error(std::string_view pointer, const std::string& message) const;

 private:
  friend class JsonParser;
  nlohmann::json root_;
  std::string path_;
  std::unordered_map<std::string, SourceLocation> locations_;
};

// Appends one reference token to a JSON pointer, escaping '~' and '/'.
std::string json_pointer_append(std::string_view pointer, std::string_view token);

// Reads a whole file; throws InputError naming it when it cannot.
std::string read_text_file(const std::string& path, size_t max_bytes);

}  // namespace caustica
