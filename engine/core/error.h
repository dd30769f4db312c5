#pragma once
// The three failure classes of the command line contract (the README: "bad input exits 1 ..."): bad input exits 1,
// usage mistakes exit 2, device or runtime failures exit 3. Programmer mistakes are asserts.
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace caustica {

struct SourceLocation {
  int line = 0;    // 1-based; 0 when unknown
  int column = 0;  // 1-based; 0 when unknown
};

// Bad input: a graph, scene, parameter or file the user gave. The message already names the file,
// the line and the JSON pointer where there is one.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Bad input at a known place in a file (JsonDocument::error).
class LocatedError : public InputError {
 public:
  LocatedError(const std::string& message, SourceLocation where) : InputError(message), where_(where) {}
  SourceLocation where() const { return where_; }

 private:
  SourceLocation where_;
};

// The errors of an input's independent parts (a graph's passes, a pass's parameters and ports),
// gathered so that one run reports them all, in the order of their place in the file.
class ErrorList {
 public:
  static constexpr size_t kMaxReported = 20;

  // Runs `part`, keeping the InputError it throws; returns whether it succeeded.
  template <class Part>
  bool attempt(Part&& part) {
    try {
      part();
      return true;
    } catch (const LocatedError& e) {
      errors_.push_back({e.where(), e.what()});
    } catch (const InputError& e) {
      errors_.push_back({{}, e.what()});
    }
    return false;
  }
  // Throws one InputError holding every message gathered (a line each, at most kMaxReported), if any.
  void throw_if_any();

 private:
  struct Entry {
    SourceLocation where;
    std::string message;
  };
  std::vector<Entry> errors_;
};

class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class DeviceError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A frame that did not finish within its time (a shader that never ends): the device is still busy
// with it, so the process cannot tear its Vulkan objects down and ends at once (exit 3) after
// saving what it must. `pass()` names the pass that was running.
class FrameTimeout : public DeviceError {
 public:
  FrameTimeout(const std::string& message, std::string pass) : DeviceError(message), pass_(std::move(pass)) {}
  const std::string& pass() const { return pass_; }

 private:
  std::string pass_;
};

// SIGINT or SIGTERM arrived while a command waited for the device (core/interrupt.h): the command
// ends at once, whatever the device is doing.
class Interrupted : public std::runtime_error {
 public:
  explicit Interrupted(int signal) : std::runtime_error("interrupted"), signal_(signal) {}
  int signal() const { return signal_; }

 private:
  int signal_;
};

// "file:line:col" with the parts that are known.
std::string format_location(const std::string& file, SourceLocation where);

}  // namespace caustica
