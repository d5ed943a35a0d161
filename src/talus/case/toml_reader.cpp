#include "talus/case/toml_reader.hpp"

#include <cctype>
#include <sstream>

namespace talus {

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j)
    row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

namespace case_reading {

std::string printable(const std::string& text, std::size_t max) {
  std::string out = text.substr(0, max);
  for (char& ch : out)
    if (ch < 0x20 || ch > 0x7e) ch = '?';
  return out + (text.size() > max ? "..." : "");
}

std::string suggest(const std::string& word, const std::vector<std::string>& choices) {
  std::string best;
  std::size_t best_d = std::max<std::size_t>(3, word.size() / 2) + 1;
  for (const auto& c : choices) {
    const std::size_t d = edit_distance(word, c);
    if (d < best_d) best_d = d, best = c;
  }
  return best.empty() ? std::string{} : fmt::format(" (did you mean '{}'?)", best);
}

void apply_override(toml::table& doc, const Override& o, const std::string& file) {
  const std::string& spec = o.spec;
  const std::string& from = o.origin;
  const auto eq = spec.find('=');
  if (eq == std::string::npos || eq == 0)
    throw CaseError(
        fmt::format("{}: {} '{}': expected key.path=value", file, from, printable(spec)));
  const std::string path = spec.substr(0, eq);
  const std::string text = spec.substr(eq + 1);
  std::vector<std::string> keys;
  std::stringstream ss(path);
  for (std::string k; std::getline(ss, k, '.');)
    keys.push_back(k);
  if (path.front() == '.' || path.back() == '.' ||
      std::any_of(keys.begin(), keys.end(), [](const std::string& k) { return k.empty(); }))
    throw CaseError(
        fmt::format("{}: {} '{}': a key path with an empty part", file, from, printable(path)));
  toml::node* node = &doc;
  std::string walked;
  for (std::size_t i = 0; i + 1 < keys.size(); ++i) {
    walked += (walked.empty() ? "" : ".") + keys[i];
    toml::node* next = nullptr;
    if (auto* t = node->as_table()) {
      next = t->get(keys[i]);
      if (!next) next = &t->insert_or_assign(keys[i], toml::table{}).first->second;
    } else if (auto* a = node->as_array()) {
      for (std::size_t j = 0; j < a->size() && !next; ++j) {
        auto* e = a->get(j)->as_table();
        if (std::to_string(j) == keys[i] ||
            (e && e->get("name") && e->get("name")->value<std::string>() == keys[i]))
          next = a->get(j);
      }
    }
    if (!next) throw CaseError(fmt::format("{}: {} {}: no entry '{}'", file, from, path, walked));
    node = next;
  }
  auto* t = node->as_table();
  if (!t) throw CaseError(fmt::format("{}: {} {}: '{}' is not a table", file, from, path, walked));
  // A key the document does not have at the top level may be one of a section's: say which.
  if (keys.size() == 1 && !t->get(keys[0]))
    for (const auto& [section, node] : doc)
      if (const auto* sub = node.as_table(); sub && sub->get(keys[0]))
        throw CaseError(fmt::format("{}: {} {}: no top-level key '{}' (did you mean {}.{}?)", file,
                                    from, path, keys[0], section.str(), keys[0]));
  toml::table parsed;
  try {
    parsed = toml::parse("v = " + text, from); // the value's source path names the override
  } catch (const toml::parse_error& e) {
    // A bare word (letters, digits, '_' and '-') is a string; anything else must be TOML.
    const bool bare = !text.empty() && std::all_of(text.begin(), text.end(), [](char ch) {
      return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == '-';
    });
    if (!bare)
      throw CaseError(fmt::format("{}: {} {}: the value '{}' does not parse as TOML ({}): "
                                  "write a number, true/false, a quoted string or an array "
                                  "[...]",
                                  file, from, printable(path), printable(text), e.description()));
    parsed =
        toml::parse("v = \"" + text + "\"", from); // no character of a bare word needs escaping
  }
  t->insert_or_assign(keys.back(), std::move(*parsed.get("v"))); // moved: keeps its source
}

} // namespace case_reading

} // namespace talus
