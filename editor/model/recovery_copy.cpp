#include "model/recovery_copy.h"

#include <filesystem>

#include "io/files.h"

namespace caustica::editor {

std::string recovery_path(const std::string& graph_file) {
  std::filesystem::path path(graph_file);
  const std::string extension = path.has_extension() ? path.extension().string() : ".json";
  path.replace_extension();
  return path.string() + ".recovered" + extension;
}

std::string write_recovery_copy(const GraphModel& model) {
  if (!model.modified()) return "";
  const std::string path = recovery_path(model.path());
  io::write_text_atomically(path, model.text());
  return path;
}

std::string recovery_offer(const std::string& graph_file) {
  const std::string path = recovery_path(graph_file);
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return "";
  return path + " holds unsaved edits of " + graph_file + " from a session that ended on a device failure: to take them, quit and " +
         "move it over the graph file (mv " + path + " " + graph_file + "), or open it (caustica edit " + path +
         "); delete it to drop them";
}

}  // namespace caustica::editor
