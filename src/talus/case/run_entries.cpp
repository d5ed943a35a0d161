#include "talus/case/run_entries.hpp"

#include <map>
#include <sstream>
#include <utility>

namespace talus::case_reading {

std::vector<Override> take_run_entries(toml::table& doc, const Where& where, InputFiles& files) {
  std::vector<Override> sets;
  TableReader root(doc, "", where);
  for_each_entry(root, "run", [&](TableReader& r, std::size_t) {
    const std::vector<std::string> specs = string_list(r, "set");
    for (std::size_t i = 0; i < specs.size(); ++i) // each named by its line in case.toml
      sets.push_back({specs[i], fmt::format("[[run]] set (line {})",
                                            r.array("set")->get(i)->source().begin.line)});
    std::map<std::string, std::string> renames;
    if (const toml::table* t = r.table("files"))
      for (auto&& [k, v] : *t) {
        if (!v.is_string()) r.fail("files", "expected \"name written\" = \"name read\" strings");
        renames[std::string(k.str())] = v.value<std::string>().value();
      }
    files.add_renames(std::move(renames));
  });
  doc.erase("run");
  return sets;
}

std::string text_as_run(std::string text, const std::vector<std::string>& overrides,
                        const InputFiles& files) {
  const auto renames = files.renames_to_copies();
  if (overrides.empty() && renames.empty()) return text;
  toml::table entry;
  if (!overrides.empty()) {
    toml::array set;
    for (const auto& o : overrides)
      set.push_back(o);
    entry.insert("set", std::move(set));
  }
  if (!renames.empty()) {
    toml::table t;
    for (const auto& [from, to] : renames)
      t.insert(from, to);
    entry.insert("files", std::move(t));
  }
  toml::array runs;
  runs.push_back(std::move(entry));
  toml::table trailer;
  trailer.insert("run", std::move(runs));
  if (!text.empty() && text.back() != '\n') text += '\n';
  std::ostringstream out;
  out << "\n# Added by talus run: the --set values of the run and where it copied the files it "
         "read.\n"
      << trailer << "\n";
  return text + out.str();
}

} // namespace talus::case_reading
