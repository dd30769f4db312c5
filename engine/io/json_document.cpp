#include "io/json_document.h"

#include <sys/stat.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>

namespace caustica {

std::string json_pointer_append(std::string_view pointer, std::string_view token) {
  std::string out(pointer);
  out += '/';
  for (char c : token) {
    if (c == '~') out += "~0";
    else if (c == '/') out += "~1";
    else out += c;
  }
  return out;
}

std::string read_text_file(const std::string& path, size_t max_bytes) {
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) {
    throw InputError(path + ": cannot open: " + std::strerror(errno));
  }
  if (S_ISDIR(info.st_mode)) throw InputError(path + ": is a directory, not a file");
  // A FIFO would block the open and a device such as /dev/zero never ends: only plain files are read.
  if (!S_ISREG(info.st_mode)) throw InputError(path + ": is not a regular file");
  if (static_cast<size_t>(info.st_size) > max_bytes) {
    throw InputError(path + ": file is " + std::to_string(info.st_size) + " bytes, more than the limit of " +
                     std::to_string(max_bytes));
  }
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!file) throw InputError(path + ": cannot open: " + std::strerror(errno));
  // Read to the end rather than trusting st_size: files under /proc report 0 and still hold text.
  std::string text;
  char chunk[65536];
  while (size_t n = std::fread(chunk, 1, sizeof chunk, file.get())) {
    text.append(chunk, n);
    if (text.size() > max_bytes) throw InputError(path + ": file is more than the limit of " + std::to_string(max_bytes) + " bytes");
  }
  if (std::ferror(file.get())) throw InputError(path + ": cannot read: " + std::strerror(errno));
  return text;
}

class JsonParser {
 public:
  JsonParser(std::string_view text, JsonDocument& doc) : text_(text), doc_(doc) {}

  void run() {
    skip_bom();
    skip_space();
    if (at_end()) fail("empty document: expected a JSON value");
    doc_.root_ = value("", 0);
    skip_space();
    if (!at_end()) fail("unexpected text after the JSON value");
  }

 private:
  std::string_view text_;
  JsonDocument& doc_;
  size_t pos_ = 0;
  int line_ = 1;
  size_t line_start_ = 0;

  bool at_end() const { return pos_ >= text_.size(); }
  char peek() const { return at_end() ? '\0' : text_[pos_]; }
  SourceLocation here() const { return {line_, static_cast<int>(pos_ - line_start_) + 1}; }

  [[noreturn]] void fail(const std::string& message) const {
    throw InputError(format_location(doc_.path_, here()) + ": invalid JSON: " + message);
  }

  void advance() {
    if (text_[pos_] == '\n') {
      ++line_;
      line_start_ = pos_ + 1;
    }
    ++pos_;
  }

  void skip_bom() {
    if (text_.substr(0, 3) == "\xEF\xBB\xBF") pos_ = line_start_ = 3;
  }

  void skip_space() {
    while (!at_end()) {
      char c = peek();
      if (c == ' ' || c == '\t' || c == '\n' || c == '\r') advance();
      else break;
    }
  }

  void expect(char c, const char* what) {
    if (peek() != c) fail(std::string("expected ") + what + describe_found());
    advance();
  }

  std::string describe_found() const {
    if (at_end()) return ", found the end of the file";
    char c = peek();
    if (static_cast<unsigned char>(c) < 0x20) return ", found a control character";
    return std::string(", found '") + c + "'";
  }

  nlohmann::json value(const std::string& pointer, int depth) {
    if (depth > JsonDocument::kMaxDepth) {
      fail("nesting deeper than " + std::to_string(JsonDocument::kMaxDepth) + " levels");
    }
    doc_.locations_[pointer] = here();
    switch (peek()) {
      case '{': return object(pointer, depth);
      case '[': return array(pointer, depth);
      case '"': return nlohmann::json(string());
      case 't': literal("true"); return true;
      case 'f': literal("false"); return false;
      case 'n': literal("null"); return nullptr;
      default:
        if (peek() == '-' || (peek() >= '0' && peek() <= '9')) return number();
        if (at_end()) fail("expected a value, found the end of the file");
        if (text_.substr(pos_, 3) == "NaN" || text_.substr(pos_, 8) == "Infinity") {
          fail("NaN and Infinity are not JSON numbers");
        }
        fail(std::string("expected a value") + describe_found());
    }
  }

  void literal(std::string_view word) {
    if (text_.substr(pos_, word.size()) != word) fail("expected a value" + describe_found());
    for (size_t i = 0; i < word.size(); ++i) advance();
  }

  nlohmann::json object(const std::string& pointer, int depth) {
    advance();  // '{'
    nlohmann::json out = nlohmann::json::object();
    skip_space();
    if (peek() == '}') {
      advance();
      return out;
    }
    while (true) {
      skip_space();
      if (peek() != '"') fail("expected a quoted member name" + describe_found());
      SourceLocation key_at = here();
      std::string key = string();
      if (out.contains(key)) {
        throw InputError(format_location(doc_.path_, key_at) + ": duplicate member name \"" + key +
                         "\" (at " + json_pointer_append(pointer, key) + ")");
      }
      skip_space();
      expect(':', "':' after a member name");
      skip_space();
      std::string child = json_pointer_append(pointer, key);
      out[key] = value(child, depth + 1);
      skip_space();
      if (peek() == ',') {
        advance();
        continue;
      }
      if (peek() == '}') {
        advance();
        return out;
      }
      fail("expected ',' or '}' in an object" + describe_found());
    }
  }

  nlohmann::json array(const std::string& pointer, int depth) {
    advance();  // '['
    nlohmann::json out = nlohmann::json::array();
    skip_space();
    if (peek() == ']') {
      advance();
      return out;
    }
    while (true) {
      skip_space();
      out.push_back(value(json_pointer_append(pointer, std::to_string(out.size())), depth + 1));
      skip_space();
      if (peek() == ',') {
        advance();
        continue;
      }
      if (peek() == ']') {
        advance();
        return out;
      }
      fail("expected ',' or ']' in an array" + describe_found());
    }
  }

  unsigned hex4() {
    unsigned code = 0;
    for (int i = 0; i < 4; ++i) {
      char c = peek();
      unsigned digit;
      if (c >= '0' && c <= '9') digit = static_cast<unsigned>(c - '0');
      else if (c >= 'a' && c <= 'f') digit = static_cast<unsigned>(c - 'a' + 10);
      else if (c >= 'A' && c <= 'F') digit = static_cast<unsigned>(c - 'A' + 10);
      else fail("bad \\u escape: expected four hex digits");
      code = code * 16 + digit;
      advance();
    }
    return code;
  }

  static void append_utf8(std::string& out, unsigned code) {
    if (code < 0x80) {
      out += static_cast<char>(code);
    } else if (code < 0x800) {
      out += static_cast<char>(0xC0 | (code >> 6));
      out += static_cast<char>(0x80 | (code & 0x3F));
    } else if (code < 0x10000) {
      out += static_cast<char>(0xE0 | (code >> 12));
      out += static_cast<char>(0x80 | ((code >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (code & 0x3F));
    } else {
      out += static_cast<char>(0xF0 | (code >> 18));
      out += static_cast<char>(0x80 | ((code >> 12) & 0x3F));
      out += static_cast<char>(0x80 | ((code >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (code & 0x3F));
    }
  }

  // Bytes in the well-formed UTF-8 sequence at the start of `s` (RFC 3629: no overlong forms, no
  // surrogates, nothing above U+10FFFF), or 0.
  static size_t utf8_length(std::string_view s) {
    const auto byte = [&](size_t i) { return i < s.size() ? static_cast<unsigned char>(s[i]) : 0u; };
    const unsigned lead = byte(0);
    size_t n;
    unsigned code;
    if (lead >= 0xC2 && lead <= 0xDF) n = 2, code = lead & 0x1Fu;
    else if (lead >= 0xE0 && lead <= 0xEF) n = 3, code = lead & 0x0Fu;
    else if (lead >= 0xF0 && lead <= 0xF4) n = 4, code = lead & 0x07u;
    else return 0;
    for (size_t i = 1; i < n; ++i) {
      if ((byte(i) & 0xC0u) != 0x80u) return 0;
      code = (code << 6) | (byte(i) & 0x3Fu);
    }
    if ((n == 3 && code < 0x800) || (n == 4 && (code < 0x10000 || code > 0x10FFFF)) || (code >= 0xD800 && code <= 0xDFFF)) return 0;
    return n;
  }

  std::string string() {
    advance();  // '"'
    std::string out;
    while (true) {
      if (at_end()) fail("unterminated string");
      char c = peek();
      if (c == '"') {
        advance();
        break;
      }
      if (static_cast<unsigned char>(c) < 0x20) fail("control character inside a string");
      if (static_cast<unsigned char>(c) >= 0x80) {
        // JSON text is UTF-8; anything else would surface later as an exception far from its cause.
        const size_t n = utf8_length(text_.substr(pos_));
        if (n == 0) fail("invalid UTF-8 inside a string");
        for (size_t i = 0; i < n; ++i) {
          out += peek();
          advance();
        }
        continue;
      }
      if (c != '\\') {
        out += c;
        advance();
        continue;
      }
      advance();
      char e = peek();
      if (at_end()) fail("unterminated string");
      advance();
      switch (e) {
        case '"': out += '"'; break;
        case '\\': out += '\\'; break;
        case '/': out += '/'; break;
        case 'b': out += '\b'; break;
        case 'f': out += '\f'; break;
        case 'n': out += '\n'; break;
        case 'r': out += '\r'; break;
        case 't': out += '\t'; break;
        case 'u': {
          unsigned code = hex4();
          if (code >= 0xD800 && code <= 0xDBFF) {
            if (text_.substr(pos_, 2) != "\\u") fail("lone high surrogate in \\u escape");
            advance();
            advance();
            unsigned low = hex4();
            if (low < 0xDC00 || low > 0xDFFF) fail("bad low surrogate in \\u escape");
            code = 0x10000 + ((code - 0xD800) << 10) + (low - 0xDC00);
          } else if (code >= 0xDC00 && code <= 0xDFFF) {
            fail("lone low surrogate in \\u escape");
          }
          append_utf8(out, code);
          break;
        }
        default: fail(std::string("unknown escape '\\") + e + "'");
      }
    }
    return out;
  }

  nlohmann::json number() {
    size_t start = pos_;
    bool integral = true;
    if (peek() == '-') advance();
    if (peek() == '0') {
      advance();
    } else if (peek() >= '1' && peek() <= '9') {
      while (peek() >= '0' && peek() <= '9') advance();
    } else {
      fail("expected a digit");
    }
    if (peek() == '.') {
      integral = false;
      advance();
      if (!(peek() >= '0' && peek() <= '9')) fail("expected a digit after '.'");
      while (peek() >= '0' && peek() <= '9') advance();
    }
    if (peek() == 'e' || peek() == 'E') {
      integral = false;
      advance();
      if (peek() == '+' || peek() == '-') advance();
      if (!(peek() >= '0' && peek() <= '9')) fail("expected a digit in the exponent");
      while (peek() >= '0' && peek() <= '9') advance();
    }
    std::string literal_text(text_.substr(start, pos_ - start));
    if (integral) {
      errno = 0;
      char* end = nullptr;
      long long v = std::strtoll(literal_text.c_str(), &end, 10);
      if (errno == 0) return v;
    }
    double v = std::strtod(literal_text.c_str(), nullptr);
    if (!std::isfinite(v)) fail("number " + literal_text + " is out of range");
    return v;
  }
};

JsonDocument JsonDocument::parse(std::string_view text, std::string path) {
  JsonDocument doc;
  doc.path_ = std::move(path);
  if (text.size() > kMaxBytes) {
    throw InputError(doc.path_ + ": document is larger than " + std::to_string(kMaxBytes) + " bytes");
  }
  JsonParser(text, doc).run();
  return doc;
}

JsonDocument JsonDocument::load(const std::string& path) {
  return parse(read_text_file(path, kMaxBytes), path);
}

SourceLocation JsonDocument::locate(std::string_view pointer) const {
  std::string key(pointer);
  while (true) {
    auto it = locations_.find(key);
    if (it != locations_.end()) return it->second;
    size_t slash = key.rfind('/');
    if (slash == std::string::npos) return {};
    key.resize(slash);
  }
}

LocatedError JsonDocument::error(std::string_view pointer, const std::string& message) const {
  std::string where = pointer.empty() ? std::string("/") : std::string(pointer);
  const SourceLocation location = locate(pointer);
  return LocatedError(format_location(path_, location) + ": " + message + " (at " + where + ")", location);
}

}  // namespace caustica
