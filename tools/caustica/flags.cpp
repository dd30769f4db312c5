#include "flags.h"

#include <algorithm>
#include <cstdlib>
#include <set>

#include "core/paths.h"
#include "core/suggest.h"
#include "graph/plan.h"

namespace caustica::cli {

FlagTable::FlagTable(std::initializer_list<Flag> flags) {
  for (const Flag& f : flags) add(f);
}

FlagTable& FlagTable::add(Flag flag) {
  // Two declarations of one name would make the second unreachable: a mistake in the table itself.
  if (std::any_of(flags_.begin(), flags_.end(), [&](const Flag& f) { return f.name == flag.name; }))
    throw std::logic_error("flag " + flag.name + " is declared twice");
  flags_.push_back(std::move(flag));
  return *this;
}

std::vector<std::string> FlagTable::names() const {
  std::vector<std::string> names;
  for (const Flag& f : flags_) names.push_back(f.name);
  return names;
}

void FlagTable::parse(Args& args, const std::function<void(const std::string&)>& positional) const {
  std::set<std::string> given;
  while (!args.done()) {
    const std::string a = args.take();
    const auto flag = std::find_if(flags_.begin(), flags_.end(), [&](const Flag& f) { return f.name == a; });
    if (flag == flags_.end()) {
      if (positional && a.rfind("--", 0) != 0) {
        positional(a);
        continue;
      }
      unknown_option(a, names());
    }
    if (!flag->repeatable) given_once(given, a);
    flag->take(flag->value.empty() ? std::string() : args.value(a));
  }
}

std::string FlagTable::help() const {
  constexpr size_t kColumn = 22;  // where the help text starts, after the two spaces of indent
  std::string text;
  for (const Flag& f : flags_) {
    std::string head = f.name + (f.value.empty() ? "" : " " + f.value);
    head += std::string(head.size() < kColumn ? kColumn - head.size() : 1, ' ');
    text += "  " + head;
    for (size_t start = 0; start <= f.help.size();) {
      const size_t end = std::min(f.help.find('\n', start), f.help.size());
      if (start > 0) text += std::string(kColumn + 2, ' ');
      text += f.help.substr(start, end - start) + "\n";
      start = end + 1;
    }
  }
  return text;
}

Flag uint_flag(std::string name, std::string value, std::string help, uint64_t& out, uint64_t min, uint64_t max) {
  const std::string flag = name;
  return {std::move(name), std::move(value), std::move(help),
          [&out, flag, min, max](const std::string& v) { out = parse_uint(flag, v, min, max); }};
}

Flag uint32_flag(std::string name, std::string value, std::string help, uint32_t& out, uint32_t min, uint32_t max) {
  const std::string flag = name;
  return {std::move(name), std::move(value), std::move(help),
          [&out, flag, min, max](const std::string& v) { out = static_cast<uint32_t>(parse_uint(flag, v, min, max)); }};
}

Flag number_flag(std::string name, std::string value, std::string help, double& out, double min, double max) {
  const std::string flag = name;
  return {std::move(name), std::move(value), std::move(help),
          [&out, flag, min, max](const std::string& v) { out = parse_number(flag, v, min, max); }};
}

Flag text_flag(std::string name, std::string value, std::string help, std::string& out) {
  return {std::move(name), std::move(value), std::move(help), [&out](const std::string& v) { out = v; }};
}

Flag switch_flag(std::string name, std::string help, bool& out, bool value) {
  return {std::move(name), "", std::move(help), [&out, value](const std::string&) { out = value; }};
}

Flag names_flag(std::string name, std::string value, std::string help, std::vector<std::string>& out) {
  const std::string flag = name;
  return {std::move(name), std::move(value), std::move(help), [&out, flag](const std::string& v) { out = parse_names(flag, v); }};
}

Flag powers_flag(std::string name, std::string value, std::string help, std::vector<uint32_t>& out, uint32_t min, uint32_t max) {
  const std::string flag = name;
  return {std::move(name), std::move(value), std::move(help),
          [&out, flag, min, max](const std::string& v) { out = parse_powers_of_two(flag, v, min, max); }};
}

Flag graph_flag(std::string& graph, std::string help) {
  if (help.empty()) {
    help =
        "graph to run (default: graphs/caustics_adaptive.json in the data folder); a\n"
        "bundled one also by its name from any folder (--graph caustics_regular)";
  }
  return {"--graph", "FILE", std::move(help), [&graph](const std::string& v) { graph = find_data_file(v, "graphs"); }};
}

Flag scene_flag(std::string& scene, bool* given, std::string help) {
  if (help.empty()) help = "the scene, or a model file (.gltf, .glb, .obj, .off) as render takes it";
  return {"--scene", "FILE", std::move(help), [&scene, given](const std::string& v) {
            scene = find_data_file(v, "scenes");
            if (given) *given = true;
          }};
}

Flag no_stage_flag(bool& stage) {
  return switch_flag("--no-stage", "with a model file: no floor", stage, false);
}

Flag size_flag(uint32_t& width, uint32_t& height, std::string help) {
  return {"--size", "WxH", std::move(help), [&width, &height](const std::string& v) { parse_size(v, width, height); }};
}

Flag set_flag(std::vector<std::string>& sets, std::string help) {
  if (help.empty()) help = "override a graph parameter (repeatable)";
  return {"--set", "NAME=VALUE", std::move(help), [&sets](const std::string& v) { sets.push_back(v); }, true};
}

Flag frames_flag(uint32_t& frames, uint32_t max, std::string help) {
  return uint32_flag("--frames", "N", std::move(help), frames, 1, max);
}

Flag orbit_flag(float& degrees, std::string help) {
  return {"--orbit", "DEG", std::move(help),
          [&degrees](const std::string& v) { degrees = static_cast<float>(parse_number("--orbit", v, -180, 180)); }};
}

Flag stats_flag(std::string& stats, std::string help) {
  return text_flag("--stats", "FILE.json", std::move(help), stats);
}

Flag device_flag(std::string& device) {
  return text_flag("--device", "NAME", "Vulkan device whose name contains NAME (default: lavapipe)", device);
}

Flag tracer_flag() {
  return {"--tracer", "KIND",
          "how passes that trace exact paths walk the scene: ray_query (the driver's ray\n"
          "queries), compute (the engine's BVH in compute shaders, every device) or auto\n"
          "(default: ray queries where the device has them, else compute; CAUSTICA_TRACER)",
          [](const std::string& v) {
            if (v != "auto" && !graph::parse_tracer(v)) throw UsageError("--tracer " + v + ": expected ray_query, compute or auto");
            ::setenv("CAUSTICA_TRACER", v.c_str(), 1);
          }};
}

Flag frame_timeout_flag(double& seconds, double* first_frame_seconds, std::string default_help) {
  return {"--frame-timeout", "S",
          "end with exit code 3 and the name of the pass that was running when a frame has not\n"
          "finished after S seconds (a shader that never ends); " +
              std::move(default_help),
          [&seconds, first_frame_seconds](const std::string& v) {
            seconds = parse_number("--frame-timeout", v, 0.1, 86400);
            if (first_frame_seconds) *first_frame_seconds = seconds;
          }};
}

Flag validate_flag(bool& validate, std::string help) {
  if (help.empty()) {
    help =
        "enable Khronos validation (with synchronization validation); any\n"
        "message makes the command exit 3";
  }
  return switch_flag("--validate", std::move(help), validate);
}

Flag moving_flag(bool& moving, std::string help) {
  if (help.empty()) {
    help =
        "the graph's parameters as declared (the values while moving); by default, as\n"
        "the viewer at rest, each parameter's first \"while_still\" value where the graph\n"
        "declares one and --set does not set it (caustics_progressive: distance=ray_query)";
  }
  return switch_flag("--moving", std::move(help), moving);
}

Flag blur_flag(double& sigma, std::string help) {
  return number_flag("--blur", "SIGMA", std::move(help), sigma, 0, 64);
}

}  // namespace caustica::cli
