#pragma once
// Typed reads from a JsonDocument whose errors name the file, line and JSON pointer: the shared
// vocabulary of the graph and scene loaders.
#include <cctype>
#include <cmath>
#include <string>
#include <vector>

#include "core/suggest.h"
#include "io/json_document.h"

namespace caustica {

class JsonReader {
 public:
  explicit JsonReader(const JsonDocument& doc) : doc_(doc) {}

  const nlohmann::json& object(const nlohmann::json& value, const std::string& pointer, const char* what) const {
    if (!value.is_object()) throw doc_.error(pointer, std::string(what) + " must be an object, not " + type_name(value));
    return value;
  }

  void only_keys(const nlohmann::json& value, const std::string& pointer, const std::vector<std::string>& allowed,
                 const char* what) const {
    for (const auto& [key, unused] : value.items()) {
      bool known = false;
      for (const auto& a : allowed) known = known || a == key;
      if (!known) {
        throw doc_.error(json_pointer_append(pointer, key),
                         "unknown member '" + key + "' in " + what + did_you_mean(key, allowed));
      }
    }
  }

  std::string string(const nlohmann::json& value, const std::string& pointer, const char* what) const {
    if (!value.is_string()) throw doc_.error(pointer, std::string(what) + " must be a string, not " + type_name(value));
    return value.get<std::string>();
  }

  std::string name(const nlohmann::json& value, const std::string& pointer, const char* what) const {
    std::string text = string(value, pointer, what);
    if (text.empty()) throw doc_.error(pointer, std::string(what) + " must not be empty");
    if (text.size() > 128) throw doc_.error(pointer, std::string(what) + " is longer than 128 characters");
    for (char c : text) {
      bool ok = std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.';
      if (!ok) throw doc_.error(pointer, std::string(what) + " \"" + text + "\" may only use letters, digits, '_', '-' and '.'");
    }
    return text;
  }

  // An expression: a string, or a positive integer literal.
  std::string expression(const nlohmann::json& value, const std::string& pointer, const char* what) const {
    if (value.is_number_integer()) return std::to_string(value.get<long long>());
    if (value.is_number_float()) return value.dump();
    if (value.is_string()) return value.get<std::string>();
    throw doc_.error(pointer, std::string(what) + " must be a number or an expression string, not " + type_name(value));
  }

  static std::string type_name(const nlohmann::json& value) {
    switch (value.type()) {
      case nlohmann::json::value_t::null: return "null";
      case nlohmann::json::value_t::object: return "an object";
      case nlohmann::json::value_t::array: return "an array";
      case nlohmann::json::value_t::string: return "a string";
      case nlohmann::json::value_t::boolean: return "a boolean";
      default: return "a number";
    }
  }


  double number(const nlohmann::json& value, const std::string& pointer, const char* what, double min, double max) const {
    if (!value.is_number()) throw doc_.error(pointer, std::string(what) + " must be a number, not " + type_name(value));
    const double v = value.get<double>();
    if (v < min || v > max) {
      throw doc_.error(pointer, std::string(what) + " must be in [" + format_number(min) + ", " + format_number(max) + "], not " + format_number(v));
    }
    return v;
  }

  bool boolean(const nlohmann::json& value, const std::string& pointer, const char* what) const {
    if (!value.is_boolean()) throw doc_.error(pointer, std::string(what) + " must be true or false, not " + type_name(value));
    return value.get<bool>();
  }

  // An array of exactly n numbers, each within [min, max].
  std::vector<double> numbers(const nlohmann::json& value, const std::string& pointer, const char* what, size_t n, double min,
                              double max) const {
    if (!value.is_array() || value.size() != n) {
      throw doc_.error(pointer, std::string(what) + " must be an array of " + std::to_string(n) + " numbers");
    }
    std::vector<double> out;
    for (size_t i = 0; i < n; ++i) out.push_back(number(value[i], pointer + "/" + std::to_string(i), what, min, max));
    return out;
  }

  static std::string format_number(double v) {
    nlohmann::json j = v;
    // The range test comes first: converting a double beyond long long's range is undefined.
    if (std::abs(v) < 1e15 && v == std::floor(v)) return std::to_string(static_cast<long long>(v));
    return j.dump();
  }

  InputError error(const std::string& pointer, const std::string& message) const { return doc_.error(pointer, message); }

 private:
  const JsonDocument& doc_;
};

}  // namespace caustica
