#pragma once
// Hot reload: the graph and scene as last loaded successfully, with the user's parameter edits on
// top, and the files' modification times that tell when to load them again.
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>

#include "graph/graph_desc.h"
#include "scene/scene.h"

namespace caustica::editor {

struct Session {
  std::string graph_file, scene_file;
  std::filesystem::file_time_type graph_time, scene_time;
  std::optional<graph::GraphDesc> graph;  // as loaded, before edits
  std::shared_ptr<const scene::Scene> scene;
  std::map<std::string, std::string> edits;  // parameter -> JSON value
  std::set<std::string> disabled;            // passes switched off in the panel
  std::string status;                        // the last reload, or the error that kept the old files
  bool status_is_error = false;

  void report(std::string message, bool error) {
    status = std::move(message);
    status_is_error = error;
  }
};

// The session's graph with its parameter edits and switched-off passes applied.
graph::GraphDesc edited(const Session& s);
// Takes command-line assignments (--set NAME=VALUE, as render reads them) as the user's edits, checked
// against the graph file.
void set_from_command_line(Session& s, const std::vector<std::string>& assignments);

// A file's modification time (the epoch's if it cannot be read).
std::filesystem::file_time_type modified(const std::string& path);

}  // namespace caustica::editor
