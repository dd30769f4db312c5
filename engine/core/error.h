#pragma once
// The three failure classes of the command line contract (DESIGN.md, "Errors"): bad input exits 1,
// usage mistakes exit 2, device or runtime failures exit 3. Programmer mistakes are asserts.
#include <stdexcept>
#include <string>

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

class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class DeviceError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// "file:line:col" with the parts that are known.
std::string format_location(const std::string& file, SourceLocation where);

}  // namespace caustica
