#include "graph/expression.h"

#include <cctype>
#include <cmath>
#include <stdexcept>

#include "core/suggest.h"

namespace caustica::graph {

bool is_name_start(char c) {
  return std::isalpha(static_cast<unsigned char>(c)) || c == '_';
}
bool is_name_char(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.';
}

namespace {

class Evaluator {
 public:
  Evaluator(std::string_view text, const ExpressionScope& scope) : text_(text), scope_(scope) {}

  double run() {
    if (text_.size() > 1024) fail("expression longer than 1024 characters");
    double v = sum();
    skip();
    if (pos_ < text_.size()) fail("unexpected '" + std::string(1, text_[pos_]) + "'");
    return v;
  }

 private:
  std::string_view text_;
  const ExpressionScope& scope_;
  size_t pos_ = 0;
  int depth_ = 0;

  [[noreturn]] void fail(const std::string& what) const {
    throw std::invalid_argument("in expression \"" + std::string(text_) + "\" at character " + std::to_string(pos_ + 1) + ": " + what);
  }

  void skip() {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
  }
  bool accept(char c) {
    skip();
    if (pos_ < text_.size() && text_[pos_] == c) {
      ++pos_;
      return true;
    }
    return false;
  }

  double sum() {
    double v = product();
    while (true) {
      if (accept('+'))
        v += product();
      else if (accept('-'))
        v -= product();
      else
        return v;
    }
  }

  double product() {
    double v = unary();
    while (true) {
      if (accept('*')) {
        v *= unary();
      } else if (accept('/')) {
        double d = unary();
        if (d == 0) fail("division by zero");
        v /= d;
      } else if (accept('%')) {
        double d = unary();
        if (d == 0) fail("remainder by zero");
        v = std::fmod(v, d);
      } else {
        return v;
      }
    }
  }

  double unary() {
    if (accept('-')) return -unary();
    if (accept('+')) return unary();
    return primary();
  }

  double primary() {
    skip();
    if (pos_ >= text_.size()) fail("expected a number or a name, found the end");
    if (++depth_ > 64) fail("nested too deeply");
    double v = primary_inner();
    --depth_;
    return v;
  }

  double primary_inner() {
    char c = text_[pos_];
    if (c == '(') {
      ++pos_;
      double v = sum();
      if (!accept(')')) fail("expected ')'");
      return v;
    }
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') {
      size_t start = pos_;
      while (pos_ < text_.size() && (std::isdigit(static_cast<unsigned char>(text_[pos_])) || text_[pos_] == '.')) ++pos_;
      if (pos_ < text_.size() && (text_[pos_] == 'e' || text_[pos_] == 'E')) {
        ++pos_;
        if (pos_ < text_.size() && (text_[pos_] == '+' || text_[pos_] == '-')) ++pos_;
        while (pos_ < text_.size() && std::isdigit(static_cast<unsigned char>(text_[pos_]))) ++pos_;
      }
      std::string literal(text_.substr(start, pos_ - start));
      char* end = nullptr;
      double v = std::strtod(literal.c_str(), &end);
      if (end != literal.c_str() + literal.size()) fail("bad number '" + literal + "'");
      return v;
    }
    if (is_name_start(c)) {
      size_t start = pos_;
      while (pos_ < text_.size() && is_name_char(text_[pos_])) ++pos_;
      std::string name(text_.substr(start, pos_ - start));
      if (accept('(')) return call(name);
      std::optional<double> value = scope_.lookup(name);
      if (!value) fail("unknown name '" + name + "'" + did_you_mean(name, scope_.known_names));
      return *value;
    }
    fail("unexpected '" + std::string(1, c) + "'");
  }

  double call(const std::string& function) {
    std::vector<double> args;
    if (!accept(')')) {
      do {
        args.push_back(sum());
      } while (accept(','));
      if (!accept(')')) fail("expected ')' after the arguments of " + function);
    }
    auto arity = [&](size_t n) {
      if (args.size() != n) {
        fail(function + " takes " + std::to_string(n) + " argument" + (n == 1 ? "" : "s") + ", not " + std::to_string(args.size()));
      }
    };
    if (function == "min") {
      arity(2);
      return std::min(args[0], args[1]);
    }
    if (function == "max") {
      arity(2);
      return std::max(args[0], args[1]);
    }
    if (function == "floor") {
      arity(1);
      return std::floor(args[0]);
    }
    if (function == "ceil") {
      arity(1);
      return std::ceil(args[0]);
    }
    if (function == "round") {
      arity(1);
      return std::round(args[0]);
    }
    if (function == "log2") {
      arity(1);
      return std::log2(args[0]);
    }
    if (function == "pow") {
      arity(2);
      return std::pow(args[0], args[1]);
    }
    fail("unknown function '" + function + "'" + did_you_mean(function, {"min", "max", "floor", "ceil", "round", "log2", "pow"}));
  }
};

}  // namespace

double evaluate_expression(std::string_view text, const ExpressionScope& scope) {
  Evaluator evaluator(text, scope);
  double v = evaluator.run();
  if (!std::isfinite(v)) throw std::invalid_argument("expression \"" + std::string(text) + "\" is not finite");
  return v;
}

}  // namespace caustica::graph
