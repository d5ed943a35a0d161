#include "talus/output/files.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fmt/format.h>
#include <unistd.h>

namespace talus {

void write_file_atomic(const std::string& path, std::string_view content) {
  write_file_atomic(path, {content});
}

void write_file_atomic(const std::string& path, std::initializer_list<std::string_view> parts) {
  const std::string tmp = path + ".tmp";
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw OutputError(fmt::format("{}: cannot write: {}", path, std::strerror(errno)));
  for (const std::string_view content : parts)
    for (std::size_t done = 0; done < content.size();) {
      const ssize_t n = ::write(fd, content.data() + done, content.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        const int err = n < 0 ? errno : ENOSPC;
        ::close(fd);
        ::unlink(tmp.c_str());
        throw OutputError(fmt::format("{}: write failed: {} (the previous version is kept)", path,
                                      std::strerror(err)));
      }
      done += static_cast<std::size_t>(n);
    }
  if (::fsync(fd) != 0 || ::close(fd) != 0) {
    const int err = errno;
    ::unlink(tmp.c_str());
    throw OutputError(fmt::format("{}: cannot flush: {}", path, std::strerror(err)));
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const int err = errno;
    ::unlink(tmp.c_str());
    throw OutputError(fmt::format("{}: cannot rename into place: {}", path, std::strerror(err)));
  }
  // Make the rename itself durable: a crash after this leaves the new file, never none.
  const auto slash = path.find_last_of('/');
  const std::string dir = slash == std::string::npos ? "." : path.substr(0, slash + 1);
  if (const int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC); dfd >= 0) {
    ::fsync(dfd);
    ::close(dfd);
  }
}

void prepare_run_folder(const std::string& dir, bool overwrite) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(dir, ec)) return;
  if (!fs::is_directory(dir, ec))
    throw RunFolderError(fmt::format("{}: exists and is not a folder: give another --out", dir));
  if (fs::is_empty(dir, ec)) return;
  const bool has_checkpoints = fs::exists(dir + "/checkpoints", ec);
  const bool run_folder = has_checkpoints || fs::exists(dir + "/case.toml", ec) ||
                          fs::exists(dir + "/summary.json", ec);
  if (!run_folder)
    throw RunFolderError(fmt::format(
        "{}: the folder holds files that are not a talus run folder's (no case.toml, "
        "summary.json or checkpoints/): give another --out; it is not emptied, even with "
        "--overwrite",
        dir));
  if (!overwrite)
    throw RunFolderError(fmt::format(
        "{}: the folder holds an earlier run: give another --out, or --overwrite to empty it "
        "first{}",
        dir,
        has_checkpoints ? fmt::format(", or talus run --restart {} to continue that run", dir)
                        : std::string()));
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    fs::remove_all(entry.path(), ec);
    if (ec)
      throw OutputError(fmt::format("{}: cannot empty the run folder: {}: {}", dir,
                                    entry.path().string(), ec.message()));
  }
  if (ec) throw OutputError(fmt::format("{}: cannot list the run folder: {}", dir, ec.message()));
}

} // namespace talus
