#pragma once
// caustica edit's recovery copy: when a session ends on a device failure (a frame that does not
// finish: a user shader that never ends), the user's unsaved graph is written beside its file, and
// the next open of the file offers it. Nothing here needs a window or a device
// (tests/recovery_copy_test.cpp).
#include <string>

#include "model/graph_model.h"

namespace caustica::editor {

// Beside the graph file: graphs/mine.json -> graphs/mine.recovered.json.
std::string recovery_path(const std::string& graph_file);
// Writes the model's unsaved graph (GraphModel::text) to recovery_path(model.path()); returns that
// path, or "" when nothing was unsaved (the file holds it all).
std::string write_recovery_copy(const GraphModel& model);
// At open: what to tell the user about a recovery copy beside `graph_file` (which file, and how to
// take it or drop it); "" when there is none. The editor leaves the copy for the user to take: it
// may be older than edits saved since.
std::string recovery_offer(const std::string& graph_file);

}  // namespace caustica::editor
