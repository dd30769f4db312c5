#pragma once
// Size expressions in graph files: "output.width / 2", "grid * grid * 16", "max(1, light_size / 4)".
// Numbers, names, + - * / %, parentheses, and min max floor ceil round log2 pow.
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace caustica::graph {

struct ExpressionScope {
  // Returns the value of a name, or nullopt when the name is unknown.
  std::function<std::optional<double>(std::string_view)> lookup;
  // Names offered as suggestions when a name is unknown.
  std::vector<std::string> known_names;
};

// Throws std::invalid_argument with a message that says what and where in the expression.
double evaluate_expression(std::string_view text, const ExpressionScope& scope);

// A name in an expression ("scene.light0.spot"): a letter or '_', then letters, digits, '_' and '.'.
bool is_name_start(char c);
bool is_name_char(char c);

}  // namespace caustica::graph
