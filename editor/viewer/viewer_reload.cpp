#include "viewer/viewer_impl.h"

#include <iostream>

namespace caustica::editor {

bool Viewer::Impl::reload_shaders() {
  std::set<std::filesystem::path> edited;
  std::string names;
  for (auto& [file, time] : shader_times_) {
    const auto now = modified(file.string());
    if (now == time) continue;
    time = now;
    edited.insert(file);
    names += (names.empty() ? "" : ", ") + file.filename().string();
  }
  if (edited.empty()) return false;
  try {
    shaders_saved_.insert(edited.begin(), edited.end());
    configure();
    session_.report("reloaded " + names, false);
  } catch (const std::exception& e) {
    session_.report(e.what(), true);
  }
  std::fprintf(stderr, "view: %s%s\n", session_.status_is_error ? "kept the last good shaders: " : "", session_.status.c_str());
  return true;
}

void Viewer::Impl::watch_shaders() {
  std::map<std::filesystem::path, std::filesystem::file_time_type> watched;
  for (const auto& file : executor_.shader_files()) {
    const auto seen = shader_times_.find(file);
    watched[file] = seen != shader_times_.end() ? seen->second : modified(file.string());
  }
  shader_times_ = std::move(watched);
}

std::string Viewer::Impl::shown_name() const {
  const std::string scene_name =
      session_.scene && !session_.scene->name.empty() ? session_.scene->name : std::filesystem::path(session_.scene_file).stem().string();
  return executor_.plan().graph_name + " on " + scene_name;
}

bool Viewer::Impl::reload(bool first) {
  const auto graph_time = first || options_.watch_graph_file ? modified(session_.graph_file) : session_.graph_time;
  const auto scene_time = modified(session_.scene_file);
  if (!first && graph_time == session_.graph_time && scene_time == session_.scene_time) return false;
  try {
    graph::GraphDesc g = first || graph_time != session_.graph_time ? graph::load_graph_file(session_.graph_file) : *session_.graph;
    auto scene = std::make_shared<const scene::Scene>(scene::load_scene_file(session_.scene_file, options_.stage));
    for (const auto& warning : scene->warnings) std::cerr << "caustica: warning: " << warning << "\n";
    std::optional<graph::GraphDesc> previous = std::move(session_.graph);
    session_.graph = std::move(g);
    forget_still_values();
    try {
      executor_.set_scene(scene);
      configure();
    } catch (...) {
      session_.graph = std::move(previous);
      if (session_.scene) executor_.set_scene(session_.scene);
      if (session_.graph) configure();
      throw;
    }
    session_.scene = scene;
    window_.set_title("caustica: " + shown_name());
    session_.status = first ? "loaded " + session_.graph_file : "reloaded " + session_.graph_file + " and " + session_.scene_file;
    session_.status_is_error = false;
    std::fprintf(stderr, "view: %s\n", session_.status.c_str());
    for (const auto& warning : executor_.plan().warnings) {
      session_.report("warning: " + warning, true);
      std::fprintf(stderr, "view: warning: %s\n", warning.c_str());
    }
  } catch (const std::exception& e) {
    session_.status = e.what();
    session_.status_is_error = true;
    // On the first load there is nothing to keep: the caller reports the error and exits.
    if (!first) std::fprintf(stderr, "view: kept the last good files: %s\n", e.what());
  }
  session_.graph_time = graph_time;
  session_.scene_time = scene_time;
  return true;
}

void Viewer::Impl::configure(bool showing_passes_kept, bool picture_may_stand) {
  graph::ConfigureOptions configure;
  if (!inspector_.inspected.empty()) configure.retained.insert(inspector_.inspected);
  // While only the camera moves, the light's passes keep their last results.
  configure.reuse_unchanged_passes = options_.reuse;
  configure.hand_over.edited_shaders = shaders_saved_;
  configure.hand_over.picture_may_stand = picture_may_stand;
  const VkExtent2D size = render_size();
  graph::GraphDesc graph = edited(session_);
  const ViewBudget::Setting& setting = budget_.setting();
  for (auto& p : graph.parameters) {
    if (setting.step.lowered && p.while_moving) p.value = *p.while_moving;
  }
  if (setting.still_values) {
    std::set<std::string> edited;  // the user's values stand at rest
    for (const auto& [name, value] : session_.edits) edited.insert(name);
    graph::apply_still_values(graph, edited, setting.still_level);
  }
  try {
    executor_.configure(graph, size.width, size.height, configure);
  } catch (const InputError&) {
    if (inspector_.inspected.empty()) throw;
    inspector_.inspected.clear();  // the inspected image left the graph: back to its output
    configure.retained.clear();
    executor_.configure(graph, size.width, size.height, configure);
  }
  shaders_saved_.clear();  // the plan that set them up anew runs
  budget_.plan_changed(executor_.picture_standing(), showing_passes_kept);
  watch_shaders();
}

}  // namespace caustica::editor
