#include "viewer/hot_reload.h"

#include <algorithm>

#include "core/error.h"

namespace caustica::editor {

graph::GraphDesc edited(const Session& s) {
  graph::GraphDesc g = *s.graph;
  for (auto& pass : g.passes) {
    if (s.disabled.count(pass.name)) pass.enabled = "0";
  }
  // The edits are JSON values (a choice among them a quoted string), checked again because a
  // reloaded file may have changed the parameter.
  for (const auto& [name, value] : s.edits) {
    // An init-capture: clang 14 cannot capture a structured binding.
    auto p = std::find_if(g.parameters.begin(), g.parameters.end(),
                          [&name = name](const graph::GraphParameter& gp) { return gp.decl.name == name; });
    if (p == g.parameters.end()) throw InputError(s.graph_file + " has no parameter '" + name + "' any more (set in the viewer)");
    const nlohmann::json parsed = nlohmann::json::parse(value);
    if (const std::string problem = graph::check_param_value(p->decl, parsed); !problem.empty()) {
      throw InputError(s.graph_file + ": parameter '" + name + "' as set in the viewer " + problem);
    }
    p->value = parsed;
  }
  return g;
}

void set_from_command_line(Session& s, const std::vector<std::string>& assignments) {
  if (assignments.empty()) return;
  graph::GraphDesc g = graph::load_graph_file(s.graph_file);
  graph::apply_overrides(g, assignments);
  for (const auto& assignment : assignments) {
    const std::string name = assignment.substr(0, assignment.find('='));
    s.edits[name] = g.find_parameter(name)->value.dump();
  }
}

std::filesystem::file_time_type modified(const std::string& path) {
  std::error_code ec;
  const auto t = std::filesystem::last_write_time(path, ec);
  return ec ? std::filesystem::file_time_type{} : t;
}

}  // namespace caustica::editor
