#pragma once
// A command's flags as a table: each declared once (name, value placeholder, help, how its value
// is parsed and where it goes), from which the parsing, the did-you-mean for a misspelt flag, the
// refusal of a flag given twice and the options part of --help are all generated, so that none of
// them can disagree with another.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "cli.h"

namespace caustica::cli {

struct Flag {
  std::string name;   // "--size"
  std::string value;  // "WxH"; empty: a switch, which takes no value
  std::string help;   // lines after the first are indented under it in --help
  // Parses and stores the value (a switch: called with ""); throws UsageError naming the flag.
  std::function<void(const std::string& value)> take;
  bool repeatable = false;  // --set, --dump: each one adds; any other flag given twice is refused
};

class FlagTable {
 public:
  FlagTable() = default;
  FlagTable(std::initializer_list<Flag> flags);
  FlagTable& add(Flag flag);
  // Takes every argument. An argument that is not a flag goes to `positional`, or, without one, is
  // refused as an unknown option, as is a misspelt flag (with the nearest declared one).
  void parse(Args& args, const std::function<void(const std::string&)>& positional = nullptr) const;
  // The "  --name VALUE   help" lines, in the order declared.
  std::string help() const;
  std::vector<std::string> names() const;
  const std::vector<Flag>& flags() const { return flags_; }

 private:
  std::vector<Flag> flags_;
};

// The flags several commands share, each defined here alone; `help` replaces the usual text where
// a command means something of its own by it.
Flag graph_flag(std::string& graph, std::string help = "");
Flag scene_flag(std::string& scene, bool* given = nullptr, std::string help = "");
Flag no_stage_flag(bool& stage);
Flag size_flag(uint32_t& width, uint32_t& height, std::string help);
Flag set_flag(std::vector<std::string>& sets, std::string help = "");
Flag frames_flag(uint32_t& frames, uint32_t max, std::string help);
Flag orbit_flag(float& degrees, std::string help);
Flag stats_flag(std::string& stats, std::string help);
Flag device_flag(std::string& device);
// --tracer ray_query|compute|auto: how exact paths walk the scene; sets CAUSTICA_TRACER, which
// every executor of the process reads (graph::tracer_from_environment).
Flag tracer_flag();
Flag validate_flag(bool& validate, std::string help = "");
// --frame-timeout S: every frame's limit, a plan's first included (graph::Executor::set_frame_timeout):
// `seconds` and, where given, `first_frame_seconds`.
Flag frame_timeout_flag(double& seconds, double* first_frame_seconds, std::string default_help);
Flag moving_flag(bool& moving, std::string help = "");
Flag blur_flag(double& sigma, std::string help);

// A flag whose value is a whole number, a number or text stored as it is.
Flag uint_flag(std::string name, std::string value, std::string help, uint64_t& out, uint64_t min, uint64_t max);
Flag uint32_flag(std::string name, std::string value, std::string help, uint32_t& out, uint32_t min, uint32_t max);
Flag number_flag(std::string name, std::string value, std::string help, double& out, double min, double max);
Flag text_flag(std::string name, std::string value, std::string help, std::string& out);
Flag switch_flag(std::string name, std::string help, bool& out, bool value = true);
// Comma-separated: names (parse_names), or powers of two within [min, max] (parse_powers_of_two).
Flag names_flag(std::string name, std::string value, std::string help, std::vector<std::string>& out);
Flag powers_flag(std::string name, std::string value, std::string help, std::vector<uint32_t>& out, uint32_t min, uint32_t max);

}  // namespace caustica::cli
