// The flag table that every caustica command's parsing, did-you-mean, duplicate checks and --help
// are generated from (tools/caustica/flags.h), checked without running a command.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "flags.h"

namespace {

using caustica::UsageError;
using caustica::cli::Args;
using caustica::cli::FlagTable;

struct Parsed {
  uint32_t width = 0, height = 0, frames = 1;
  std::vector<std::string> sets, positional;
  bool moving = false;
  std::string error;  // the UsageError's message; empty when parsing succeeded
};

// Parses `argv` with a table of --size, --frames, --set (repeatable) and --moving; positionals
// are taken only where `positionals` says so.
Parsed parse(std::vector<std::string> argv, bool positionals = false) {
  Parsed p;
  const FlagTable table{caustica::cli::size_flag(p.width, p.height, "output size"),
                        caustica::cli::frames_flag(p.frames, 100, "frames to run\nsecond line"), caustica::cli::set_flag(p.sets),
                        caustica::cli::moving_flag(p.moving)};
  std::vector<char*> raw;
  for (auto& a : argv) raw.push_back(a.data());
  Args args(static_cast<int>(raw.size()), raw.data(), 0);
  try {
    if (positionals)
      table.parse(args, [&p](const std::string& a) { p.positional.push_back(a); });
    else
      table.parse(args);
  } catch (const UsageError& e) {
    p.error = e.what();
  }
  return p;
}

TEST(CliFlags, ValuesGoWhereTheTableSays) {
  const Parsed p = parse({"--size", "64x36", "--set", "a=1", "--frames", "7", "--set", "b=2", "--moving"});
  EXPECT_EQ(p.error, "");
  EXPECT_EQ(p.width, 64u);
  EXPECT_EQ(p.height, 36u);
  EXPECT_EQ(p.frames, 7u);
  EXPECT_EQ(p.sets, (std::vector<std::string>{"a=1", "b=2"}));
  EXPECT_TRUE(p.moving);
}

TEST(CliFlags, AMisspeltFlagIsRefusedWithTheNearestDeclaredOne) {
  EXPECT_EQ(parse({"--frams", "3"}).error, "unknown option '--frams' (did you mean '--frames'?); see --help");
  EXPECT_EQ(parse({"--movin"}).error, "unknown option '--movin' (did you mean '--moving'?); see --help");
  EXPECT_EQ(parse({"--zzzzzzzz"}).error, "unknown option '--zzzzzzzz'; see --help");
}

TEST(CliFlags, AFlagGivenTwiceIsRefusedUnlessItRepeats) {
  EXPECT_EQ(parse({"--size", "1x1", "--size", "2x2"}).error, "--size is given twice: give it once");
  EXPECT_EQ(parse({"--moving", "--moving"}).error, "--moving is given twice: give it once");
  EXPECT_EQ(parse({"--set", "a=1", "--set", "a=2"}).error, "");
}

TEST(CliFlags, AFlagWithoutItsValueSaysSo) {
  EXPECT_EQ(parse({"--frames"}).error, "--frames needs a value");
  EXPECT_EQ(parse({"--frames", "0"}).error, "--frames 0: expected a whole number from 1 to 100");
  EXPECT_EQ(parse({"--size", "5"}).error, "--size 5: expected WIDTHxHEIGHT, e.g. 1280x720");
}

TEST(CliFlags, PositionalsGoToTheCommandOnlyWhereItTakesThem) {
  EXPECT_EQ(parse({"a.exr", "--frames", "2", "b.exr"}, true).positional, (std::vector<std::string>{"a.exr", "b.exr"}));
  EXPECT_EQ(parse({"a.exr"}).error, "unknown option 'a.exr'; see --help");
  EXPECT_EQ(parse({"--framez", "2"}, true).error, "unknown option '--framez' (did you mean '--frames'?); see --help");
}

TEST(CliFlags, HelpListsEveryDeclaredFlagWithItsValueAndEveryLineOfItsText) {
  Parsed p;
  const FlagTable table{caustica::cli::size_flag(p.width, p.height, "output size"),
                        caustica::cli::frames_flag(p.frames, 100, "frames to run\nsecond line"), caustica::cli::set_flag(p.sets),
                        caustica::cli::moving_flag(p.moving)};
  const std::string help = table.help();
  EXPECT_EQ(table.names(), (std::vector<std::string>{"--size", "--frames", "--set", "--moving"}));
  for (const auto& flag : table.flags()) {
    const std::string head = "  " + flag.name + (flag.value.empty() ? "" : " " + flag.value) + " ";
    EXPECT_NE(help.find(head), std::string::npos) << flag.name << "\n" << help;
  }
  EXPECT_NE(help.find("  --size WxH            output size\n"), std::string::npos) << help;
  EXPECT_NE(help.find("  --frames N            frames to run\n                        second line\n"), std::string::npos) << help;
  EXPECT_NE(help.find("  --set NAME=VALUE      override a graph parameter (repeatable)\n"), std::string::npos) << help;
  EXPECT_LT(help.find("--size"), help.find("--moving"));  // in the order declared
}

TEST(CliFlags, AFlagDeclaredTwiceIsAMistakeInTheTable) {
  uint32_t w = 0, h = 0;
  FlagTable table{caustica::cli::size_flag(w, h, "output size")};
  EXPECT_THROW(table.add(caustica::cli::size_flag(w, h, "again")), std::logic_error);
}

}  // namespace
