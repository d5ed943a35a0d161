#include "talus/case/input_files.hpp"

#include <algorithm>

namespace talus::case_reading {

std::string InputFiles::resolve(const std::string& written) {
  namespace fs = std::filesystem;
  std::string name = written;
  for (const auto& r : renames_)
    if (const auto it = r.find(name); it != r.end()) name = it->second;
  const fs::path source = fs::path(name).is_absolute() ? fs::path(name) : base_dir_ / name;
  const std::string read = source.lexically_normal().string();
  for (std::size_t i = 0; i < files_.size(); ++i)
    if (files_[i].source == read) {
      named_.emplace_back(name, i);
      return read;
    }
  // The copy keeps the file's name; a second file of the same name gets "-2", "-3", ...
  const fs::path file = source.filename();
  std::string copy = "inputs/" + file.string();
  for (int k = 2; std::any_of(files_.begin(), files_.end(),
                              [&](const InputFile& f) { return f.copy == copy; });
       ++k)
    copy = "inputs/" + file.stem().string() + "-" + std::to_string(k) + file.extension().string();
  named_.emplace_back(name, files_.size());
  files_.push_back({read, copy});
  return read;
}

void InputFiles::add_sidecars(const std::string& read) {
  namespace fs = std::filesystem;
  const auto it = std::find_if(files_.begin(), files_.end(),
                               [&](const InputFile& f) { return f.source == read; });
  if (it == files_.end()) return;
  const std::string copy = it->copy;
  auto add = [&](const std::string& source, const std::string& copied) {
    std::error_code ec;
    if (!fs::is_regular_file(source, ec)) return;
    for (const InputFile& f : files_)
      if (f.source == source) return;
    files_.push_back({source, copied});
  };
  for (const char* ext : {".prj", ".shx", ".dbf", ".cpg", ".tfw"})
    add(fs::path(read).replace_extension(ext).string(),
        fs::path(copy).replace_extension(ext).string());
  add(read + ".aux.xml", copy + ".aux.xml");
}

std::map<std::string, std::string> InputFiles::renames_to_copies() const {
  std::map<std::string, std::string> out;
  for (const auto& [name, i] : named_)
    if (name != files_[i].copy) out[name] = files_[i].copy;
  return out;
}

} // namespace talus::case_reading
