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
  AtomicFile file(path);
  for (const std::string_view content : parts)
    file.write(content);
  file.commit();
}

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)), tmp_(path_ + ".tmp") {
  fd_ = ::open(tmp_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) throw OutputError(fmt::format("{}: cannot write: {}", path_, std::strerror(errno)));
}

AtomicFile::~AtomicFile() {
  if (fd_ >= 0) {
    ::close(fd_);
    ::unlink(tmp_.c_str());
  }
}

void AtomicFile::fail(const std::string& what) {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  ::unlink(tmp_.c_str());
  throw OutputError(path_ + ": " + what);
}

void AtomicFile::write(std::string_view content) {
  for (std::size_t done = 0; done < content.size();) {
    const ssize_t n = ::write(fd_, content.data() + done, content.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0)
      fail(fmt::format("write failed: {} (the previous version is kept)",
                       std::strerror(n < 0 ? errno : ENOSPC)));
    done += static_cast<std::size_t>(n);
  }
}

void AtomicFile::commit() {
  if (::fsync(fd_) != 0) fail(fmt::format("cannot flush: {}", std::strerror(errno)));
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) {
    const int err = errno;
    ::unlink(tmp_.c_str());
    throw OutputError(fmt::format("{}: cannot flush: {}", path_, std::strerror(err)));
  }
  if (std::rename(tmp_.c_str(), path_.c_str()) != 0) {
    const int err = errno;
    ::unlink(tmp_.c_str());
    throw OutputError(fmt::format("{}: cannot rename into place: {}", path_, std::strerror(err)));
  }
  // Make the rename itself durable: a crash after this leaves the new file, never none.
  const auto slash = path_.find_last_of('/');
  const std::string dir = slash == std::string::npos ? "." : path_.substr(0, slash + 1);
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
