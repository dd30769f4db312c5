#pragma once
// Where a value lies in a JSON text, found by the tests' own scanner. The editor's json_text finds
// spans too, but a test that asked it where an edit may write would only check it against itself.
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace json_span {

// Bytes [begin, end) of a text.
struct Span {
  size_t begin = 0, end = 0;
  size_t size() const { return end - begin; }
  bool operator==(const Span&) const = default;
};

// The value at a JSON pointer and what surrounds it in its container. For the whole document the
// gaps are the text before and after the value.
struct Located {
  Span value;
  Span key;         // an object member's key, quotes included; empty at value.begin otherwise
  Span member;      // from the key (or an element's value) to the end of the value
  Span gap_before;  // from the previous sibling's end, or just inside the opening bracket, to member.begin
  Span gap_after;   // from value.end to the next sibling's member.begin, or to the closing bracket
};

// RFC 6901: "/a~1b/0" is {"a/b", "0"}; "" is the whole document.
inline std::vector<std::string> pointer_tokens(std::string_view pointer) {
  if (pointer.empty()) return {};
  if (pointer.front() != '/') throw std::invalid_argument("a JSON pointer starts with '/': " + std::string(pointer));
  std::vector<std::string> tokens(1);
  for (size_t i = 1; i < pointer.size(); ++i) {
    if (pointer[i] == '/') {
      tokens.emplace_back();
    } else if (pointer[i] == '~' && i + 1 < pointer.size() && (pointer[i + 1] == '0' || pointer[i + 1] == '1')) {
      tokens.back() += pointer[++i] == '0' ? '~' : '/';
    } else {
      tokens.back() += pointer[i];
    }
  }
  return tokens;
}

inline std::string append_token(std::string pointer, std::string_view token) {
  pointer += '/';
  for (char c : token) pointer += c == '~' ? "~0" : c == '/' ? "~1" : std::string(1, c);
  return pointer;
}

namespace detail {

// A recursive-descent pass over the whole text that records the member on the pointer's path.
class Scanner {
 public:
  Scanner(std::string_view text, std::vector<std::string> path) : text_(text), path_(std::move(path)) {}

  Located run() {
    if (text_.substr(0, 3) == "\xEF\xBB\xBF") pos_ = 3;  // a UTF-8 byte order mark, which the engine's parser skips too
    skip_space();
    const size_t begin = pos_;
    const Span value = scan_value(0, true);
    if (path_.empty()) found_ = Located{value, {begin, begin}, value, {0, begin}, {value.end, text_.size()}};
    skip_space();
    if (pos_ != text_.size()) fail("the end of the text");
    if (!found_) throw std::out_of_range("no value at the pointer");
    return *found_;
  }

 private:
  // `depth` tokens of the path lead to this value when `on_path`.
  Span scan_value(size_t depth, bool on_path) {
    skip_space();
    const size_t begin = pos_;
    if (peek() == '{' || peek() == '[') {
      scan_container(depth, on_path);
    } else if (peek() == '"') {
      scan_string();
    } else {
      scan_scalar();
    }
    return {begin, pos_};
  }

  void scan_container(size_t depth, bool on_path) {
    const bool object = peek() == '{';
    const char close = object ? '}' : ']';
    size_t previous_end = ++pos_;
    skip_space();
    if (peek() == close) {
      ++pos_;
      return;
    }
    for (size_t index = 0;; ++index) {
      const size_t member_begin = pos_;
      Span key{member_begin, member_begin};
      std::string name = std::to_string(index);
      if (object) {
        name = scan_string();
        key.end = pos_;
        skip_space();
        expect(':');
      }
      const bool leads_to_target = on_path && depth < path_.size() && path_[depth] == name;
      const Span value = scan_value(depth + 1, leads_to_target);
      skip_space();
      const bool more = peek() == ',';
      if (more) {
        ++pos_;
        skip_space();
        if (peek() == close) fail("a member after the comma");
      }
      if (leads_to_target && depth + 1 == path_.size())
        found_ = Located{value, key, {member_begin, value.end}, {previous_end, member_begin}, {value.end, pos_}};
      previous_end = value.end;
      if (!more) break;
    }
    expect(close);
  }

  // The string's value, escapes decoded, so that keys compare with the pointer's tokens.
  std::string scan_string() {
    expect('"');
    std::string out;
    while (true) {
      if (pos_ >= text_.size()) fail("an unterminated string");
      const char c = text_[pos_++];
      if (c == '"') return out;
      if (static_cast<unsigned char>(c) < 0x20) fail("a control character in a string");
      if (c != '\\') {
        out += c;
        continue;
      }
      const char escape = peek();
      ++pos_;
      switch (escape) {
        case '"':
        case '\\':
        case '/': out += escape; break;
        case 'b': out += '\b'; break;
        case 'f': out += '\f'; break;
        case 'n': out += '\n'; break;
        case 'r': out += '\r'; break;
        case 't': out += '\t'; break;
        case 'u': append_utf8(code_point(), out); break;
        default: fail("an unknown escape");
      }
    }
  }

  // After "\u": four hex digits, and a second "\uXXXX" when they are a high surrogate.
  uint32_t code_point() {
    const uint32_t unit = hex4();
    if (unit < 0xD800 || unit > 0xDBFF || text_.substr(pos_, 2) != "\\u") return unit;
    pos_ += 2;
    return 0x10000 + ((unit - 0xD800) << 10) + (hex4() - 0xDC00);
  }

  uint32_t hex4() {
    uint32_t value = 0;
    for (int i = 0; i < 4; ++i, ++pos_) {
      const char c = peek();
      const int digit = is_digit(c) ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10 : c >= 'A' && c <= 'F' ? c - 'A' + 10 : -1;
      if (digit < 0) fail("four hex digits after \\u");
      value = value * 16 + static_cast<uint32_t>(digit);
    }
    return value;
  }

  static void append_utf8(uint32_t cp, std::string& out) {
    auto byte = [&](uint32_t b) { out += static_cast<char>(b); };
    if (cp < 0x80) {
      byte(cp);
    } else if (cp < 0x800) {
      byte(0xC0 | cp >> 6);
      byte(0x80 | (cp & 0x3F));
    } else if (cp < 0x10000) {
      byte(0xE0 | cp >> 12);
      byte(0x80 | (cp >> 6 & 0x3F));
      byte(0x80 | (cp & 0x3F));
    } else {
      byte(0xF0 | cp >> 18);
      byte(0x80 | (cp >> 12 & 0x3F));
      byte(0x80 | (cp >> 6 & 0x3F));
      byte(0x80 | (cp & 0x3F));
    }
  }

  void scan_scalar() {
    for (const std::string_view literal : {"true", "false", "null"}) {
      if (text_.substr(pos_, literal.size()) == literal) {
        pos_ += literal.size();
        return;
      }
    }
    const size_t begin = pos_;
    if (peek() == '-') ++pos_;
    if (!is_digit(peek())) fail("a value");
    while (is_digit(peek()) || peek() == '.' || peek() == 'e' || peek() == 'E' || peek() == '+' || peek() == '-') ++pos_;
    if (pos_ == begin) fail("a number");
  }

  static bool is_digit(char c) { return c >= '0' && c <= '9'; }
  char peek() const { return pos_ < text_.size() ? text_[pos_] : '\0'; }
  void skip_space() {
    while (peek() == ' ' || peek() == '\t' || peek() == '\n' || peek() == '\r') ++pos_;
  }
  void expect(char c) {
    if (peek() != c) fail(std::string("'") + c + "'");
    ++pos_;
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw std::invalid_argument("not JSON at byte " + std::to_string(pos_) + ": expected " + what);
  }

  std::string_view text_;
  std::vector<std::string> path_;
  size_t pos_ = 0;
  std::optional<Located> found_;
};

}  // namespace detail

// Throws std::out_of_range when nothing is at `pointer`, std::invalid_argument when `text` is not JSON.
inline Located locate(std::string_view text, std::string_view pointer) {
  return detail::Scanner(text, pointer_tokens(pointer)).run();
}

}  // namespace json_span
