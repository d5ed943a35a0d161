// Reading TOML tables for the case parser: a reader per table that knows its key path, reports
// every error with the file, the line and the key, and names the unknown keys it did not use with
// the nearest valid one ("did you mean").
#pragma once

#include "talus/case/parse.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <fmt/format.h>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace talus::case_reading {

// At most `max` characters of `text`, each byte that is not printable ASCII shown as '?': what a
// message may quote of a user's value or a file's content (no terminal escape reaches the
// terminal through an error).
std::string printable(const std::string& text, std::size_t max = 60);

// " (did you mean 'x'?)" for the choice nearest `word`, or nothing if none is near.
std::string suggest(const std::string& word, const std::vector<std::string>& choices);

// Where an error points: the file and the line of a node. A value an override set carries the
// override's origin as its source path ("--set", or the run folder's "[[run]] set (line N)"); a
// table an override made has no line at all.
struct Where {
  std::string file;
  [[noreturn]] void fail(const toml::source_region& src, const std::string& key,
                         const std::string& msg) const {
    const auto line = src.begin.line;
    if (line != 0 && src.path && *src.path != file)
      throw CaseError(fmt::format("{}: (from {}) {}: {}", file, *src.path, key, msg));
    if (line == 0) throw CaseError(fmt::format("{}: (from an override) {}: {}", file, key, msg));
    throw CaseError(fmt::format("{}:{}: {}: {}", file, line, key, msg));
  }
};

// Reads one TOML table, remembering which keys were used so the leftovers are reported as
// unknown with the nearest valid key.
class TableReader {
public:
  TableReader(const toml::table& t, std::string path, const Where& where)
      : t_(t), path_(std::move(path)), where_(where) {}

  std::string key_path(const std::string& key) const {
    return path_.empty() ? key : path_ + "." + key;
  }
  const toml::node* find(const std::string& key) {
    known_.insert(key);
    return t_.get(key);
  }
  bool has(const std::string& key) {
    known_.insert(key);
    return t_.contains(key);
  }
  [[noreturn]] void fail(const std::string& key, const std::string& msg) const {
    const toml::node* n = t_.get(key);
    where_.fail(n ? n->source() : t_.source(), key_path(key), msg);
  }
  // A missing key, pointing at a present key that looks like a misspelling of it.
  [[noreturn]] void fail_missing(const std::string& key) const {
    for (auto&& [k, v] : t_) {
      const std::string name(k.str());
      if (!known_.count(name) &&
          edit_distance(name, key) <= std::max<std::size_t>(2, key.size() / 3))
        where_.fail(
            t_.source(), key_path(key),
            fmt::format("required key is missing (line {} has '{}')", v.source().begin.line, name));
    }
    where_.fail(t_.source(), key_path(key), "required key is missing");
  }

  double number(const std::string& key) {
    const toml::node* n = find(key);
    if (!n) fail_missing(key);
    return as_number(*n, key);
  }
  double number(const std::string& key, double fallback) {
    return has(key) ? number(key) : fallback;
  }
  std::optional<double> optional_number(const std::string& key) {
    if (!has(key)) return std::nullopt;
    return number(key);
  }
  // An integer in [lo, hi] (checked before any narrowing, so 2^32 + 2 is not 2).
  int integer(const std::string& key, int fallback, int lo, int hi) {
    const toml::node* n = find(key);
    if (!n) return fallback;
    if (!n->is_integer()) fail(key, fmt::format("expected an integer, got {}", type_name(*n)));
    const long long v = n->value<long long>().value();
    if (v < lo || v > hi) fail(key, fmt::format("must be in [{}, {}], got {}", lo, hi, v));
    return static_cast<int>(v);
  }
  // A name: a non-empty string.
  std::string name(const std::string& key, const std::string& fallback) {
    const std::string s = has(key) || fallback.empty() ? string(key) : fallback;
    if (s.find_first_not_of(" \t") == std::string::npos) fail(key, "must not be empty");
    return s;
  }
  bool boolean(const std::string& key, bool fallback) {
    const toml::node* n = find(key);
    if (!n) return fallback;
    if (!n->is_boolean()) fail(key, fmt::format("expected true or false, got {}", type_name(*n)));
    return n->value<bool>().value();
  }
  // A string of printable characters: a control character (C0, DEL or C1: a NUL, a line break,
  // a terminal escape sequence) would reach the terminal, the CSVs and the JSON raw.
  std::string string(const std::string& key) {
    const toml::node* n = find(key);
    if (!n) fail_missing(key);
    if (!n->is_string()) fail(key, fmt::format("expected a string, got {}", type_name(*n)));
    std::string s = n->value<std::string>().value();
    for (std::size_t i = 0; i < s.size(); ++i) {
      const auto c = static_cast<unsigned char>(s[i]);
      const bool c1 = c == 0xC2 && i + 1 < s.size() && static_cast<unsigned char>(s[i + 1]) < 0xA0;
      if (c < 0x20 || c == 0x7F || c1)
        fail(key, fmt::format("holds a control character (byte {} of the string, U+{:04X}): "
                              "names, titles and file names are printable text",
                              i + 1, c1 ? static_cast<unsigned char>(s[i + 1]) : c));
    }
    return s;
  }
  std::string string(const std::string& key, const std::string& fallback) {
    return has(key) ? string(key) : fallback;
  }
  // A string that must be one of `choices`.
  std::string choice(const std::string& key, const std::vector<std::string>& choices,
                     const std::string& fallback) {
    const std::string s = string(key, fallback);
    if (std::find(choices.begin(), choices.end(), s) == choices.end()) {
      std::string list;
      for (const auto& c : choices)
        list += (list.empty() ? "" : ", ") + c;
      fail(key, fmt::format("'{}' is not one of: {}{}", s, list, suggest(s, choices)));
    }
    return s;
  }
  // A vector of exactly n numbers (n = the case's dimension).
  Vec3a vector(const std::string& key, int n) {
    const toml::node* node = find(key);
    if (!node) fail_missing(key);
    return as_vector(*node, key, n);
  }
  Vec3a vector(const std::string& key, int n, const Vec3a& fallback) {
    return has(key) ? vector(key, n) : fallback;
  }
  const toml::table* table(const std::string& key) {
    const toml::node* n = find(key);
    if (!n) return nullptr;
    if (!n->is_table()) fail(key, fmt::format("expected a table, got {}", type_name(*n)));
    return n->as_table();
  }
  const toml::array* array(const std::string& key) {
    const toml::node* n = find(key);
    if (!n) return nullptr;
    if (!n->is_array()) fail(key, fmt::format("expected an array, got {}", type_name(*n)));
    return n->as_array();
  }

  // A key this table does not take in its present form, but another form of it does (a key
  // of another material model): finish() names that form instead of "unknown key".
  void belongs_elsewhere(const std::string& key, std::string where) {
    elsewhere_[key] = std::move(where);
  }

  // Reports the first key that no one asked for.
  void finish() const {
    std::vector<std::string> known(known_.begin(), known_.end());
    for (auto&& [k, v] : t_) {
      const std::string name(k.str());
      if (known_.count(name)) continue;
      const auto other = elsewhere_.find(name);
      where_.fail(k.source().begin.line ? k.source() : v.source(), key_path(name),
                  other != elsewhere_.end() ? other->second : "unknown key" + suggest(name, known));
    }
  }

  double as_number(const toml::node& n, const std::string& key) const {
    if (n.is_floating_point()) {
      const double v = n.value<double>().value();
      if (!std::isfinite(v)) where_.fail(n.source(), key_path(key), "must be a finite number");
      return v;
    }
    if (n.is_integer()) return static_cast<double>(n.value<long long>().value());
    where_.fail(n.source(), key_path(key), fmt::format("expected a number, got {}", type_name(n)));
  }
  Vec3a as_vector(const toml::node& node, const std::string& key, int n) const {
    const toml::array* a = node.as_array();
    if (!a || static_cast<int>(a->size()) != n)
      where_.fail(node.source(), key_path(key),
                  fmt::format("expected an array of {} numbers (one per dimension)", n));
    Vec3a v{0.0, 0.0, 0.0};
    for (int i = 0; i < n; ++i)
      v[i] = as_number(*a->get(i), fmt::format("{}[{}]", key, i));
    return v;
  }
  static std::string type_name(const toml::node& n) {
    switch (n.type()) {
    case toml::node_type::table:
      return "a table";
    case toml::node_type::array:
      return "an array";
    case toml::node_type::string:
      return "a string";
    case toml::node_type::integer:
      return "an integer";
    case toml::node_type::floating_point:
      return "a number";
    case toml::node_type::boolean:
      return "a boolean";
    default:
      return "a date or time";
    }
  }
  const Where& where() const { return where_; }
  const toml::table& raw() const { return t_; }

private:
  const toml::table& t_;
  std::string path_;
  const Where& where_;
  std::set<std::string> known_;
  std::map<std::string, std::string> elsewhere_; // belongs_elsewhere
};

// Each [[section]] entry as a reader with path "section[i]".
template <class F>
void for_each_entry(TableReader& root, const std::string& key, F&& f) {
  const toml::array* arr = root.array(key);
  if (!arr) return;
  for (std::size_t i = 0; i < arr->size(); ++i) {
    const toml::node* n = arr->get(i);
    if (!n->is_table())
      root.where().fail(n->source(), fmt::format("{}[{}]", key, i),
                        fmt::format("expected a table: write [[{}]] sections", key));
    TableReader r(*n->as_table(), fmt::format("{}[{}]", key, i), root.where());
    f(r, i);
    r.finish();
  }
}

inline void require(TableReader& r, const std::string& key, bool ok, const std::string& msg) {
  if (!ok) r.fail(key, msg);
}

// The names of a case's materials, bodies, ... in order (for lookups and "did you mean").
template <class T>
std::vector<std::string> names_of(const std::vector<T>& items) {
  std::vector<std::string> names;
  for (const T& x : items)
    names.push_back(x.name);
  return names;
}

// Which of a list of named things a key refers to.
inline int lookup(TableReader& r, const std::string& key, const std::vector<std::string>& names,
                  const std::string& what) {
  const std::string s = r.string(key);
  const auto it = std::find(names.begin(), names.end(), s);
  if (it == names.end())
    r.fail(key, fmt::format("no {} is named '{}'{}", what, s, suggest(s, names)));
  return static_cast<int>(it - names.begin());
}

// `bodies = ["a", "b"]`: two different bodies, as indices.
inline std::pair<int, int> read_body_pair(TableReader& r,
                                          const std::vector<std::string>& body_names) {
  const toml::array* a = r.array("bodies");
  if (!a) r.fail_missing("bodies");
  if (a->size() != 2 || !a->get(0)->is_string() || !a->get(1)->is_string())
    r.fail("bodies", "expected two body names, e.g. bodies = [\"slide\", \"bedrock\"]");
  int ids[2];
  for (int k = 0; k < 2; ++k) {
    const std::string name = a->get(k)->value<std::string>().value();
    const auto it = std::find(body_names.begin(), body_names.end(), name);
    if (it == body_names.end())
      r.fail("bodies", fmt::format("no body is named '{}'{}", name, suggest(name, body_names)));
    ids[k] = static_cast<int>(it - body_names.begin());
  }
  if (ids[0] == ids[1]) r.fail("bodies", "a pair needs two different bodies");
  return {ids[0], ids[1]};
}

// An optional array of strings (e.g. --set style overrides).
inline std::vector<std::string> string_list(TableReader& r, const std::string& key) {
  std::vector<std::string> out;
  if (!r.has(key)) return out;
  const toml::array* a = r.array(key);
  if (!a) r.fail(key, "expected an array of strings");
  for (std::size_t i = 0; i < a->size(); ++i) {
    const auto s = a->get(i)->value<std::string>();
    if (!s) r.fail(key, fmt::format("element {} is not a string", i));
    out.push_back(*s);
  }
  return out;
}

// An override "a.b.c=value" and where it came from: "--set", or "[[run]] set (line N)" of a run
// folder's case.toml (which errors name).
struct Override {
  std::string spec;
  std::string origin = "--set";
};

// Applies an override to the document: segments index arrays by number or by an entry's name;
// the value is TOML, or a bare word taken as a string. Throws CaseError naming its origin.
void apply_override(toml::table& doc, const Override& o, const std::string& file);

} // namespace talus::case_reading
