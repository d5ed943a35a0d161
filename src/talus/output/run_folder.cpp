#include "talus/output/run_folder.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <ctime>
#include <fcntl.h>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <iterator>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

namespace talus {

namespace {

namespace fs = std::filesystem;

bool all_digits(std::string_view s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
}

// `name` without the suffix of a temporary talus writes it through (AtomicFile: NAME.tmp or
// NAME.tmp.N; a frame's scratch: NAME.body.tmp), or as it is.
std::string_view without_temporary(std::string_view name) {
  if (const auto k = name.rfind(".tmp.");
      k != std::string_view::npos && all_digits(name.substr(k + 5)))
    name = name.substr(0, k);
  else if (name.ends_with(".tmp"))
    name = name.substr(0, name.size() - 4);
  else
    return name;
  if (name.ends_with(".body")) name = name.substr(0, name.size() - 5);
  return name;
}

// NAME_DDDDDD.EXT, talus's numbered frames.
bool numbered(std::string_view name, std::string_view prefix, std::string_view ext) {
  return name.starts_with(prefix) && name.ends_with(ext) &&
         all_digits(name.substr(prefix.size(), name.size() - prefix.size() - ext.size()));
}

// A regular file (not a link) directly in the run folder that talus writes.
bool talus_file(std::string_view name) {
  name = without_temporary(name);
  for (const char* own :
       {run_folder_marker, "case.toml", "case_as_run.toml", "legend.json", "summary.json",
        "energy.csv", "bodies.csv", "probes.csv", "waves.csv", "contacts.csv", "interfaces.csv",
        "particles.pvd", "contact_nodes.pvd", "particles_fixed.vtu"})
    if (name == own) return true;
  return numbered(name, "particles_", ".vtu") || numbered(name, "contact_nodes_", ".vtu");
}

// A regular file in one of talus's sub-folders: the input copies (each named, quoted, in the
// [[run]] files table of the folder's case.toml, `case_text`), the checkpoints, the maps, the plots
// its tools draw.
bool talus_file_in(std::string_view folder, std::string_view name, const std::string& case_text) {
  name = without_temporary(name);
  if (folder == "inputs") {
    const std::string copy = "inputs/" + std::string(name);
    return case_text.find("'" + copy + "'") != std::string::npos ||
           case_text.find("\"" + copy + "\"") != std::string::npos;
  }
  if (folder == "checkpoints") return numbered(name, "step_", ".ckpt");
  if (folder == "maps")
    return name.ends_with(".tif") || name.ends_with(".geojson") || name == "profile.csv";
  return name.ends_with(".png") || name.ends_with(".csv") || name.ends_with(".json");
}

[[noreturn]] void refuse(const std::string& message) {
  throw RunFolderError(message);
}

// What the marker of a locked folder says of the run that holds it (printable characters only).
std::string holder(int fd) {
  char buf[512] = {};
  const ssize_t n = ::pread(fd, buf, sizeof buf - 1, 0);
  std::string s;
  ssize_t i = 0;
  while (i < n && buf[i] != '\n') // the first line names the file, not the run
    ++i;
  for (; i < n; ++i) {
    const char c = buf[i];
    if (c == '\n')
      s += s.empty() ? "" : "; ";
    else if (std::isprint(static_cast<unsigned char>(c)))
      s += c;
  }
  while (s.ends_with("; "))
    s.resize(s.size() - 2);
  return s.empty() ? "another talus process" : s;
}

} // namespace

std::vector<std::string> foreign_entries(const std::string& dir) {
  std::vector<std::string> out;
  std::error_code ec;
  // The folder's case.toml names the input copies talus made (none if it has none, or if it is
  // not a regular file of a case's size).
  std::string case_text;
  const std::string case_file = dir + "/case.toml";
  if (fs::is_regular_file(fs::symlink_status(case_file, ec)) &&
      fs::file_size(case_file, ec) < (std::uintmax_t{16} << 20)) {
    std::ifstream in(case_file, std::ios::binary);
    case_text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    const fs::file_type type = e.symlink_status(ec).type();
    if (type == fs::file_type::regular && talus_file(name)) continue;
    if (type == fs::file_type::directory &&
        (name == "inputs" || name == "checkpoints" || name == "plots" || name == "maps")) {
      for (const auto& f : fs::directory_iterator(e.path(), ec)) {
        const std::string inner = f.path().filename().string();
        if (f.symlink_status(ec).type() != fs::file_type::regular ||
            !talus_file_in(name, inner, case_text))
          out.push_back(name + "/" + inner);
      }
      continue;
    }
    out.push_back(name);
  }
  if (ec) out.push_back(fmt::format("(the folder cannot be listed: {})", ec.message()));
  std::sort(out.begin(), out.end());
  return out;
}

RunFolder::RunFolder(std::string dir, Use use) : dir_(std::move(dir)) {
  // A refusal after the marker was taken must let it go: a constructor that throws runs no
  // destructor, and the lock would hold the folder for the rest of the process.
  try {
    take(use);
  } catch (...) {
    if (marker_fd_ >= 0) ::close(marker_fd_);
    marker_fd_ = -1;
    if (dir_fd_ >= 0) anchor_folder("", -1), ::close(dir_fd_);
    dir_fd_ = -1;
    throw;
  }
}

void RunFolder::take(Use use) {
  std::error_code ec;
  const fs::file_status st = fs::symlink_status(dir_, ec);
  if (use == Use::restart && !fs::is_directory(fs::status(dir_, ec)))
    refuse(fmt::format("{}: no such run folder", dir_));
  if (!fs::exists(st)) {
    fs::create_directories(dir_, ec);
    if (ec)
      throw OutputError(fmt::format("{}: cannot create the run folder: {}", dir_, ec.message()));
  } else if (!fs::is_directory(fs::status(dir_, ec))) {
    refuse(fmt::format("{}: exists and is not a folder: give another --out", dir_));
  }
  const std::string marker = dir_ + "/" + run_folder_marker;
  const bool marked = fs::exists(fs::symlink_status(marker, ec));
  if (use == Use::restart) {
    // A folder of an older talus has no marker yet: it gets one, if it holds the checkpoints a
    // restart needs; any other folder is not Talus's to mark.
    if (!marked && !fs::is_directory(fs::symlink_status(dir_ + "/checkpoints", ec)))
      refuse(fmt::format("{}: the folder has no {} marker and no checkpoints/, so it is not a "
                         "talus run folder: there is nothing to restart",
                         dir_, run_folder_marker));
    take_marker(!marked);
    return;
  }
  if (!marked) {
    if (!fs::is_empty(dir_, ec))
      refuse(fmt::format(
          "{}: the folder holds files and no {} marker, so it is not a talus run folder (or one "
          "written by a talus older than the marker): give another --out; it is not emptied, "
          "even with --overwrite",
          dir_, run_folder_marker));
    take_marker(true);
    return;
  }
  take_marker(false); // refused here if another run holds it
  // A marker alone: a run that stopped before it wrote anything.
  bool only_marker = true;
  for (const auto& e : fs::directory_iterator(dir_, ec))
    only_marker = only_marker && e.path().filename() == run_folder_marker;
  if (only_marker) return;
  if (use == Use::fresh)
    refuse(fmt::format(
        "{}: the folder holds an earlier run: give another --out, or --overwrite to empty it "
        "first{}",
        dir_,
        fs::exists(dir_ + "/checkpoints", ec)
            ? fmt::format(", or talus run --restart {} to continue that run", dir_)
            : std::string()));
  const std::vector<std::string> foreign = foreign_entries(dir_);
  if (!foreign.empty())
    refuse(fmt::format("{}: the run folder holds {} entr{} talus did not write ({}{}): --overwrite "
                       "removes only talus's files and leaves this folder as it is: move them, or "
                       "give another --out",
                       dir_, foreign.size(), foreign.size() == 1 ? "y" : "ies",
                       fmt::join(foreign.begin(),
                                 foreign.begin() + std::min<std::size_t>(foreign.size(), 5), ", "),
                       foreign.size() > 5 ? ", ..." : ""));
  for (const auto& e : fs::directory_iterator(dir_, ec)) {
    if (e.path().filename() == run_folder_marker) continue;
    fs::remove_all(e.path(), ec);
    if (ec)
      throw OutputError(fmt::format("{}: cannot empty the run folder: {}: {}", dir_,
                                    e.path().string(), ec.message()));
  }
  if (ec) throw OutputError(fmt::format("{}: cannot list the run folder: {}", dir_, ec.message()));
}

void RunFolder::take_marker(bool create) {
  const std::string marker = dir_ + "/" + run_folder_marker;
  const int flags = O_RDWR | O_NOFOLLOW | O_CLOEXEC | (create ? O_CREAT | O_EXCL : 0);
  marker_fd_ = ::open(marker.c_str(), flags, 0644);
  if (marker_fd_ < 0 && create && errno == EEXIST) // made by a run that started at the same time
    marker_fd_ = ::open(marker.c_str(), O_RDWR | O_NOFOLLOW | O_CLOEXEC);
  if (marker_fd_ < 0)
    refuse(
        fmt::format("{}: cannot open the run folder's marker: {}", marker, std::strerror(errno)));
  struct stat m {};
  if (::fstat(marker_fd_, &m) != 0 || !S_ISREG(m.st_mode))
    refuse(fmt::format("{}: the run folder's marker is not a regular file", marker));
  if (::flock(marker_fd_, LOCK_EX | LOCK_NB) != 0) {
    const std::string who = holder(marker_fd_);
    ::close(marker_fd_);
    marker_fd_ = -1;
    refuse(fmt::format("{}: the run folder is in use by {}: wait for that run to end (or stop it "
                       "with Ctrl-C or kill), or give another --out",
                       dir_, who));
  }
  // Who holds it, for a second run's refusal.
  char host[256] = {};
  ::gethostname(host, sizeof host - 1);
  const std::time_t now = std::time(nullptr);
  char when[32] = {};
  std::strftime(when, sizeof when, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  const std::string text =
      fmt::format("talus run folder\ntalus process {} on {}, since {}\n", ::getpid(), host, when);
  if (::ftruncate(marker_fd_, 0) != 0 ||
      ::pwrite(marker_fd_, text.data(), text.size(), 0) != static_cast<ssize_t>(text.size()))
    throw OutputError(fmt::format("{}: cannot write: {}", marker, std::strerror(errno)));
  // The folder held open: the run's writes go into it even if its path is later given to
  // another folder (which receives nothing; check_still_here then stops the run).
  dir_fd_ = ::open(dir_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  struct stat d {};
  if (dir_fd_ < 0 || ::fstat(dir_fd_, &d) != 0)
    throw OutputError(
        fmt::format("{}: cannot open the run folder: {}", dir_, std::strerror(errno)));
  anchor_folder(dir_, dir_fd_);
  dev_ = d.st_dev, dir_ino_ = d.st_ino, marker_ino_ = m.st_ino;
}

RunFolder::RunFolder(RunFolder&& other) noexcept
    : dir_(std::move(other.dir_)), marker_fd_(other.marker_fd_), dir_fd_(other.dir_fd_),
      dev_(other.dev_), dir_ino_(other.dir_ino_), marker_ino_(other.marker_ino_) {
  other.marker_fd_ = -1;
  other.dir_fd_ = -1;
}

RunFolder::~RunFolder() {
  if (marker_fd_ >= 0) ::close(marker_fd_); // releases the lock
  if (dir_fd_ >= 0) anchor_folder("", -1), ::close(dir_fd_);
}

void RunFolder::check_still_here() const {
  struct stat d {
  }, m{};
  const std::string marker = dir_ + "/" + run_folder_marker;
  if (::stat(dir_.c_str(), &d) != 0 || d.st_dev != dev_ || d.st_ino != dir_ino_ ||
      ::lstat(marker.c_str(), &m) != 0 || m.st_ino != marker_ino_)
    throw OutputError(fmt::format(
        "{}: the run folder was removed, emptied or replaced while this run wrote it: the run "
        "stops rather than write a partial folder",
        dir_));
}

} // namespace talus
