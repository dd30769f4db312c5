#include "cli.h"

#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>

#include "core/suggest.h"
#include "io/json_reader.h"

namespace caustica::cli {

uint64_t parse_uint(const std::string& flag, const std::string& text, uint64_t min, uint64_t max) {
  size_t used = 0;
  unsigned long long v = 0;
  try {
    v = std::stoull(text, &used);
    // Counts such as 1e8 photons: a whole mantissa and a small whole exponent.
    if (used < text.size() && text[used] == 'e' && used + 1 < text.size() && text.size() - used <= 3 &&
        std::all_of(text.begin() + static_cast<std::ptrdiff_t>(used) + 1, text.end(), [](char c) { return c >= '0' && c <= '9'; })) {
      for (int e = std::stoi(text.substr(used + 1)); e > 0 && v <= max; --e) v *= 10;
      used = text.size();
    }
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || text.empty() || text[0] == '-' || v < min || v > max) {
    throw UsageError(flag + " " + text + ": expected a whole number from " + std::to_string(min) + " to " + std::to_string(max));
  }
  return v;
}

double parse_number(const std::string& flag, const std::string& text, double min, double max) {
  size_t used = 0;
  double v = 0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || text.empty() || !std::isfinite(v) || v < min || v > max) {
    throw UsageError(flag + " " + text + ": expected a number from " + JsonReader::format_number(min) + " to " +
                     JsonReader::format_number(max));
  }
  return v;
}

void parse_size(const std::string& v, uint32_t& width, uint32_t& height) {
  const size_t x = v.find_first_of("xX");
  const std::string usage = "--size " + v + ": expected WIDTHxHEIGHT, e.g. 1280x720";
  if (x == std::string::npos) throw UsageError(usage);
  if (x == 0) throw UsageError(usage + " (the width is missing)");
  if (x + 1 == v.size()) throw UsageError(usage + " (the height is missing)");
  const auto part = [&](const char* name, const std::string& text) {
    try {
      return static_cast<uint32_t>(parse_uint("--size", text, 1, 16384));
    } catch (const UsageError&) {
      throw UsageError(usage + " (the " + name + " '" + text + "' is not a whole number from 1 to 16384)");
    }
  };
  width = part("width", v.substr(0, x));
  height = part("height", v.substr(x + 1));
}

std::vector<uint32_t> parse_powers_of_two(const std::string& flag, const std::string& list, uint32_t min, uint32_t max) {
  std::vector<uint32_t> values;
  for (size_t start = 0; start <= list.size();) {
    const size_t comma = std::min(list.find(',', start), list.size());
    const uint64_t v = parse_uint(flag, list.substr(start, comma - start), min, max);
    if ((v & (v - 1)) != 0) throw UsageError(flag + ": " + std::to_string(v) + " is not a power of two");
    values.push_back(static_cast<uint32_t>(v));
    start = comma + 1;
  }
  return values;
}

std::vector<std::string> parse_names(const std::string& flag, const std::string& list) {
  std::vector<std::string> names;
  for (size_t start = 0; start <= list.size();) {
    const size_t comma = std::min(list.find(',', start), list.size());
    names.push_back(list.substr(start, comma - start));
    if (names.back().empty()) throw UsageError(flag + " " + list + ": expected names separated by commas");
    start = comma + 1;
  }
  return names;
}

void given_once(std::set<std::string>& given, const std::string& flag) {
  if (!given.insert(flag).second) throw UsageError(flag + " is given twice: give it once");
}

void unknown_option(const std::string& arg, const std::vector<std::string>& known) {
  throw UsageError("unknown option '" + arg + "'" + did_you_mean(arg, known) + "; see --help");
}

vk::ContextOptions device_options(const std::string& device, bool validate) {
  vk::ContextOptions options{device, validate, false};
  const char* fault = std::getenv("CAUSTICA_FAULT");
  if (fault == nullptr || *fault == '\0') return options;
  const std::string name = fault;
  if (name == "device_lost")
    options.injected_fault = VK_ERROR_DEVICE_LOST;
  else if (name == "out_of_memory")
    options.injected_fault = VK_ERROR_OUT_OF_DEVICE_MEMORY;
  else
    throw UsageError("CAUSTICA_FAULT=" + name + ": expected device_lost or out_of_memory");
  return options;
}

ProgressLine::ProgressLine(std::string label, uint64_t total)
    : label_(std::move(label)),
      total_(std::max<uint64_t>(total, 1)),
      start_(std::chrono::steady_clock::now()),
      terminal_(::isatty(STDERR_FILENO) != 0) {}

void ProgressLine::update(uint64_t done) {
  const int tenths = static_cast<int>(10 * std::min(done, total_) / total_);
  if (!terminal_ && tenths == printed_tenths_) return;
  printed_tenths_ = tenths;
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double left = done > 0 ? elapsed / double(done) * double(total_ - std::min(done, total_)) : 0.0;
  std::fprintf(stderr, "%s%s %llu/%llu (%.0f%%)  %.1f s elapsed, %.1f s left   %s", terminal_ ? "\r" : "", label_.c_str(),
               static_cast<unsigned long long>(done), static_cast<unsigned long long>(total_), 100.0 * double(done) / double(total_),
               elapsed, left, terminal_ && done < total_ ? "" : "\n");
}

std::vector<std::string> apply_at_rest(graph::GraphDesc& graph, const std::vector<std::string>& sets) {
  std::set<std::string> kept;
  for (const auto& assignment : sets) kept.insert(assignment.substr(0, assignment.find('=')));
  return graph::apply_still_values(graph, kept);
}

void configure_at_rest(const std::string& file, graph::GraphDesc& graph, const graph::GraphDesc& declared,
                       const std::vector<std::string>& still, const std::function<void(const graph::GraphDesc&)>& configure) {
  try {
    configure(graph);
  } catch (const InputError& e) {
    if (still.empty()) throw;
    configure(declared);
    graph = declared;
    std::string values;
    for (const auto& v : still) values += (values.empty() ? "" : ", ") + v;
    std::string reason = e.what();
    std::replace(reason.begin(), reason.end(), '\n', ' ');
    std::fprintf(stderr, "caustica: note: %s: the values as declared, not those at rest (%s): %s\n", file.c_str(), values.c_str(),
                 reason.c_str());
  }
}

scene::Scene load_scene_and_warn(const std::string& path, bool stage) {
  scene::Scene scene = scene::load_scene_file(path, stage);
  for (const auto& warning : scene.warnings) std::cerr << "caustica: warning: " << warning << "\n";
  return scene;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

}  // namespace caustica::cli
