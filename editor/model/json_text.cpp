#include "model/json_text.h"

#include <algorithm>
#include <cstring>
#include <numeric>
#include <vector>

namespace caustica::editor {
// Named rather than anonymous: PreservingWriter::Original, declared in the header, holds these.
namespace json_text_parts {

using nlohmann::ordered_json;

// Where each part of a JSON text lies: a value's bytes, its key's when it is an object's member
// (an array element's key is empty, at its value), and an object's or array's members.
struct TextNode {
  size_t begin = 0, end = 0;
  std::string key;
  size_t key_begin = 0, key_end = 0;
  size_t close = 0;  // containers: the closing bracket
  std::vector<TextNode> members;
};

// The text is known to be valid JSON (it parsed), so the scanner only finds boundaries.
class Scanner {
 public:
  // nlohmann and the engine's loader skip a UTF-8 byte order mark; it stays in the text before the value.
  explicit Scanner(std::string_view text) : t_(text), i_(text.starts_with("\xEF\xBB\xBF") ? 3 : 0) {}

  TextNode value() {
    skip_space();
    TextNode node;
    node.begin = i_;
    const char c = t_[i_];
    if (c == '{' || c == '[') {
      const char close = c == '{' ? '}' : ']';
      ++i_;
      skip_space();
      while (t_[i_] != close) {
        skip_space();
        const size_t key_begin = i_;
        std::string key;
        if (c == '{') {
          i_ = string_end(i_);
          key = ordered_json::parse(t_.substr(key_begin, i_ - key_begin)).get<std::string>();
        }
        const size_t key_end = i_;
        if (c == '{') {
          skip_space();
          ++i_;  // ':'
        }
        TextNode member = value();
        member.key = std::move(key);
        member.key_begin = key_begin;
        member.key_end = key_end;
        node.members.push_back(std::move(member));
        skip_space();
        if (t_[i_] == ',') ++i_;
        skip_space();
      }
      node.close = i_++;
    } else if (c == '"') {
      i_ = string_end(i_);
    } else {
      while (i_ < t_.size() && !std::strchr(",}] \t\r\n", t_[i_])) ++i_;
    }
    node.end = i_;
    return node;
  }

 private:
  void skip_space() {
    while (i_ < t_.size() && (t_[i_] == ' ' || t_[i_] == '\t' || t_[i_] == '\r' || t_[i_] == '\n')) ++i_;
  }
  size_t string_end(size_t quote) const {
    size_t k = quote + 1;
    while (k < t_.size() && t_[k] != '"') k += t_[k] == '\\' ? 2 : 1;
    return k + 1;
  }

  std::string_view t_;
  size_t i_;
};

class Writer {
 public:
  explicit Writer(std::string_view text) : t_(text) {
    // The indent unit is the first indented line's leading whitespace; two spaces if none.
    for (size_t i = text.find('\n'); i != std::string_view::npos && i + 1 < text.size(); i = text.find('\n', i + 1)) {
      size_t k = i + 1;
      while (k < text.size() && (text[k] == ' ' || text[k] == '\t')) ++k;
      if (k > i + 1) {
        indent_char_ = text[i + 1];
        indent_ = static_cast<int>(k - i - 1);
        break;
      }
    }
  }

  void emit(const ordered_json& value, const ordered_json* old, const TextNode* node, int depth, std::string& out) const {
    if (old && *old == value) {
      out.append(t_.substr(node->begin, node->end - node->begin));
      return;
    }
    const bool same_kind = old && ((old->is_object() && value.is_object()) || (old->is_array() && value.is_array()));
    if (same_kind && !node->members.empty() && !value.empty()) {
      patch(value, *old, *node, depth, out);
      return;
    }
    fresh(value, depth, out);
  }

 private:
  void fresh(const ordered_json& value, int depth, std::string& out) const {
    // A short array of numbers (a position) stays on one line.
    const bool numbers = value.is_array() && value.size() <= 4 &&
                         std::all_of(value.begin(), value.end(), [](const ordered_json& v) { return v.is_number(); });
    const std::string text = numbers ? value.dump() : value.dump(indent_, indent_char_);
    const std::string newline = "\n" + std::string(static_cast<size_t>(indent_ * depth), indent_char_);
    for (char c : text) {
      if (c == '\n')
        out += newline;
      else
        out += c;
    }
  }

  // Which old member each new member continues: the same key (objects) or an equal value (arrays,
  // in order) anchors a pair; between anchors, the rest pair up by position (a changed value, a
  // renamed key); a new member with no partner is written fresh, an old one with none is dropped.
  // An array that kept its length was edited in place: pairing by value there would pair an element
  // set to a later one's value with that one and rewrite those in between.
  static std::vector<int> match(const ordered_json& value, const ordered_json& old, const TextNode& node) {
    std::vector<int> partner(value.size(), -1);
    if (value.is_array() && value.size() == node.members.size()) {
      std::iota(partner.begin(), partner.end(), 0);
      return partner;
    }
    std::vector<bool> used(node.members.size(), false);
    size_t next_old = 0, j = 0;
    for (auto it = value.begin(); it != value.end(); ++it, ++j) {
      for (size_t k = next_old; k < node.members.size(); ++k) {
        const bool same = value.is_object() ? node.members[k].key == it.key() : old[k] == *it;
        if (same) {
          partner[j] = static_cast<int>(k);
          used[k] = true;
          next_old = k + 1;
          break;
        }
      }
    }
    // Fill the gaps between anchors by position.
    size_t old_cursor = 0;
    for (size_t a = 0; a < partner.size(); ++a) {
      if (partner[a] >= 0) {
        old_cursor = static_cast<size_t>(partner[a]) + 1;
        continue;
      }
      size_t limit = node.members.size();
      for (size_t b = a + 1; b < partner.size(); ++b) {
        if (partner[b] >= 0) {
          limit = static_cast<size_t>(partner[b]);
          break;
        }
      }
      while (old_cursor < limit && used[old_cursor]) ++old_cursor;
      if (old_cursor < limit) {
        partner[a] = static_cast<int>(old_cursor);
        used[old_cursor++] = true;
      }
    }
    return partner;
  }

  // The separator before old member k, for a new member that is first or not: a kept comma stays where
  // its author put it (a space may come before it); the front has none, and the old first member has
  // none of its own when it moves on.
  std::string lead(const TextNode& node, size_t k, bool first) const {
    const size_t from = k == 0 ? node.begin + 1 : node.members[k - 1].end;
    std::string text(t_.substr(from, node.members[k].key_begin - from));
    const size_t comma = text.find(',');
    if (first && comma != std::string::npos)
      text.erase(comma, 1);
    else if (!first && comma == std::string::npos)
      text.insert(0, ",");
    return text;
  }

  void patch(const ordered_json& value, const ordered_json& old, const TextNode& node, int depth, std::string& out) const {
    const bool object = value.is_object();
    const std::vector<int> partner = match(value, old, node);
    const TextNode& first = node.members.front();
    const std::string colon(object ? t_.substr(first.key_end, first.begin - first.key_end) : std::string_view());
    out += object ? '{' : '[';
    size_t j = 0;
    for (auto it = value.begin(); it != value.end(); ++it, ++j) {
      if (partner[j] < 0) {
        out += lead(node, node.members.size() - 1, j == 0);
        if (object) out += ordered_json(it.key()).dump() + colon;
        fresh(*it, depth + 1, out);
        continue;
      }
      const auto k = static_cast<size_t>(partner[j]);
      const TextNode& m = node.members[k];
      out += lead(node, k, j == 0);
      if (object) {
        out += m.key == it.key() ? std::string(t_.substr(m.key_begin, m.key_end - m.key_begin)) : ordered_json(it.key()).dump();
        out += t_.substr(m.key_end, m.begin - m.key_end);
      }
      emit(*it, object ? &old.at(m.key) : &old.at(k), &m, depth + 1, out);
    }
    const TextNode& last = node.members.back();
    out += t_.substr(last.end, node.close - last.end);
    out += object ? '}' : ']';
  }

  std::string_view t_;
  int indent_ = 2;
  char indent_char_ = ' ';
};

}  // namespace json_text_parts

using json_text_parts::ordered_json;

struct PreservingWriter::Original {
  explicit Original(std::string text_in)
      : text(std::move(text_in)),
        value(ordered_json::parse(text, nullptr, false)),
        root(value.is_discarded() ? json_text_parts::TextNode{} : json_text_parts::Scanner(text).value()),
        writer(text) {}
  std::string text;
  ordered_json value;
  json_text_parts::TextNode root;
  json_text_parts::Writer writer;
};

PreservingWriter::PreservingWriter(std::string original) : original_(std::make_shared<const Original>(std::move(original))) {}

const std::string& PreservingWriter::original() const {
  return original_->text;
}

std::string PreservingWriter::write(const ordered_json& value) const {
  const Original& o = *original_;
  if (o.value.is_discarded()) return value.dump(2) + "\n";
  std::string out = o.text.substr(0, o.root.begin);
  o.writer.emit(value, &o.value, &o.root, 0, out);
  out += o.text.substr(o.root.end);
  return out;
}

std::string write_preserving(const ordered_json& value, std::string_view original) {
  return PreservingWriter(std::string(original)).write(value);
}

}  // namespace caustica::editor
