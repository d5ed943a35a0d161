#include "talus/case/input_files.hpp"

#include "talus/case/parse.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fmt/format.h>
#include <fstream>
#include <sys/stat.h>

namespace talus::case_reading {

void check_input_file(const std::string& path, std::uintmax_t max_bytes) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    throw CaseError(errno == ENOENT
                        ? fmt::format("{}: no such file", path)
                        : fmt::format("{}: cannot read the file: {}", path, std::strerror(errno)));
  if (S_ISDIR(st.st_mode)) throw CaseError(fmt::format("{}: is a folder, not a file", path));
  if (!S_ISREG(st.st_mode))
    throw CaseError(fmt::format("{}: is not a regular file (a device, FIFO or socket): talus "
                                "reads only files it can copy into the run folder",
                                path));
  if (static_cast<std::uintmax_t>(st.st_size) > max_bytes)
    throw CaseError(fmt::format("{}: is {:.3g} GB, more than the {:.3g} GB talus reads as this "
                                "kind of input",
                                path, static_cast<double>(st.st_size) / 1e9,
                                static_cast<double>(max_bytes) / 1e9));
  std::ifstream in(path, std::ios::binary);
  char head[64] = {};
  in.read(head, sizeof head - 1);
  const std::string_view start(head, static_cast<std::size_t>(in.gcount()));
  const auto tag = start.find_first_not_of(" \t\r\n\xEF\xBB\xBF");
  if (tag != std::string_view::npos && start.substr(tag).starts_with("<VRTDataset"))
    throw CaseError(fmt::format(
        "{}: is a GDAL virtual raster (VRT), whose sources a run folder cannot copy: write it "
        "as one file first (gdal_translate {} dem.tif)",
        path, path));
}

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
