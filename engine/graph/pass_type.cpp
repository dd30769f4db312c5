#include "graph/pass_type.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <sstream>

#include "graph/per_light.h"

namespace caustica::graph {

const PortDecl* PassTypeDecl::find_port(std::string_view name) const {
  for (const auto& port : ports) {
    if (port.name == name) return &port;
  }
  // An element of a per-light port, as PlannedPass::ports names it ("shadow[2]").
  const auto [base, element] = split_port_element(name);
  if (element < 0) return nullptr;
  for (const auto& port : ports) {
    if (port.name == base && port.per_light) return &port;
  }
  return nullptr;
}

const ParamDecl* PassTypeDecl::find_param(std::string_view name) const {
  for (const auto& param : params) {
    if (param.name == name) return &param;
  }
  return nullptr;
}

std::vector<std::string> dependency_names(uint32_t dependencies) {
  std::vector<std::string> names;
  for (const auto& [bit, name] : {std::pair{kDependsOnGeometry, "geometry"}, std::pair{kDependsOnLights, "lights"},
                                  std::pair{kDependsOnCamera, "camera"}, std::pair{kDependsOnFrame, "frame"}}) {
    if (dependencies & bit) names.emplace_back(name);
  }
  return names;
}

std::string_view param_type_name(ParamType type) {
  switch (type) {
    case ParamType::float_: return "float";
    case ParamType::int_: return "int";
    case ParamType::bool_: return "bool";
    case ParamType::choice: return "choice";
  }
  return "?";
}

namespace {
std::string format_number(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}
}  // namespace

std::string check_param_value(const ParamDecl& decl, const nlohmann::json& value) {
  switch (decl.type) {
    case ParamType::bool_:
      if (!value.is_boolean()) return "expects true or false, got " + value.dump();
      return "";
    case ParamType::choice: {
      if (!value.is_string()) return "expects one of its choices as a string, got " + value.dump();
      for (const auto& c : decl.choices) {
        if (c == value.get<std::string>()) return "";
      }
      std::string list;
      for (const auto& c : decl.choices) list += (list.empty() ? "" : ", ") + c;
      return "has no choice " + value.dump() + "; choices: " + list;
    }
    case ParamType::int_:
      if (!value.is_number_integer()) return "expects an integer, got " + value.dump();
      break;
    case ParamType::float_:
      if (!value.is_number()) return "expects a number, got " + value.dump();
      break;
  }
  double v = value.get<double>();
  if (!std::isfinite(v)) return "must be finite";
  if (decl.min && v < *decl.min) return "is " + format_number(v) + ", below its minimum " + format_number(*decl.min);
  if (decl.max && v > *decl.max) return "is " + format_number(v) + ", above its maximum " + format_number(*decl.max);
  int exponent = 0;
  if (decl.power_of_two && std::frexp(v, &exponent) != 0.5) {
    // The powers of two on either side that the range allows; one of them does, as the default is one.
    std::vector<std::string> nearest;
    for (double candidate : {std::ldexp(0.5, exponent), std::ldexp(1.0, exponent)}) {
      if (candidate >= std::max(1.0, decl.min.value_or(1)) && candidate <= decl.max.value_or(candidate))
        nearest.push_back(format_number(candidate));
    }
    return "is " + format_number(v) + ", not a power of two; the nearest " +
           (nearest.size() == 1 ? "is " + nearest[0] : "are " + nearest[0] + " and " + nearest[1]);
  }
  return "";
}

std::vector<int64_t> powers_of_two_within(const ParamDecl& decl) {
  assert(decl.power_of_two && decl.min && decl.max && "only a power_of_two parameter, which declares its range");
  std::vector<int64_t> out;
  for (int e = 0; e < 63 && std::ldexp(1.0, e) <= *decl.max; ++e) {
    if (std::ldexp(1.0, e) >= *decl.min) out.push_back(int64_t{1} << e);
  }
  return out;
}

nlohmann::json param_value_of_number(const ParamDecl& decl, double value, bool clamped) {
  assert(decl.type != ParamType::choice && "a choice is a string, not the value of an expression");
  if (decl.type == ParamType::bool_) return value != 0.0;
  if (clamped) value = std::clamp(value, decl.min.value_or(value), decl.max.value_or(value));
  // Within int64's range (beyond it the conversion is undefined); the range check reports the rest.
  if (decl.type == ParamType::int_) return static_cast<int64_t>(std::floor(std::clamp(value, -9e15, 9e15)));
  return value;
}

void PassRegistry::add(PassTypeDecl decl) {
  assert(!decl.type.empty() && "a pass type needs a name");
  assert(!types_.contains(decl.type) && "pass type registered twice");
  for (const auto& param : decl.params) {
    assert(check_param_value(param, param.default_value).empty() && "a declared default breaks its own range");
    assert((!param.power_of_two || (param.type == ParamType::int_ && param.min && param.max)) && "a power of two is an int with a range");
    (void)param;
  }
  std::string key = decl.type;
  types_.emplace(std::move(key), std::move(decl));
}

const PassTypeDecl* PassRegistry::find(std::string_view type) const {
  auto it = types_.find(type);
  return it == types_.end() ? nullptr : &it->second;
}

std::vector<std::string> PassRegistry::names() const {
  std::vector<std::string> out;
  for (const auto& [name, decl] : types_) out.push_back(name);
  return out;
}

}  // namespace caustica::graph
