// The editor's graph model on the CPU: every operation and its undo on every bundled graph, text
// that keeps the author's bytes (checked against spans found by the tests' own scanner, json_span.h,
// not by the code under test), saves, malformed files, and a script of operations that rebuilds one
// bundled graph from another.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "builtin_passes.h"
#include "graph/compiler.h"
#include "io/json_document.h"
#include "json_span.h"
#include "model/canvas_layout.h"
#include "model/graph_model.h"
#include "model/json_text.h"

using namespace caustica;
using editor::GraphModel;
using nlohmann::ordered_json;

namespace {

const graph::PassRegistry& registry() {
  return passes::builtin_registry();
}

std::filesystem::path graphs_dir() {
  return std::filesystem::path(CAUSTICA_SOURCE_DIR) / "graphs";
}

std::vector<std::filesystem::path> bundled_graphs() {
  std::vector<std::filesystem::path> out;
  for (const auto& e : std::filesystem::directory_iterator(graphs_dir())) {
    if (e.path().extension() == ".json" && e.path().filename() != "schema.json") out.push_back(e.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::string file_text(const std::filesystem::path& path) {
  return read_text_file(path.string(), 1 << 24);
}

std::string plan_of(const graph::GraphDesc& desc) {
  graph::CompileOptions options;
  options.scene_values = graph::typical_scene_values();
  nlohmann::json plan = graph::plan_to_json(graph::compile_graph(desc, registry(), options));
  plan.erase("file");
  return plan.dump(1);
}

// A value of the parameter other than `current`, within its declared range.
nlohmann::json other_value(const graph::ParamDecl& d, const nlohmann::json& current) {
  switch (d.type) {
    case graph::ParamType::bool_: return !current.get<bool>();
    case graph::ParamType::choice:
      for (const auto& c : d.choices) {
        if (c != current) return c;
      }
      return current;
    case graph::ParamType::int_: {
      const double v = current.get<double>();
      return static_cast<int64_t>(v + 1 <= d.max.value_or(1e9) ? v + 1 : v - 1);
    }
    case graph::ParamType::float_: {
      const double v = current.get<double>();
      return v + 0.5 <= d.max.value_or(1e9) ? v + 0.5 : v - 0.5;
    }
  }
  return current;
}

// ---- which bytes an edit may rewrite, located by the tests' own scanner (json_span.h) ----

std::string child(const std::string& pointer, const std::string& token) {
  return json_span::append_token(pointer, token);
}

// Up to 60 bytes of `text` around `at`, quoted, for failure messages.
std::string around(std::string_view text, size_t at) {
  const size_t from = at < 30 ? 0 : at - 30;
  return ordered_json(std::string(text.substr(std::min(from, text.size()), 60)))
      .dump(-1, ' ', false, ordered_json::error_handler_t::replace);
}

// Whether two texts are the same bytes; else where they first differ.
testing::AssertionResult same_bytes(std::string_view expected, std::string_view actual) {
  if (expected == actual) return testing::AssertionSuccess();
  const size_t n = std::min(expected.size(), actual.size());
  const auto at = static_cast<size_t>(std::mismatch(expected.begin(), expected.begin() + static_cast<long>(n), actual.begin()).first -
                                      expected.begin());
  return testing::AssertionFailure() << "the texts differ from byte " << at << "\n  expected: " << around(expected, at)
                                     << "\n  actual:   " << around(actual, at);
}

// What an edit did to a JSON text: the regions of the text before it that it rewrote and where each
// rewrite lies in the text after it. check() holds when every byte outside the regions is the
// original's, in order, and every rewrite reads back as what the edit put there.
class Rewrites {
 public:
  Rewrites(std::string_view before, std::string_view after) : before_(before), after_(after) {}

  // A replaced value: its text, and nothing around it, is rewritten, and reads back as `value`.
  void replaced(const std::string& before_pointer, const std::string& after_pointer, const ordered_json& value) {
    const std::string what = "replace " + before_pointer;
    const json_span::Span to = find(after_, after_pointer, what).value;
    add(what, find(before_, before_pointer, what).value, to);
    reads_back(to, value, what);
  }

  // A key changed in place: only the key's text is rewritten (a change to its value is another rewrite).
  void renamed(const std::string& before_pointer, const std::string& after_pointer) {
    const std::string what = "rename " + before_pointer + " to " + after_pointer;
    const json_span::Span to = find(after_, after_pointer, what).key;
    add(what, find(before_, before_pointer, what).key, to);
    reads_back(to, json_span::pointer_tokens(after_pointer).back(), what);
  }

  // Consecutive members removed (pointers before the edit), between the members `previous` and
  // `next` that stay (pointers after it; one may be absent). From the end of the member before them
  // to the start of the one after, one of the separators around them is left: a comma between two
  // members, else none, and the spacing before or after the removed members.
  void removed(const std::vector<std::string>& run, const std::optional<std::string>& previous, const std::optional<std::string>& next) {
    const std::string what = "remove " + run.front() + (run.size() > 1 ? ".." + run.back() : "");
    const json_span::Span gap_before = find(before_, run.front(), what).gap_before, gap_after = find(before_, run.back(), what).gap_after;
    const json_span::Span to = previous ? find(after_, *previous, what).gap_after : find(after_, *next, what).gap_before;
    add(what, {gap_before.begin, gap_after.end}, to);
    auto spacing = [](std::string_view separator) {
      std::string out(separator);
      out.erase(std::remove(out.begin(), out.end(), ','), out.end());
      return out;
    };
    const std::string_view left = after_.substr(to.begin, to.size());
    const bool one_of_the_separators = spacing(left) == spacing(before_.substr(gap_before.begin, gap_before.size())) ||
                                       spacing(left) == spacing(before_.substr(gap_after.begin, gap_after.size()));
    if (!one_of_the_separators || std::count(left.begin(), left.end(), ',') != (previous && next ? 1 : 0))
      problems_.push_back(what + ": where the members were, " + ordered_json(std::string(left)).dump() +
                          " is not one of the separators around them");
  }

  // Consecutive members added (pointers after the edit; `members` holds them as an object or array)
  // after the member `previous` that was there before (a pointer before the edit), or else before the
  // member `next` (pointers before and after the edit). The text written is a comma and the members
  // after `previous`'s value, or the members and a comma in front of `next`, in the container's spacing.
  void added(const std::vector<std::string>& run, const ordered_json& members, const std::optional<std::string>& previous,
             const std::optional<std::pair<std::string, std::string>>& next) {
    const std::string what = "add " + run.front() + (run.size() > 1 ? ".." + run.back() : "");
    const size_t begin = find(after_, run.front(), what).gap_before.begin;
    if (previous) {
      const size_t at = find(before_, *previous, what).value.end;
      add(what, {at, at}, {begin, find(after_, run.back(), what).value.end});
    } else {
      add(what, find(before_, next->first, what).gap_before, {begin, find(after_, next->second, what).gap_before.end});
    }
    std::string_view text = after_.substr(begin, rewrites_.back().after.end - begin);
    auto trim = [&] {
      while (!text.empty() && std::strchr(" \t\r\n", text.front())) text.remove_prefix(1);
      while (!text.empty() && std::strchr(" \t\r\n", text.back())) text.remove_suffix(1);
    };
    trim();
    if (!text.empty() && text.front() == ',' && previous) text.remove_prefix(1);
    if (!text.empty() && text.back() == ',' && !previous) text.remove_suffix(1);
    trim();
    const std::string wrapped = (members.is_object() ? "{" : "[") + std::string(text) + (members.is_object() ? "}" : "]");
    const ordered_json read = ordered_json::parse(wrapped, nullptr, false);
    if (read.is_discarded() || read != members)
      problems_.push_back(what + ": the text written, " + ordered_json(wrapped).dump() + ", does not read back as " + members.dump());
  }

  // Every change from `before` to `after` in the narrowest of the forms above. A container whose
  // members changed in none of them (members both added and removed, reordered) counts as replaced.
  void compare(const ordered_json& before, const ordered_json& after) {
    whole_ = after;
    compare(before, after, "", "");
  }

  // "replace /passes/1/params/radius", in the order found.
  std::vector<std::string> changes() const {
    std::vector<std::string> out;
    for (const auto& r : rewrites_) out.push_back(r.what);
    return out;
  }

  testing::AssertionResult check() const {
    if (!problems_.empty()) {
      testing::AssertionResult failure = testing::AssertionFailure();
      for (const auto& p : problems_) failure << p << "\n";
      return failure;
    }
    std::vector<Rewrite> in_order = rewrites_;
    std::stable_sort(in_order.begin(), in_order.end(), [](const Rewrite& x, const Rewrite& y) { return x.before.begin < y.before.begin; });
    size_t b = 0, a = 0;
    for (const auto& r : in_order) {
      if (r.before.begin < b || r.after.begin < a) return testing::AssertionFailure() << "rewrites overlap at " << r.what;
      if (auto difference = unchanged(b, r.before.begin, a, r.after.begin, "before " + r.what); !difference) return difference;
      b = r.before.end;
      a = r.after.end;
    }
    if (auto difference = unchanged(b, before_.size(), a, after_.size(), "at the end"); !difference) return difference;
    if (whole_ && ordered_json::parse(after_, nullptr, false) != *whole_)
      return testing::AssertionFailure() << "the text does not read back as the value";
    return testing::AssertionSuccess();
  }

 private:
  struct Rewrite {
    std::string what;
    json_span::Span before, after;
  };

  void add(const std::string& what, json_span::Span before, json_span::Span after) { rewrites_.push_back({what, before, after}); }

  json_span::Located find(std::string_view text, const std::string& pointer, const std::string& what) {
    try {
      return json_span::locate(text, pointer);
    } catch (const std::exception& e) {
      problems_.push_back(what + ": " + pointer + " not found in the text " + (text.data() == before_.data() ? "before" : "after") +
                          " the edit: " + e.what());
      return {};
    }
  }

  void reads_back(json_span::Span span, const ordered_json& value, const std::string& what) {
    const std::string_view text = after_.substr(span.begin, span.size());
    const ordered_json read = ordered_json::parse(text, nullptr, false);
    if (read.is_discarded() || read != value)
      problems_.push_back(what + ": the text written, " + ordered_json(std::string(text)).dump() + ", does not read back as " +
                          value.dump());
  }

  // The bytes between rewrites: the same in both texts, or where they first differ.
  testing::AssertionResult unchanged(size_t b, size_t b_end, size_t a, size_t a_end, const std::string& where) const {
    const std::string_view kept = before_.substr(b, b_end - b), written = after_.substr(a, a_end - a);
    if (kept == written) return testing::AssertionSuccess();
    const size_t n = std::min(kept.size(), written.size());
    const size_t at =
        static_cast<size_t>(std::mismatch(kept.begin(), kept.begin() + static_cast<long>(n), written.begin()).first - kept.begin());
    return testing::AssertionFailure() << "a byte outside the rewritten regions changed (" << where << ", byte " << b + at
                                       << " of the original)\n  original: " << around(before_, b + at)
                                       << "\n  written:  " << around(after_, a + at)
                                       << "\n  rewrites: " << testing::PrintToString(changes());
  }

  void compare(const ordered_json& before, const ordered_json& after, const std::string& bp, const std::string& ap) {
    if (before == after) return;
    const bool same_kind = (before.is_object() && after.is_object()) || (before.is_array() && after.is_array());
    if (same_kind && !before.empty() && !after.empty() && compare_members(before, after, bp, ap)) return;
    replaced(bp, ap, after);
  }

  struct Members {
    std::vector<std::string> tokens;  // keys, or indices
    std::vector<const ordered_json*> values;
    size_t size() const { return tokens.size(); }
  };
  static Members members_of(const ordered_json& container) {
    Members m;
    for (const auto& [key, value] : container.items()) {
      m.tokens.push_back(key);
      m.values.push_back(&value);
    }
    return m;
  }

  // Pairs each member after the edit with the one before it continues (an object's by key, or in place
  // where keys were renamed; an array's in place, or in order by value when elements were removed or
  // added); false when the change is not removals alone, additions alone or renames.
  bool compare_members(const ordered_json& before, const ordered_json& after, const std::string& bp, const std::string& ap) {
    const bool object = before.is_object();
    const Members b = members_of(before), a = members_of(after);
    std::vector<int> partner(a.size(), -1);
    auto in = [](const std::vector<std::string>& keys, const std::string& key) {
      return std::find(keys.begin(), keys.end(), key) != keys.end();
    };
    bool renames = object && a.size() == b.size();
    for (size_t i = 0; renames && i < a.size(); ++i)
      renames = a.tokens[i] == b.tokens[i] || (!in(b.tokens, a.tokens[i]) && !in(a.tokens, b.tokens[i]));
    if (renames || (!object && a.size() == b.size())) {
      for (size_t i = 0; i < a.size(); ++i) partner[i] = static_cast<int>(i);
    } else if (object) {
      int last = -1;
      for (size_t j = 0; j < a.size(); ++j) {
        const auto it = std::find(b.tokens.begin(), b.tokens.end(), a.tokens[j]);
        if (it == b.tokens.end()) continue;
        partner[j] = static_cast<int>(it - b.tokens.begin());
        if (partner[j] < last) return false;  // reordered
        last = partner[j];
      }
    } else if (a.size() < b.size()) {
      size_t i = 0;
      for (size_t j = 0; j < a.size(); ++i) {
        if (i == b.size()) return false;
        if (*b.values[i] == *a.values[j]) partner[j++] = static_cast<int>(i);
      }
    } else {
      size_t j = 0;
      for (size_t i = 0; i < b.size(); ++j) {
        if (j == a.size()) return false;
        if (*b.values[i] == *a.values[j]) partner[j] = static_cast<int>(i++);
      }
    }
    std::vector<int> after_index(b.size(), -1);
    for (size_t j = 0; j < a.size(); ++j) {
      if (partner[j] >= 0) after_index[static_cast<size_t>(partner[j])] = static_cast<int>(j);
    }
    const bool any_added = std::count(partner.begin(), partner.end(), -1) > 0;
    const bool any_removed = std::count(after_index.begin(), after_index.end(), -1) > 0;
    if (any_added && any_removed) return false;

    auto before_at = [&](size_t i) { return child(bp, b.tokens[i]); };
    auto after_at = [&](size_t j) { return child(ap, a.tokens[j]); };
    for (size_t i = 0; i < b.size();) {
      if (after_index[i] >= 0) {
        ++i;
        continue;
      }
      std::vector<std::string> run;
      size_t end = i;
      for (; end < b.size() && after_index[end] < 0; ++end) run.push_back(before_at(end));
      removed(run, i > 0 ? std::optional(after_at(static_cast<size_t>(after_index[i - 1]))) : std::nullopt,
              end < b.size() ? std::optional(after_at(static_cast<size_t>(after_index[end]))) : std::nullopt);
      i = end;
    }
    for (size_t j = 0; j < a.size();) {
      if (partner[j] >= 0) {
        ++j;
        continue;
      }
      std::vector<std::string> run;
      ordered_json members = object ? ordered_json::object() : ordered_json::array();
      size_t end = j;
      for (; end < a.size() && partner[end] < 0; ++end) {
        run.push_back(after_at(end));
        if (object)
          members[a.tokens[end]] = *a.values[end];
        else
          members.push_back(*a.values[end]);
      }
      added(run, members, j > 0 ? std::optional(before_at(static_cast<size_t>(partner[j - 1]))) : std::nullopt,
            end < a.size() ? std::optional(std::pair(before_at(static_cast<size_t>(partner[end])), after_at(end))) : std::nullopt);
      j = end;
    }
    for (size_t j = 0; j < a.size(); ++j) {
      if (partner[j] < 0) continue;
      const auto i = static_cast<size_t>(partner[j]);
      if (object && a.tokens[j] != b.tokens[i]) renamed(before_at(i), after_at(j));
      compare(*b.values[i], *a.values[j], before_at(i), after_at(j));
    }
    return true;
  }

  std::string_view before_, after_;
  std::vector<Rewrite> rewrites_;
  std::vector<std::string> problems_;
  std::optional<ordered_json> whole_;
};

// Whether `after` is `before` with only what changed between their values rewritten.
testing::AssertionResult only_changes_rewritten(const ordered_json& before_value, std::string_view before, const ordered_json& after_value,
                                                std::string_view after, std::vector<std::string>* changes = nullptr) {
  Rewrites rewrites(before, after);
  rewrites.compare(before_value, after_value);
  if (changes) *changes = rewrites.changes();
  return rewrites.check();
}

// Every value in `value` (itself too), as JSON pointers, parents before children.
void collect_pointers(const ordered_json& value, const std::string& pointer, std::vector<std::string>& out) {
  out.push_back(pointer);
  if (!value.is_structured()) return;
  for (const auto& [key, member] : value.items()) collect_pointers(member, child(pointer, key), out);
}

std::vector<std::string> all_pointers(const ordered_json& value) {
  std::vector<std::string> out;
  collect_pointers(value, "", out);
  return out;
}

ordered_json& at(ordered_json& value, const std::string& pointer) {
  return value.at(ordered_json::json_pointer(pointer));
}

std::string parent_of(const std::string& pointer) {
  return pointer.substr(0, pointer.rfind('/'));
}

// A value of another kind or another text than `value`'s: every kind of JSON scalar, strings with escapes.
ordered_json different(const ordered_json& value) {
  if (value.is_boolean()) return !value.get<bool>();
  if (value.is_number_integer()) return value.get<int64_t>() + 1;
  if (value.is_number()) return value.get<double>() + 0.5;
  if (value.is_string()) return value.get<std::string>() + " \"edited\"\\\n\u00e9";
  if (value.is_null()) return 0;
  return "was a container";
}

// A random value; small, with every kind of JSON value, and numbers that read back exactly.
ordered_json random_value(std::mt19937& random, int depth = 0) {
  switch (random() % (depth < 2 ? 7 : 5)) {
    case 0: return nullptr;
    case 1: return random() % 2 == 0;
    case 2: return static_cast<int64_t>(random() % 2001) - 1000;
    case 3: return static_cast<double>(random() % 100000) / 64.0;
    case 4: return "s" + std::to_string(random() % 100) + (random() % 2 ? "\t\"q\"/\\\u00e9" : "");
    case 5: {
      ordered_json array = ordered_json::array();
      for (unsigned i = random() % 4; i > 0; --i) array.push_back(random_value(random, depth + 1));
      return array;
    }
    default: {
      ordered_json object = ordered_json::object();
      for (unsigned i = random() % 4; i > 0; --i) object["k" + std::to_string(i)] = random_value(random, depth + 1);
      return object;
    }
  }
}

// Every edit, and every refusal, leaves a model whose text is a valid graph; an applied edit
// rewrites the text of what it changed and nothing else; undo gives back the text before the edit
// byte for byte, and redo the text after it.
// Returns whether the edit was applied.
template <class Edit>
bool check_edit_and_undo(GraphModel& model, const std::string& what, Edit&& edit) {
  SCOPED_TRACE(what);
  const std::string before = model.text();
  const ordered_json before_value = model.json();
  bool applied = false;
  try {
    edit();
    applied = model.text() != before;
  } catch (const InputError& e) {
    EXPECT_EQ(model.text(), before) << "a refused edit changed the graph: " << e.what();
    EXPECT_FALSE(std::string(e.what()).empty());
    if (std::getenv("SHOW_REFUSALS")) std::printf("  refused %s: %s\n", what.c_str(), e.what());
    return false;
  }
  if (!applied) return false;
  const std::string after = model.text();
  EXPECT_TRUE(only_changes_rewritten(before_value, before, model.json(), after));
  EXPECT_NO_THROW(graph::load_graph(JsonDocument::parse(after, "edited.json")));
  EXPECT_TRUE(model.undo());
  EXPECT_EQ(model.text(), before);
  EXPECT_TRUE(model.redo());
  EXPECT_EQ(model.text(), after);
  EXPECT_TRUE(model.undo());
  return true;
}

// One edit of a JSON value, and what it may rewrite in the value's text.
struct ValueEdit {
  std::string what;
  ordered_json value;                     // the edited value
  std::function<void(Rewrites&)> expect;  // the rewrites it may make
};

ValueEdit replace_at(const ordered_json& value, const std::string& pointer, const ordered_json& replacement) {
  ValueEdit edit{"replace " + pointer, value, {}};
  at(edit.value, pointer) = replacement;
  edit.expect = [=](Rewrites& r) { r.replaced(pointer, pointer, replacement); };
  return edit;
}

// The member's token in its container as it is after `position` members of it, for pointers.
std::string token_at(const ordered_json& container, size_t position) {
  if (container.is_array()) return std::to_string(position);
  auto it = container.items().begin();
  for (size_t i = 0; i < position; ++i) ++it;
  return it.key();
}

ValueEdit remove_at(const ordered_json& value, const std::string& pointer) {
  const std::string container_pointer = parent_of(pointer);
  ValueEdit edit{"remove " + pointer, value, {}};
  ordered_json& container = at(edit.value, container_pointer);
  const std::string token = json_span::pointer_tokens(pointer).back();
  size_t position = 0;
  while (token_at(container, position) != token) ++position;
  const size_t size = container.size();
  // The tokens of the neighbours that stay, as they are after the removal.
  const std::optional<std::string> previous =
      position > 0 ? std::optional(child(container_pointer, token_at(container, position - 1))) : std::nullopt;
  std::optional<std::string> next;
  if (position + 1 < size)
    next = child(container_pointer, container.is_array() ? std::to_string(position) : token_at(container, position + 1));
  if (container.is_array())
    container.erase(static_cast<size_t>(position));
  else
    container.erase(token);
  if (size == 1) {
    const ordered_json emptied = container;
    edit.expect = [=](Rewrites& r) { r.replaced(container_pointer, container_pointer, emptied); };
  } else {
    edit.expect = [=](Rewrites& r) { r.removed({pointer}, previous, next); };
  }
  return edit;
}

// Adds `member` to the container at `container_pointer` as its member number `position`, under
// `key` when it is an object.
ValueEdit insert_at(const ordered_json& value, const std::string& container_pointer, size_t position, const std::string& key,
                    const ordered_json& member) {
  ValueEdit edit{"insert " + child(container_pointer, key) + " at " + std::to_string(position), value, {}};
  ordered_json& container = at(edit.value, container_pointer);
  const ordered_json old = container;
  if (old.is_array()) {
    container.insert(container.begin() + static_cast<long>(position), member);
  } else {
    ordered_json rebuilt = ordered_json::object();
    size_t i = 0;
    for (const auto& [k, v] : old.items()) {
      if (i++ == position) rebuilt[key] = member;
      rebuilt[k] = v;
    }
    if (position == old.size()) rebuilt[key] = member;
    container = rebuilt;
  }
  if (old.empty()) {
    const ordered_json filled = container;
    edit.expect = [=](Rewrites& r) { r.replaced(container_pointer, container_pointer, filled); };
    return edit;
  }
  const std::string added = child(container_pointer, old.is_array() ? std::to_string(position) : key);
  ordered_json members = old.is_array() ? ordered_json::array({member}) : ordered_json::object({{key, member}});
  std::optional<std::string> previous;
  std::optional<std::pair<std::string, std::string>> next;
  if (position > 0) previous = child(container_pointer, token_at(old, position - 1));
  if (position < old.size())
    next = std::pair(child(container_pointer, token_at(old, position)), child(container_pointer, token_at(container, position + 1)));
  edit.expect = [=](Rewrites& r) { r.added({added}, members, previous, next); };
  return edit;
}

ValueEdit rename_at(const ordered_json& value, const std::string& pointer, const std::string& new_key) {
  const std::string container_pointer = parent_of(pointer);
  const std::string key = json_span::pointer_tokens(pointer).back();
  ValueEdit edit{"rename " + pointer + " to " + new_key, value, {}};
  ordered_json rebuilt = ordered_json::object();
  for (const auto& [k, v] : at(edit.value, container_pointer).items()) rebuilt[k == key ? new_key : k] = v;
  at(edit.value, container_pointer) = rebuilt;
  const std::string renamed = child(container_pointer, new_key);
  edit.expect = [=](Rewrites& r) { r.renamed(pointer, renamed); };
  return edit;
}

}  // namespace

TEST(JsonSpan, LocatesValuesKeysAndSeparators) {
  // The tests' scanner is what the byte checks below trust, so it is checked on its own first.
  const std::string text = " {\"a\": [1, {\"b~/c\": \"x\\\"y\"}] , \"k\\u00e9\": null} \n";
  auto bytes = [&](json_span::Span s) { return text.substr(s.begin, s.size()); };
  EXPECT_EQ(bytes(json_span::locate(text, "").value), text.substr(1, text.size() - 3));
  const json_span::Located b = json_span::locate(text, "/a/1/b~0~1c");
  EXPECT_EQ(bytes(b.value), "\"x\\\"y\"");
  EXPECT_EQ(bytes(b.key), "\"b~/c\"");
  EXPECT_EQ(bytes(b.member), "\"b~/c\": \"x\\\"y\"");
  const json_span::Located one = json_span::locate(text, "/a/0");
  EXPECT_EQ(bytes(one.value), "1");
  EXPECT_EQ(one.gap_before, (json_span::Span{one.value.begin, one.value.begin}));
  EXPECT_EQ(bytes(one.gap_after), ", ");
  EXPECT_EQ(bytes(json_span::locate(text, "/a").gap_after), " , ");
  const json_span::Located escaped_key = json_span::locate(text, "/k\u00e9");
  EXPECT_EQ(bytes(escaped_key.gap_before), " , ");
  EXPECT_EQ(bytes(escaped_key.value), "null");
  EXPECT_EQ(escaped_key.gap_after.size(), 0u);
  EXPECT_THROW(json_span::locate(text, "/a/2"), std::out_of_range);
  EXPECT_THROW(json_span::locate(text, "/b"), std::out_of_range);
  EXPECT_THROW(json_span::locate("{\"a\": }", "/a"), std::invalid_argument);
  EXPECT_THROW(json_span::locate("[1] 2", ""), std::invalid_argument);
}

TEST(JsonText, UnchangedValuesKeepTheirBytes) {
  // Values changed one at a time: the text written is the original outside that value's text, and
  // that text reads back as the new value. Every value of core_demo.json and of texts that use the
  // freedoms JSON gives its writers; a quarter of every other bundled graph's, a different quarter each.
  // (Writing the unchanged value gives the original too.)
  std::vector<std::pair<std::string, std::string>> texts;
  for (const auto& path : bundled_graphs()) texts.emplace_back(path.filename().string(), file_text(path));
  // Space before a colon and before a comma, none after a comma, tabs, padding, a number as its
  // author spelled it.
  texts.emplace_back("odd", "  {\"b\" :1,\"a\":[ 1,2 ,3],\n\t\"c\": {\"x\": 1.50}}  \n");
  texts.emplace_back("spelled", "{\"n\":[1.50,-0.0,1E2,0e-1],\r\n\"s\":\"\\u0041\\/\",\"k\\u00e9\":{\"t\":true,\"f\":false,\"z\":null}}");
  size_t sampled = 0;
  for (const auto& [name, text] : texts) {
    const ordered_json value = ordered_json::parse(text);
    EXPECT_EQ(editor::write_preserving(value, text), text) << name;
    const bool every_value = name == "core_demo.json" || name == "odd" || name == "spelled";
    const std::vector<std::string> pointers = all_pointers(value);
    for (size_t i = 1; i < pointers.size(); ++i) {
      if (!every_value && i % 4 != sampled % 4) continue;
      const std::string& pointer = pointers[i];
      ordered_json edited = value;
      ordered_json& changed = at(edited, pointer);
      const ordered_json replacement = different(changed);
      changed = replacement;
      const std::string written = editor::write_preserving(edited, text);
      Rewrites rewrites(text, written);
      rewrites.replaced(pointer, pointer, replacement);
      EXPECT_TRUE(rewrites.check()) << name << " " << pointer;
    }
    ++sampled;
  }
}

namespace {

// Sets the value at `pointer` in `text` and checks that the text written changed there alone.
void expect_setting_rewrites_only_it(const std::string& text, const std::string& pointer, const ordered_json& replacement) {
  ordered_json value = ordered_json::parse(text);
  value[ordered_json::json_pointer(pointer)] = replacement;
  const std::string written = editor::write_preserving(value, text);
  Rewrites rewrites(text, written);
  rewrites.replaced(pointer, pointer, replacement);
  EXPECT_TRUE(rewrites.check()) << written;
}

}  // namespace

// An array element set to the value of a later element keeps its place: pairing it with that
// element's text would write the elements in between afresh.
TEST(JsonText, AnArrayElementSetToALaterElementsValueKeepsTheOthersBytes) {
  expect_setting_rewrites_only_it("{\"a\": [1, 2.50, 3]}", "/a/0", 3);
  // Through the model: a position written on one line by its author, moved to where x equals the old y.
  GraphModel model(file_text(graphs_dir() / "core_demo.json"), "core_demo.json", registry());
  model.set_position("pattern", 120, 40);
  std::string placed = model.text();
  const size_t at_position = placed.find("\"pattern\": [");
  ASSERT_NE(at_position, std::string::npos);
  placed.replace(at_position, placed.find(']', at_position) + 1 - at_position, "\"pattern\": [120, 40]");
  GraphModel moved(placed, "core_demo.json", registry());
  moved.set_position("pattern", 40, 40);
  EXPECT_TRUE(only_changes_rewritten(ordered_json::parse(placed), placed, moved.json(), moved.text()));
}

// A container with a changed member keeps each kept member's separator as it was, so a space its
// author put before a comma stays before it.
TEST(JsonText, SpaceBeforeACommaStaysWhereItWas) {
  expect_setting_rewrites_only_it("  {\"b\" :1,\"a\":[ 1,2 ,3],\n\t\"c\": {\"x\": 1.50}}  \n", "/a/2", 4);
}

TEST(JsonText, AnEditChangesOnlyWhatWasEdited) {
  const std::string text = file_text(graphs_dir() / "core_demo.json");
  ordered_json value = ordered_json::parse(text);
  value["passes"][1]["params"]["radius"] = 5;
  std::string expected = text;
  const std::string from = R"("params": {"radius": "$blur_radius", "axis": "x"})";
  ASSERT_NE(expected.find(from), std::string::npos);
  expected.replace(expected.find(from), from.size(), R"("params": {"radius": 5, "axis": "x"})");
  EXPECT_EQ(editor::write_preserving(value, text), expected);

  // A removed member takes its separator with it; an added one copies its neighbours' spacing.
  value = ordered_json::parse(text);
  value["resources"].erase("preview");
  value["resources"]["extra"] = {{"type", "image"}, {"format", "rgba8"}};
  const std::string written = editor::write_preserving(value, text);
  EXPECT_EQ(ordered_json::parse(written), value);
  EXPECT_EQ(written.find("preview\": {"), std::string::npos);
  EXPECT_NE(written.find(",\n    \"extra\": {"), std::string::npos) << written;
  // Everything after the resources is the original's text.
  const std::string tail = text.substr(text.find("  \"passes\""));
  EXPECT_EQ(written.substr(written.size() - tail.size()), tail);
}

TEST(JsonText, AnyEditReadsBackAsTheEditedValue) {
  // Random edits of every kind at random places in every bundled graph: the text written is the
  // original outside the edited value's text (a removed member's: its separators; an added one's: the
  // point after its previous sibling), and what is written there reads back as the edit.
  std::mt19937 random(7);
  for (const auto& path : bundled_graphs()) {
    const std::string text = file_text(path);
    const ordered_json value = ordered_json::parse(text);
    const std::vector<std::string> pointers = all_pointers(value);
    std::vector<std::string> containers, members, object_members;
    for (const auto& p : pointers) {
      const ordered_json& v = value.at(ordered_json::json_pointer(p));
      if (v.is_structured()) containers.push_back(p);
      if (p.empty()) continue;
      members.push_back(p);
      if (value.at(ordered_json::json_pointer(parent_of(p))).is_object()) object_members.push_back(p);
    }
    const size_t passes = value["passes"].size();
    for (int round = 0; round < 60; ++round) {
      const std::string pass = "/passes/" + std::to_string(random() % passes);
      auto pick = [&](const std::vector<std::string>& from) { return from[random() % from.size()]; };
      ValueEdit edit;
      switch (round % 9) {
        // Edits a person makes to a graph.
        case 0: edit = remove_at(value, pass); break;
        case 1: edit = insert_at(value, "/passes", passes, "", {{"name", "new"}, {"type", "tonemap"}}); break;
        case 2: {
          const ordered_json x = {1, 2, {{"deep", "er"}}};
          const std::string params = child(pass, "params");
          edit = value.contains(ordered_json::json_pointer(params))
                     ? insert_at(value, params, value.at(ordered_json::json_pointer(params)).size(), "x", x)
                     : insert_at(value, pass, value.at(ordered_json::json_pointer(pass)).size(), "params", {{"x", x}});
          break;
        }
        case 3: edit = remove_at(value, child(pass, "name")); break;
        case 4: edit = replace_at(value, "/resources", ordered_json::object()); break;
        // Any edit anywhere.
        case 5: {
          const std::string p = pick(pointers);
          ordered_json replacement = random_value(random);
          if (replacement == value.at(ordered_json::json_pointer(p))) replacement = different(replacement);
          edit = replace_at(value, p, replacement);
          break;
        }
        case 6: edit = remove_at(value, pick(members)); break;
        case 7: {
          const std::string p = pick(containers);
          const size_t size = value.at(ordered_json::json_pointer(p)).size();
          edit = insert_at(value, p, random() % (size + 1), "added_" + std::to_string(round), random_value(random));
          break;
        }
        default: edit = rename_at(value, pick(object_members), "renamed_" + std::to_string(round)); break;
      }
      SCOPED_TRACE(path.filename().string() + ": " + edit.what);
      const std::string written = editor::write_preserving(edit.value, text);
      EXPECT_EQ(ordered_json::parse(written), edit.value);
      Rewrites rewrites(text, written);
      edit.expect(rewrites);
      EXPECT_TRUE(rewrites.check());
    }
  }
}

TEST(GraphModel, EveryBundledGraphRoundTripsByteForByte) {
  const auto dir = std::filesystem::temp_directory_path() / ("caustica_round_trip_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  for (const auto& path : bundled_graphs()) {
    SCOPED_TRACE(path.filename().string());
    const std::string original = file_text(path);
    const auto copy = dir / path.filename();
    std::filesystem::copy_file(path, copy, std::filesystem::copy_options::overwrite_existing);
    GraphModel model = GraphModel::open(copy.string(), registry());
    EXPECT_TRUE(same_bytes(original, model.text()));
    EXPECT_FALSE(model.modified());
    EXPECT_FALSE(model.can_undo());
    model.save();
    EXPECT_TRUE(same_bytes(original, file_text(copy))) << "saved with no edit";

    // An edit and its undo.
    const std::string first_pass = model.json()["passes"][0]["name"];
    model.rename_pass(first_pass, first_pass + "_renamed");
    ASSERT_NE(model.text(), original);
    model.undo();
    model.save();
    EXPECT_TRUE(same_bytes(original, file_text(copy))) << "saved after an edit and its undo";

    // A value set to another and back by two edits, not by undo.
    const std::string description = model.json()["description"];
    model.set_graph_field("description", description + " (edited)");
    model.set_graph_field("description", description);
    EXPECT_TRUE(model.can_undo());
    EXPECT_FALSE(model.modified());
    model.save();
    EXPECT_TRUE(same_bytes(original, file_text(copy))) << "saved after a value was set and set back";

    // The same across saves: the file in between is the original but for the edited values' text,
    // and the second save writes them back from that file's text, not from the original's.
    std::string parameter;
    const ordered_json parameters = model.json().value("parameters", ordered_json::object());
    for (const auto& [name, d] : parameters.items()) {
      if (parameter.empty() && d.contains("min") && d.contains("max")) parameter = name;
    }
    ASSERT_FALSE(parameter.empty());
    const ordered_json declaration = model.json()["parameters"][parameter];
    const ordered_json other_default = declaration["min"] != declaration["default"] ? declaration["min"] : declaration["max"];
    const std::string default_pointer = child(child("/parameters", parameter), "default");
    model.set_graph_field("description", description + " (edited)");
    model.set_parameter_field(parameter, "default", other_default);
    model.save();
    const std::string between = file_text(copy);
    Rewrites rewrites(original, between);
    rewrites.replaced("/description", "/description", description + " (edited)");
    rewrites.replaced(default_pointer, default_pointer, other_default);
    EXPECT_TRUE(rewrites.check());
    model.set_graph_field("description", description);
    model.set_parameter_field(parameter, "default", declaration["default"]);
    model.save();
    EXPECT_TRUE(same_bytes(original, file_text(copy))) << "saved after values were set, saved, and set back";
    // An edit saved and then undone: the undo writes back from the saved text too.
    model.rename_pass(first_pass, first_pass + "_renamed");
    model.save();
    model.undo();
    model.save();
    EXPECT_TRUE(same_bytes(original, file_text(copy))) << "saved after an edit was saved and undone";
  }
  std::filesystem::remove_all(dir);
}

// Under the sanitizers (CAUSTICA_SMALL_LOOPS), ten times slower there, on a few graphs that between
// them hold every pass type the bundled graphs use (taken greedily, the graph adding most types
// first); the Release run edits every graph.
std::vector<std::filesystem::path> graphs_to_edit() {
  std::vector<std::filesystem::path> graphs = bundled_graphs();
#ifdef CAUSTICA_SMALL_LOOPS
  std::vector<std::set<std::string>> types;
  for (const auto& path : graphs) {
    std::set<std::string>& in_graph = types.emplace_back();
    const ordered_json graph = ordered_json::parse(file_text(path));
    for (const auto& pass : graph["passes"]) in_graph.insert(pass["type"].get<std::string>());
  }
  std::set<std::string> covered;
  std::vector<std::filesystem::path> chosen;
  for (;;) {
    size_t best = 0, best_new = 0;
    for (size_t i = 0; i < graphs.size(); ++i) {
      const auto adds =
          static_cast<size_t>(std::count_if(types[i].begin(), types[i].end(), [&](const std::string& t) { return !covered.count(t); }));
      if (adds > best_new) {
        best = i;
        best_new = adds;
      }
    }
    if (best_new == 0) break;
    covered.insert(types[best].begin(), types[best].end());
    chosen.push_back(graphs[best]);
  }
  graphs = chosen;
#endif
  return graphs;
}

TEST(GraphModel, EveryOperationAndItsUndoOnEveryBundledGraph) {
  const auto graphs = graphs_to_edit();
  ASSERT_FALSE(graphs.empty());
  for (const auto& path : graphs) {
    SCOPED_TRACE(path.filename().string());
    GraphModel model = GraphModel::open(path.string(), registry());
    const std::string original = model.text();
    const ordered_json doc = model.json();
    int applied = 0, tried = 0;
    auto count = [&](bool done) {
      applied += done ? 1 : 0;
      ++tried;
    };
    for (const auto& pass : doc["passes"]) {
      const std::string name = pass["name"];
      const graph::PassTypeDecl& decl = *registry().find(pass["type"].get<std::string>());
      // Always possible: a new name, a place on the canvas.
      EXPECT_TRUE(check_edit_and_undo(model, "rename " + name, [&] { model.rename_pass(name, name + "_renamed"); }));
      EXPECT_TRUE(check_edit_and_undo(model, "move " + name, [&] { model.set_position(name, 10, 20); }));
      count(check_edit_and_undo(model, "remove " + name, [&] { model.remove_pass(name); }));
      count(check_edit_and_undo(model, "disable " + name, [&] { model.set_enabled(name, false); }));
      const bool per_light = pass.value("for_each", "") == "light";
      count(check_edit_and_undo(model, "per light " + name, [&] { model.set_for_each(name, per_light ? "" : "light"); }));
      count(check_edit_and_undo(model, "per view " + name, [&] { model.set_for_each(name, "caustic_view"); }));
      for (const auto& param : decl.params) {
        // A literal value, not a graph parameter ("$NAME") or an expression (a string for a number).
        auto literal = [&](const ordered_json& value) {
          return !value.is_string() || (param.type == graph::ParamType::choice && value.get<std::string>()[0] != '$');
        };
        const nlohmann::json current = pass.contains("params") && pass["params"].contains(param.name) && literal(pass["params"][param.name])
                                           ? nlohmann::json::parse(pass["params"][param.name].dump())
                                           : param.default_value;
        count(check_edit_and_undo(model, "set " + name + "." + param.name,
                                  [&] { model.set_param(name, param.name, other_value(param, current)); }));
        count(check_edit_and_undo(model, "reset " + name + "." + param.name, [&] { model.reset_param(name, param.name); }));
      }
      for (const char* section : {"inputs", "outputs"}) {
        if (!pass.contains(section)) continue;
        for (const auto& [port, resource] : pass[section].items()) {
          count(check_edit_and_undo(model, "disconnect " + name + "." + port, [&, &port = port] { model.disconnect(name, port); }));
        }
      }
    }
    for (const auto& [resource, description] : doc["resources"].items()) {
      EXPECT_TRUE(check_edit_and_undo(model, "rename resource " + resource,
                                      [&, &resource = resource] { model.rename_resource(resource, resource + "_2"); }));
      count(check_edit_and_undo(model, "remove resource " + resource, [&, &resource = resource] { model.remove_resource(resource); }));
    }
    for (const auto& type : registry().names()) {
      count(check_edit_and_undo(model, "add " + type, [&] { model.add_pass(type); }));
    }
    // The graph's fields, a parameter's and a resource's, new ones, and the outputs.
    EXPECT_TRUE(check_edit_and_undo(model, "describe the graph", [&] { model.set_graph_field("description", "edited"); }));
    const ordered_json parameters = doc.value("parameters", ordered_json::object());
    if (!parameters.empty()) {
      const std::string first = parameters.begin().key();
      EXPECT_TRUE(
          check_edit_and_undo(model, "describe parameter " + first, [&] { model.set_parameter_field(first, "description", "edited"); }));
      count(check_edit_and_undo(model, "remove parameter " + first, [&] { model.remove_parameter(first); }));
    }
    EXPECT_TRUE(check_edit_and_undo(model, "add parameter", [&] {
      model.add_parameter("added", {{"type", "float"}, {"default", 1.0}, {"min", 0.0}, {"max", 2.0}});
    }));
    const std::string first_resource = doc["resources"].begin().key();
    EXPECT_TRUE(check_edit_and_undo(model, "describe resource " + first_resource,
                                    [&] { model.set_resource_field(first_resource, "description", "edited"); }));
    EXPECT_TRUE(check_edit_and_undo(model, "add resource", [&] { model.add_resource("added", {{"type", "image"}, {"format", "rgba8"}}); }));
    std::vector<std::string> outputs = doc["outputs"];
    outputs.push_back(first_resource);
    count(check_edit_and_undo(model, "add an output", [&] { model.set_outputs(outputs); }));
    EXPECT_EQ(model.text(), original);
    // Most edits are valid ones; the refusals are the compiler's to make.
    EXPECT_GT(applied, tried / 3) << applied << " of " << tried << " applied";
    std::printf("%s: %d of %d edits applied, the rest refused\n", path.filename().c_str(), applied, tried);
  }
}

TEST(GraphModel, EachOperationRewritesOnlyTheTextOfWhatItChanges) {
  // Each operation once on core_demo.json, with what it changes named: the text written is the
  // original outside exactly those values (and a removed member's separators, an added member's
  // place after its previous sibling), and reads back as the model's value.
  const std::string original = file_text(graphs_dir() / "core_demo.json");
  auto text_after = [&](const std::string& text, const std::function<void(GraphModel&)>& edit) {
    GraphModel model(text, "core_demo.json", registry());
    edit(model);
    return model.text();
  };
  // core_demo.json with places on the canvas, for the operations that keep them.
  const std::string placed = text_after(original, [](GraphModel& m) {
    m.set_position("pattern", 100, 40);
    m.set_position("blur_x", 300, 40);
    m.set_position("unused_preview", 100, 200);
  });
  const std::string with_gain = text_after(original, [](GraphModel& m) {
    m.add_parameter("gain", {{"type", "float"}, {"default", 1.0}, {"min", 0.0}, {"max", 4.0}});
    m.add_resource("extra", {{"type", "image"}, {"format", "rgba8"}});
  });
  auto expect_changes = [&](const std::string& text, const std::vector<std::string>& expected,
                            const std::function<void(GraphModel&)>& edit) {
    SCOPED_TRACE(expected.front());
    GraphModel model(text, "core_demo.json", registry());
    edit(model);
    std::vector<std::string> changes;
    EXPECT_TRUE(only_changes_rewritten(ordered_json::parse(text), text, model.json(), model.text(), &changes));
    EXPECT_EQ(changes, expected);
  };
  expect_changes(original, {"replace /passes/1/params/radius"}, [](GraphModel& m) { m.set_param("blur_x", "radius", 5); });
  expect_changes(original, {"add /passes/4/params"}, [](GraphModel& m) { m.set_param("unused_preview", "sun_intensity", 2.0); });
  expect_changes(original, {"remove /passes/1/params/axis"}, [](GraphModel& m) { m.reset_param("blur_x", "axis"); });
  expect_changes(original, {"remove /passes/0/params"}, [](GraphModel& m) { m.reset_param("pattern", "sun_intensity"); });
  expect_changes(original, {"add /passes/4/enabled"}, [](GraphModel& m) { m.set_enabled("unused_preview", false); });
  expect_changes(original, {"replace /passes/1/name"}, [](GraphModel& m) { m.rename_pass("blur_x", "blur_first"); });
  expect_changes(placed, {"replace /passes/0/name", "rename /editor/positions/pattern to /editor/positions/source"},
                 [](GraphModel& m) { m.rename_pass("pattern", "source"); });
  expect_changes(original, {"add /resources/box_blur_target", "add /passes/5"}, [](GraphModel& m) { m.add_pass("box_blur"); });
  expect_changes(original, {"remove /resources/preview", "remove /passes/4"}, [](GraphModel& m) { m.remove_pass("unused_preview"); });
  expect_changes(placed, {"remove /resources/preview", "remove /passes/4", "remove /editor/positions/unused_preview"},
                 [](GraphModel& m) { m.remove_pass("unused_preview"); });
  expect_changes(original, {"replace /passes/3/inputs/source"}, [](GraphModel& m) { m.connect("tonemap", "source", "hdr"); });
  expect_changes(original, {"add /resources/extra"}, [](GraphModel& m) {
    m.add_resource("extra", {{"type", "image"}, {"format", "rgba8"}});
  });
  expect_changes(with_gain, {"remove /resources/extra"}, [](GraphModel& m) { m.remove_resource("extra"); });
  expect_changes(original, {"rename /resources/preview to /resources/thumbnail", "replace /passes/4/outputs/color"},
                 [](GraphModel& m) { m.rename_resource("preview", "thumbnail"); });
  expect_changes(original, {"replace /resources/preview/width"},
                 [](GraphModel& m) { m.set_resource_field("preview", "width", "output.width / 2"); });
  expect_changes(original, {"add /resources/blurred/width"},
                 [](GraphModel& m) { m.set_resource_field("blurred", "width", "output.width"); });
  expect_changes(original, {"add /parameters/gain"}, [](GraphModel& m) {
    m.add_parameter("gain", {{"type", "float"}, {"default", 1.0}, {"min", 0.0}, {"max", 4.0}});
  });
  expect_changes(with_gain, {"remove /parameters/gain"}, [](GraphModel& m) { m.remove_parameter("gain"); });
  expect_changes(original, {"replace /parameters/exposure/default"},
                 [](GraphModel& m) { m.set_parameter_field("exposure", "default", 2.0); });
  expect_changes(original, {"replace /description"}, [](GraphModel& m) { m.set_graph_field("description", "edited"); });
  expect_changes(original, {"add /outputs/1"}, [](GraphModel& m) { m.set_outputs({"ldr", "preview"}); });
  expect_changes(original, {"replace /outputs/0"}, [](GraphModel& m) { m.set_outputs({"preview"}); });
  expect_changes(original, {"add /editor"}, [](GraphModel& m) { m.set_position("pattern", 10, 20); });
  expect_changes(placed, {"replace /editor/positions/pattern/0", "replace /editor/positions/pattern/1"},
                 [](GraphModel& m) { m.set_position("pattern", 10, 20); });
  expect_changes(placed, {"add /editor/positions/blur_y"}, [](GraphModel& m) { m.set_position("blur_y", 500, 40); });
}

// The canvas's wires: from a writer's output to each input reading what it writes, and for a history
// input ("still_mean@previous") from the writer of that resource, here the reading pass itself.
TEST(GraphModel, WiresIncludeHistoryInputs) {
  GraphModel model = GraphModel::open((graphs_dir() / "refraction_deferred.json").string(), registry());
  using editor::Wire;
  const std::vector<Wire> found = editor::wires(model.json());
  auto has = [&](const Wire& w) { return std::find(found.begin(), found.end(), w) != found.end(); };
  EXPECT_TRUE(has({"still_mean", "average", "still_mean", "previous", "still_mean", true}));
  EXPECT_TRUE(has({"still_mean", "average", "tonemap", "source", "still_mean", false}));
  for (const Wire& w : found) {
    EXPECT_FALSE(w.writer == w.reader && !w.history) << w.writer << " wired to itself";
    EXPECT_EQ(w.resource.find('@'), std::string::npos) << w.resource;
  }
}

TEST(GraphModel, InvalidEditsAreRefusedWithTheValidatorsMessage) {
  GraphModel model = GraphModel::open((graphs_dir() / "core_demo.json").string(), registry());
  const std::string before = model.text();
  auto refused = [&](auto&& edit, const std::string& message) {
    try {
      edit();
      ADD_FAILURE() << "not refused; expected '" << message << "'";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
    EXPECT_EQ(model.text(), before);
    EXPECT_FALSE(model.can_undo());
  };
  refused([&] { model.set_param("blur_x", "radius", 1000); }, "parameter 'radius' of pass 'blur_x'");
  refused([&] { model.set_param("blur_x", "radius", "$nothing"); }, "no graph parameter 'nothing'");
  refused([&] { model.set_param("blur_x", "radus", 1); }, "did you mean 'radius'");
  refused([&] { model.connect("tonemap", "source", "ldr"); }, "ldr");
  refused([&] { model.connect("tonemap", "source", "missing"); }, "no resource named 'missing'");
  refused([&] { model.connect("blur_x", "nope", "hdr"); }, "has no port 'nope'");
  refused([&] { model.disconnect("tonemap", "source"); }, "is not connected");
  refused([&] { model.remove_pass("blur_x"); }, "which no pass writes");
  refused([&] { model.rename_pass("blur_x", "blur_y"); }, "already exists");
  refused([&] { model.rename_pass("blur_x", "bad name!"); }, "pass name");
  refused([&] { model.add_pass("no_such_type"); }, "unknown pass type");
  refused([&] { model.remove_pass("nobody"); }, "no pass named 'nobody'");
  refused([&] { model.set_outputs({"nothing"}); }, "nothing");
  refused([&] { model.set_resource_field("hdr", "format", "rgba9"); }, "unknown format 'rgba9'");
  refused([&] { model.add_pass("lighting"); }, "cannot add a lighting pass");
}

TEST(GraphModel, AddPassFillsPortsAndDefaultsAndRemovePassTakesItsResources) {
  GraphModel model = GraphModel::open((graphs_dir() / "core_demo.json").string(), registry());
  const std::string original = model.text();
  const std::string name = model.add_pass("box_blur");
  EXPECT_EQ(name, "box_blur");
  const ordered_json& pass = model.json()["passes"].back();
  // Every declared parameter at its default; the input bound to an image a pass writes, the
  // latest writer first (tonemap writes rgba8, which a blur does not take; unused_preview's is).
  for (const auto& p : registry().find("box_blur")->params)
    EXPECT_EQ(nlohmann::json::parse(pass["params"][p.name].dump()), p.default_value);
  EXPECT_EQ(pass["inputs"]["source"], "preview");
  EXPECT_EQ(pass["outputs"]["target"], "box_blur_target");
  EXPECT_EQ(model.json()["resources"]["box_blur_target"]["format"], "rgba16f");
  // Its output has the size of its input (one extent group): a quarter of the frame.
  EXPECT_EQ(model.json()["resources"]["box_blur_target"]["width"], "output.width / 4");
  // Re-wired to a full-size image, the output it made follows (else the pass could not go live).
  model.connect("box_blur", "source", "hdr");
  EXPECT_EQ(model.json()["resources"]["box_blur_target"]["width"], "output.width");
  model.connect("tonemap", "source", "box_blur_target");
  EXPECT_EQ(model.desc().passes.back().name, "box_blur");
  model.undo();
  model.undo();
  EXPECT_EQ(model.add_pass("box_blur"), "box_blur_2");
  model.remove_pass("box_blur_2");
  model.remove_pass("box_blur");
  EXPECT_FALSE(model.json()["resources"].contains("box_blur_target"));
  EXPECT_EQ(model.text(), original);
  EXPECT_FALSE(model.modified());
  EXPECT_EQ(model.undo_label(), "remove pass box_blur");
}

TEST(GraphModel, SavesOnlyWhatChangedAndNeverOverAnotherEditorsChange) {
  const auto dir = std::filesystem::temp_directory_path() / ("caustica_model_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto path = dir / "g.json";
  std::filesystem::copy_file(graphs_dir() / "caustics_adaptive.json", path, std::filesystem::copy_options::overwrite_existing);
  const std::string original = file_text(path);
  GraphModel model = GraphModel::open(path.string(), registry());
  model.save();
  EXPECT_EQ(file_text(path), original);

  model.set_param("tonemap", "exposure", 2.5);
  EXPECT_TRUE(model.modified());
  model.save();
  EXPECT_FALSE(model.modified());
  std::string expected = original;
  const std::string from = "\"exposure\": \"$exposure\"";
  ASSERT_NE(expected.find(from), std::string::npos);
  expected.replace(expected.find(from), from.size(), "\"exposure\": 2.5");
  EXPECT_EQ(file_text(path), expected);

  // Another editor writes the file: a save is refused until the user says to overwrite.
  { std::ofstream(path) << original; }
  EXPECT_TRUE(model.changed_on_disk());
  model.set_param("tonemap", "exposure", 3.0);
  EXPECT_THROW(model.save(), InputError);
  EXPECT_EQ(file_text(path), original);
  model.save(true);
  EXPECT_EQ(ordered_json::parse(file_text(path))["passes"].back()["params"]["exposure"], 3.0);
  // No temporary file is left beside it.
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), std::filesystem::directory_iterator()), 1);
  std::filesystem::remove_all(dir);
}

TEST(GraphModel, MalformedFilesAreMessagesNotCrashes) {
  // Each input is refused with a message naming the file; none opens. The broken copies of a valid
  // graph fail for their one defect alone.
  const std::string good = file_text(graphs_dir() / "core_demo.json");
  ASSERT_NO_THROW(GraphModel(good, "bad.json", registry()));
  std::string duplicated = good;
  duplicated.insert(good.find("\"name\""), "\"name\": \"first\",\n  ");
  std::string nul = good;
  nul.insert(good.find("core_demo") + 4, std::string(1, '\0'));
  std::string lone_surrogate = good;
  lone_surrogate.insert(good.find("core_demo") + 4, "\\ud800");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"", "empty document"},
      {"{", "bad.json:1:2"},
      {"{\"passes\": 3}", "bad.json"},
      {"[1, 2]", "bad.json"},
      {"{\"a\": 1, \"a\": 2}", "duplicate member name \"a\""},
      {"\"just a string\"", "bad.json"},
      {good.substr(0, good.size() / 2), "bad.json:"},
      {good.substr(0, good.rfind('}')), "bad.json:"},
      {good + "x", "unexpected text after the JSON value"},
      {good + "{}", "unexpected text after the JSON value"},
      {duplicated, "duplicate member name \"name\""},
      {"// a comment\n" + good, "bad.json:1:1"},
      {nul, "control character"},
      {lone_surrogate, "lone high surrogate"},
  };
  for (const auto& [text, message] : cases) {
    try {
      GraphModel model(text, "bad.json", registry());
      ADD_FAILURE() << "opened without an error:\n" << text.substr(0, 200);
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << "expected '" << message << "' in: " << e.what();
    } catch (const std::exception& e) {
      ADD_FAILURE() << "refused without a message that names the file: " << e.what();
    }
  }
  // The CLI's bad graphs, each with the message `caustica validate` gives (its .expect file).
  int files = 0, opened_refused = 0;
  for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(CAUSTICA_SOURCE_DIR) / "tests/data/bad_graphs")) {
    if (entry.path().extension() != ".json") continue;
    ++files;
    std::string expected = file_text(std::filesystem::path(entry.path()).replace_extension(".expect"));
    while (!expected.empty() && expected.back() == '\n') expected.pop_back();
    try {
      // One that loads as a graph but does not compile opens refused, to be repaired, with the
      // same message.
      const GraphModel refused = GraphModel::open(entry.path().string(), registry());
      EXPECT_NE(refused.refusal().find(entry.path().filename().string()), std::string::npos) << refused.refusal();
      EXPECT_NE(refused.refusal().find(expected), std::string::npos) << "expected '" << expected << "' in: " << refused.refusal();
      ++opened_refused;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(entry.path().filename().string()), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << "expected '" << expected << "' in: " << e.what();
    } catch (const std::exception& e) {
      ADD_FAILURE() << entry.path().filename() << " refused without a message that names the file: " << e.what();
    }
  }
  EXPECT_GE(files, 30);
  EXPECT_GE(opened_refused, 5) << "the bad graphs that compile-fail should open refused";
}

// A graph file that starts with a UTF-8 byte order mark opens (the engine's parser skips the mark)
// and can be edited: json_text's scanner skips the mark too, and keeps it in the text written.
TEST(GraphModel, AFileWithAByteOrderMarkCanBeEdited) {
  const std::string text = "\xEF\xBB\xBF" + file_text(graphs_dir() / "core_demo.json");
  GraphModel model(text, "bom.json", registry());
  EXPECT_EQ(model.text(), text);
  try {
    model.set_param("blur_x", "radius", 5);
  } catch (const InputError& e) {
    FAIL() << e.what();
  }
  const std::string edited = model.text();  // Rewrites keeps views of both texts
  Rewrites rewrites(text, edited);
  rewrites.replaced("/passes/1/params/radius", "/passes/1/params/radius", 5);
  EXPECT_TRUE(rewrites.check());
}

// caustics_adaptive.json rebuilt from core_demo.json by the model's operations alone, in the order a
// person would use them in the editor; the compiled plans are the same.
TEST(GraphModel, AnEditScriptRebuildsCausticsAdaptiveFromCoreDemo) {
  const ordered_json target = ordered_json::parse(file_text(graphs_dir() / "caustics_adaptive.json"));
  GraphModel model = GraphModel::open((graphs_dir() / "core_demo.json").string(), registry());
  const ordered_json opened_value = model.json();
  const std::string opened = model.text();
  // A second model takes the same steps and saves after each: every save rewrites only what its step
  // changed in the file as last saved. (Between saves the text is the file as opened with what
  // differs from it rewritten; members that were never saved have no text of their own to keep.)
  const auto dir = std::filesystem::temp_directory_path() / ("caustica_script_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto copy = dir / "g.json";
  std::filesystem::copy_file(graphs_dir() / "core_demo.json", copy, std::filesystem::copy_options::overwrite_existing);
  GraphModel saving = GraphModel::open(copy.string(), registry());
  auto checked = [&](auto&& edit) {
    edit(model);
    EXPECT_TRUE(only_changes_rewritten(opened_value, opened, model.json(), model.text())) << model.undo_label();
    const ordered_json saved_value = saving.json();
    const std::string saved = file_text(copy);
    edit(saving);
    saving.save();
    EXPECT_EQ(saving.json(), model.json());
    EXPECT_TRUE(only_changes_rewritten(saved_value, saved, saving.json(), file_text(copy))) << saving.undo_label();
  };
  checked([&](GraphModel& m) { m.set_graph_field("name", target["name"]); });
  checked([&](GraphModel& m) { m.set_graph_field("description", target["description"]); });
  for (const auto& [name, declaration] : target["parameters"].items()) {
    if (!model.json()["parameters"].contains(name)) {
      checked([&, &name = name, &declaration = declaration](GraphModel& m) { m.add_parameter(name, declaration); });
      continue;
    }
    for (const auto& [field, value] : declaration.items())
      checked([&, &name = name, &field = field, &value = value](GraphModel& m) { m.set_parameter_field(name, field, value); });
  }
  for (const auto& [name, description] : target["resources"].items()) {
    if (!model.json()["resources"].contains(name))
      checked([&, &name = name, &description = description](GraphModel& m) { m.add_resource(name, description); });
  }
  std::set<std::string> kept;
  for (const auto& pass : target["passes"]) {
    const std::string name = pass["name"];
    kept.insert(name);
    bool exists = false;
    for (const auto& p : model.json()["passes"]) exists = exists || p["name"] == name;
    std::vector<std::string> made;  // resources add_pass made for the outputs, replaced below
    if (!exists) {
      checked([&](GraphModel& m) { EXPECT_EQ(m.add_pass(pass["type"], name), name); });
      const ordered_json outputs = model.json()["passes"].back().value("outputs", ordered_json::object());
      for (const auto& [port, resource] : outputs.items()) made.push_back(resource);
    }
    // Once per light before its bindings: what it writes is per light too.
    if (pass.contains("for_each")) checked([&](GraphModel& m) { m.set_for_each(name, pass["for_each"]); });
    for (const char* section : {"inputs", "outputs"}) {
      const ordered_json bindings = pass.value(section, ordered_json::object());
      for (const auto& [port, resource] : bindings.items())
        checked([&, &port = port, &resource = resource](GraphModel& m) { m.connect(name, port, resource); });
    }
    for (const auto& r : made) {
      if (!target["resources"].contains(r)) checked([&](GraphModel& m) { m.remove_resource(r); });
    }
    const ordered_json params = pass.value("params", ordered_json::object());
    for (const auto& [param, value] : params.items())
      checked([&, &param = param, &value = value](GraphModel& m) { m.set_param(name, param, value); });
    if (pass.contains("enabled")) checked([&](GraphModel& m) { m.set_enabled(name, pass["enabled"]); });
  }
  checked([&](GraphModel& m) { m.set_outputs(target["outputs"]); });
  checked([&](GraphModel& m) { m.set_graph_field("linear_output", target["linear_output"]); });
  // Readers before writers, as a person would unpick a chain.
  const ordered_json passes_now = model.json()["passes"];
  for (auto pass = passes_now.rbegin(); pass != passes_now.rend(); ++pass) {
    if (!kept.count((*pass)["name"])) checked([&](GraphModel& m) { m.remove_pass((*pass)["name"]); });
  }
  const ordered_json parameters_now = model.json()["parameters"];
  for (const auto& [name, declaration] : parameters_now.items()) {
    if (!target["parameters"].contains(name)) checked([&, &name = name](GraphModel& m) { m.remove_parameter(name); });
  }
  const ordered_json resources_now = model.json()["resources"];
  for (const auto& [name, description] : resources_now.items()) {
    if (!target["resources"].contains(name)) checked([&, &name = name](GraphModel& m) { m.remove_resource(name); });
  }
  EXPECT_EQ(plan_of(model.desc()), plan_of(graph::load_graph_file((graphs_dir() / "caustics_adaptive.json").string())));
  // And every step can be undone, back to core_demo.json as it is on disk.
  while (model.undo()) {
  }
  EXPECT_EQ(model.text(), file_text(graphs_dir() / "core_demo.json"));
  std::filesystem::remove_all(dir);
}

namespace {

// ProggyClean, ImGui's built-in font that the editor draws with: 13 px lines, 7 px a character.
const editor::TextMeasure kPanelFont{13.0f, [](const std::string& text) { return 7.0f * static_cast<float>(text.size()); }};

// A wire's label as the canvas places it along the wire: its resource's name.
std::vector<std::string> wire_names(const std::vector<editor::Wire>& wires) {
  std::vector<std::string> names;
  for (const auto& w : wires) names.push_back(w.history ? "last frame's " + w.resource : w.resource);
  return names;
}

std::string describe(const editor::Box& b) {
  return std::to_string(b.x) + "," + std::to_string(b.y) + " " + std::to_string(b.w) + "x" + std::to_string(b.h);
}

}  // namespace

// Every bundled graph opens in the editor's default window with every node inside the canvas, none
// over another, its text at the panels' size (issue 43: text 6 px high, passes outside the canvas).
TEST(CanvasLayout, EveryBundledGraphFitsTheDefaultCanvasAtTheReadableSize) {
  const editor::Box canvas{0, 0, editor::kDefaultCanvasWidth, editor::kDefaultCanvasHeight};
  for (const auto& path : bundled_graphs()) {
    SCOPED_TRACE(path.filename().string());
    const GraphModel model = GraphModel::open(path.string(), registry());
    const auto nodes = editor::layout_nodes(model.json(), registry(), kPanelFont);
    ASSERT_EQ(nodes.size(), model.json()["passes"].size());
    const editor::CanvasView view = editor::fit_view(nodes, canvas.w, canvas.h);
    EXPECT_GE(kPanelFont.line_height * view.zoom, kPanelFont.line_height) << "canvas text smaller than the panels'";
    for (size_t i = 0; i < nodes.size(); ++i) {
      const editor::Point top = view.to_screen({0, 0}, {nodes[i].box.x, nodes[i].box.y});
      const editor::Box shown{top.x, top.y, nodes[i].box.w * view.zoom, nodes[i].box.h * view.zoom};
      EXPECT_TRUE(canvas.contains(shown)) << nodes[i].name << " at " << describe(shown) << " is outside the canvas";
      for (size_t j = i + 1; j < nodes.size(); ++j)
        EXPECT_FALSE(nodes[i].box.overlaps(nodes[j].box)) << nodes[i].name << " overlaps " << nodes[j].name;
    }
  }
}

// A node is as wide as its text: its title, and each row's input and output labels side by side.
TEST(CanvasLayout, NodesHoldTheirWholeText) {
  const GraphModel model = GraphModel::open((graphs_dir() / "caustics_adaptive.json").string(), registry());
  const editor::NodeMetrics metrics(kPanelFont);
  for (const auto& n : editor::layout_nodes(model.json(), registry(), kPanelFont)) {
    EXPECT_GE(n.box.w, kPanelFont.width(n.title) + 2.0f * metrics.padding) << n.title;
    for (size_t row = 0; row < std::min(n.inputs.size(), n.outputs.size()); ++row) {
      EXPECT_GE(n.box.w, kPanelFont.width(n.inputs[row]) + kPanelFont.width(n.outputs[row]) + 2.0f * metrics.port_inset)
          << n.name << " row " << row;
    }
  }
}

// Wire labels lie over no node and no other label (issue 43: they overlapped both); a label with no
// free place along its wire is left to the hover. Of all the bundled graphs' wires, a third at least
// are labelled on the canvas.
TEST(CanvasLayout, WireLabelsOverlapNoNodeAndNoOtherLabel) {
  size_t all_wires = 0, all_placed = 0;
  for (const auto& path : bundled_graphs()) {
    SCOPED_TRACE(path.filename().string());
    const GraphModel model = GraphModel::open(path.string(), registry());
    const auto nodes = editor::layout_nodes(model.json(), registry(), kPanelFont);
    const auto wires = editor::wires(model.json());
    const auto names = wire_names(wires);
    const auto labels = editor::place_wire_labels(nodes, wires, names, kPanelFont);
    ASSERT_EQ(labels.size(), wires.size());
    size_t placed = 0;
    for (size_t i = 0; i < labels.size(); ++i) {
      if (!labels[i]) continue;
      ++placed;
      EXPECT_GE(labels[i]->w, kPanelFont.width(names[i])) << names[i];
      for (const auto& n : nodes) EXPECT_FALSE(labels[i]->overlaps(n.box)) << names[i] << " over node " << n.name;
      for (size_t j = i + 1; j < labels.size(); ++j)
        EXPECT_FALSE(labels[j] && labels[i]->overlaps(*labels[j])) << names[i] << " over " << names[j];
    }
    all_wires += wires.size();
    all_placed += placed;
  }
  EXPECT_GE(3 * all_placed, all_wires) << all_placed << " of " << all_wires << " wires labelled";
}

// A graph that does not compile (core_demo with the tonemap's input unbound) opens refused with
// the compiler's message; edits that leave it refused are taken, the one that repairs it ends the
// refusal, and undo brings the refusal back (issue 43: `caustica edit` exited 1 on it).
TEST(GraphModel, AGraphThatDoesNotCompileOpensRefusedAndCanBeRepaired) {
  ordered_json broken = ordered_json::parse(file_text(graphs_dir() / "core_demo.json"));
  broken["passes"][3].erase("inputs");
  GraphModel model(broken.dump(2), "broken.json", registry());
  EXPECT_NE(model.refusal().find("input 'source' of pass 'tonemap'"), std::string::npos) << model.refusal();
  model.set_param("blur_x", "radius", 5);  // no repair: taken, still refused
  EXPECT_FALSE(model.refusal().empty());
  EXPECT_EQ(model.json()["passes"][1]["params"]["radius"], 5);
  model.connect("tonemap", "source", "blurred");
  EXPECT_EQ(model.refusal(), "");
  EXPECT_NO_THROW(graph::load_graph(JsonDocument::parse(model.text(), "repaired.json")));
  // Compiling again, an edit that breaks it is refused as before.
  EXPECT_THROW(model.disconnect("tonemap", "source"), InputError);
  ASSERT_TRUE(model.undo());
  EXPECT_FALSE(model.refusal().empty());
  ASSERT_TRUE(model.redo());
  EXPECT_EQ(model.refusal(), "");
  // What the window runs meanwhile compiles, under the graph's name.
  const graph::GraphDesc stand_in = graph::load_graph(JsonDocument::parse(editor::stand_in_graph("core_demo"), "stand_in.json"));
  EXPECT_EQ(stand_in.name, "core_demo");
  graph::CompileOptions options;
  options.scene_values = graph::typical_scene_values();
  EXPECT_NO_THROW(graph::compile_graph(stand_in, registry(), options));
}

// A user pass added from its shader file alone (the editor's "compute shader..." and "full-screen
// shader..."): its ports, parameters and dispatch are what the shader declares, its input is bound
// to an image a pass writes, the graph compiles and the canvas shows the ports. A shader that does
// not compile is refused with its file and line, and the graph stays as it was.
TEST(EditorModel, AUserPassIsDeclaredFromItsShader) {
  const auto dir = std::filesystem::temp_directory_path() / ("caustica_user_pass_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::filesystem::copy_file(graphs_dir() / "core_demo.json", dir / "g.json", std::filesystem::copy_options::overwrite_existing);
  std::ofstream(dir / "scale.comp") << "#version 460\n"
                                       "layout(local_size_x = 8, local_size_y = 8) in;\n"
                                       "layout(binding = 0) uniform sampler2D source;\n"
                                       "layout(binding = 1, rgba16f) uniform writeonly image2D target;\n"
                                       "layout(push_constant) uniform Params { float gain; int taps; } params;\n"
                                       "void main() {\n"
                                       "  const ivec2 p = ivec2(gl_GlobalInvocationID.xy);\n"
                                       "  imageStore(target, p, params.gain * float(params.taps) * texelFetch(source, p, 0));\n"
                                       "}\n";
  std::ofstream(dir / "view.frag") << "#version 460\n"
                                      "layout(binding = 0) uniform sampler2D source;\n"
                                      "layout(location = 0) out vec4 shown;\n"
                                      "void main() { shown = texelFetch(source, ivec2(gl_FragCoord.xy), 0); }\n";
  std::ofstream(dir / "bad.comp") << "#version 460\nlayout(local_size_x = 8) in;\nvoid main() { undeclared = 1; }\n";
  // Its parameters in a uniform block Params, which is no port.
  std::ofstream(dir / "weights.comp") << "#version 460\n"
                                         "layout(local_size_x = 8, local_size_y = 8) in;\n"
                                         "layout(binding = 0) uniform sampler2D source;\n"
                                         "layout(binding = 1, rgba16f) uniform writeonly image2D target;\n"
                                         "layout(binding = 2) uniform Params { float weight; uint taps; } params;\n"
                                         "void main() {\n"
                                         "  const ivec2 p = ivec2(gl_GlobalInvocationID.xy);\n"
                                         "  imageStore(target, p, params.weight * float(params.taps) * texelFetch(source, p, 0));\n"
                                         "}\n";
  GraphModel model = GraphModel::open((dir / "g.json").string(), registry());

  const std::string name = model.add_user_pass("compute", "scale.comp");
  EXPECT_EQ(model.refusal(), "");
  const ordered_json pass = model.json()["passes"].back();
  EXPECT_EQ(pass["name"], name);
  EXPECT_EQ(pass["shader"], "scale.comp");
  EXPECT_EQ(pass["ports"]["source"]["access"], "read");
  EXPECT_EQ(pass["ports"]["target"]["access"], "write");
  EXPECT_EQ(pass["ports"]["target"]["formats"], ordered_json::array({"rgba16f"}));
  EXPECT_EQ(pass["parameters"]["gain"]["type"], "float");
  EXPECT_EQ(pass["parameters"]["taps"]["type"], "int");
  EXPECT_EQ(pass["dispatch"], "target");
  ASSERT_TRUE(pass.contains("inputs") && pass["inputs"].contains("source"));
  EXPECT_EQ(model.json()["resources"][pass["inputs"]["source"].get<std::string>()]["format"], "rgba16f");
  bool drawn = false;
  for (const auto& n : editor::layout_nodes(model.json(), registry(), kPanelFont)) {
    if (n.name != name) continue;
    drawn = true;
    EXPECT_EQ(n.inputs, std::vector<std::string>{"source"});
    EXPECT_EQ(n.outputs, std::vector<std::string>{"target"});
  }
  EXPECT_TRUE(drawn);
  EXPECT_NE(model.pass_type(pass).find_param("gain"), nullptr) << "the pass panel lists the shader's parameters";

  model.add_user_pass("compute", "weights.comp");
  EXPECT_EQ(model.refusal(), "");
  const ordered_json weights = model.json()["passes"].back();
  EXPECT_EQ(weights["parameters"]["weight"]["type"], "float");
  EXPECT_EQ(weights["parameters"]["taps"]["type"], "int");
  EXPECT_FALSE(weights["ports"].contains("params") || weights["ports"].contains("Params")) << "the parameter block became a port";

  const std::string shown = model.add_user_pass("fullscreen", "view.frag");
  const ordered_json view = model.json()["passes"].back();
  EXPECT_EQ(view["ports"]["shown"]["access"], "write");
  EXPECT_FALSE(view.contains("dispatch"));
  EXPECT_EQ(model.refusal(), "");

  const ordered_json before = model.json();
  try {
    model.add_user_pass("compute", "bad.comp");
    ADD_FAILURE() << "a shader that does not compile was taken";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.comp:3"), std::string::npos) << e.what();
  }
  EXPECT_THROW(model.add_pass("compute"), InputError) << "a user pass needs its shader";
  EXPECT_EQ(model.json(), before);
  std::filesystem::remove_all(dir);
}

// A graph written for one light (its shadow map made once, for light 0): "once per light" on the
// shadow pass makes it and its map per light, its light the instance's, and the lighting pass's
// per-light port then reads every light's map; once again undoes it to the byte.
TEST(GraphModel, APassMadeOncePerLightTakesWhatItWritesWithIt) {
  ordered_json doc = ordered_json::parse(file_text(graphs_dir() / "caustics_adaptive.json"));
  for (auto& p : doc["passes"]) {
    if (p["name"] != "shadow") continue;
    p.erase("for_each");
    p.erase("enabled");
    p.erase("params");
  }
  for (const char* key : {"for_each", "layers", "fallback"}) doc["resources"]["shadow"].erase(key);
  const std::string one_light = doc.dump(2) + "\n";
  GraphModel model(one_light, "one_light.json", registry());
  ASSERT_TRUE(model.refusal().empty()) << model.refusal();
  EXPECT_TRUE(check_edit_and_undo(model, "per light shadow", [&] { model.set_for_each("shadow", "light"); }));
  EXPECT_THROW(model.set_for_each("shadow", "lights"), InputError);
  model.set_for_each("shadow", "light");
  const ordered_json& made = model.json();
  for (const auto& p : made["passes"]) {
    if (p["name"] != "shadow") continue;
    EXPECT_EQ(p["for_each"], "light");
    EXPECT_EQ(p["params"]["light"], "$light");
  }
  EXPECT_EQ(made["resources"]["shadow"]["for_each"], "light");
  graph::CompileOptions options;
  options.scene_values = graph::typical_scene_values();
  const graph::Plan plan = graph::compile_graph(graph::load_graph(JsonDocument::parse(model.text(), "made.json")), registry(), options);
  const auto lighting = std::find_if(plan.passes.begin(), plan.passes.end(), [](const auto& p) { return p.name == "lighting"; });
  ASSERT_NE(lighting, plan.passes.end());
  EXPECT_EQ(plan.resources[lighting->ports.at("shadow[0]")].name, "shadow#0");
  model.set_for_each("shadow", "");
  EXPECT_EQ(model.text(), one_light);
}
