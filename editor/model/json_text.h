#pragma once
// JSON text that keeps its author's bytes. The graph editor changes a graph as a value
// (nlohmann::ordered_json, which keeps key order); writing it back with dump() would reformat the
// whole file. write_preserving instead copies the original text of every part that did not change
// and writes only what did, in the style of its neighbours.
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace caustica::editor {

// `value` as JSON text. `original` is the text `value` was read from (valid JSON) or empty. Every
// value equal to the one at the same place in `original` keeps its original text; a changed object
// or array keeps the separators and spacing of its unchanged members, and new members take those
// of their neighbours. So writing an unchanged value gives `original` byte for byte.
std::string write_preserving(const nlohmann::ordered_json& value, std::string_view original);

// write_preserving against one original, read once: the editor writes its graph after every edit,
// and reading the original (parsing it, finding its parts' bytes) cost more than the writing.
class PreservingWriter {
 public:
  explicit PreservingWriter(std::string original);
  std::string write(const nlohmann::ordered_json& value) const;
  const std::string& original() const;

 private:
  struct Original;
  std::shared_ptr<const Original> original_;
};

}  // namespace caustica::editor
