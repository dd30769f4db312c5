#include "viewer/hot_reload.h"

#include <algorithm>

namespace caustica::editor {

graph::GraphDesc edited(const Session& s) {
  graph::GraphDesc g = *s.graph;
  for (auto& pass : g.passes) {
    if (s.disabled.count(pass.name)) pass.enabled = "0";
  }
  std::vector<std::string> sets;
  for (const auto& [name, value] : s.edits) sets.push_back(name + "=" + value);
  graph::apply_overrides(g, sets);
  return g;
}

std::filesystem::file_time_type modified(const std::string& path) {
  std::error_code ec;
  const auto t = std::filesystem::last_write_time(path, ec);
  return ec ? std::filesystem::file_time_type{} : t;
}

std::filesystem::file_time_type newest_file(const std::filesystem::path& folder) {
  // file_time_type's epoch lies in the future on libstdc++: today's times are negative.
  auto newest = std::filesystem::file_time_type::min();
  std::error_code ec;
  for (auto it = std::filesystem::recursive_directory_iterator(folder, ec); !ec && it != std::filesystem::recursive_directory_iterator();
       it.increment(ec)) {
    if (it->is_regular_file(ec)) newest = std::max(newest, it->last_write_time(ec));
  }
  return newest;
}

}  // namespace caustica::editor
