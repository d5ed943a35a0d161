#include "talus/output/files.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fmt/format.h>
#include <mutex>
#include <sys/stat.h>
#include <unistd.h>

namespace talus {

namespace {

std::mutex anchor_mutex;
std::string anchored_dir;
int anchored_fd = -1;

// A path as the system calls take it: relative to the anchored folder if it lies under it.
struct At {
  int fd;
  std::string name;
};
At at(const std::string& path) {
  const std::lock_guard<std::mutex> lock(anchor_mutex);
  const std::size_t n = anchored_dir.size();
  if (anchored_fd >= 0 && path.size() > n + 1 && path.compare(0, n, anchored_dir) == 0 &&
      path[n] == '/')
    return {anchored_fd, path.substr(n + 1)};
  return {AT_FDCWD, path};
}

int unlink_at(const std::string& path) {
  const At a = at(path);
  return ::unlinkat(a.fd, a.name.c_str(), 0);
}

} // namespace

void anchor_folder(const std::string& dir, int dirfd) {
  const std::lock_guard<std::mutex> lock(anchor_mutex);
  anchored_dir = dirfd >= 0 ? dir : std::string();
  anchored_fd = dirfd;
}

void remove_file(const std::string& path) {
  unlink_at(path);
}

void make_folder(const std::string& path) {
  const At a = at(path);
  if (::mkdirat(a.fd, a.name.c_str(), 0755) != 0 && errno != EEXIST)
    throw OutputError(fmt::format("{}: cannot create: {}", path, std::strerror(errno)));
}

void write_file_atomic(const std::string& path, std::string_view content) {
  write_file_atomic(path, {content});
}

void write_file_atomic(const std::string& path, std::initializer_list<std::string_view> parts) {
  AtomicFile file(path);
  for (const std::string_view content : parts)
    file.write(content);
  file.commit();
}

std::string create_new_file(const std::string& path, int& fd, unsigned mode) {
  constexpr int tries = 100;
  for (int k = 0; k < tries; ++k) {
    const std::string name = k == 0 ? path : fmt::format("{}.{}", path, k);
    const At a = at(name);
    fd = ::openat(a.fd, a.name.c_str(), O_RDWR | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, mode);
    if (fd >= 0) return name;
    if (errno != EEXIST) break;
  }
  throw OutputError(
      fmt::format("{}: cannot write: {}", path,
                  errno == EEXIST ? "every temporary name is taken" : std::strerror(errno)));
}

AtomicFile::AtomicFile(std::string path, unsigned mode) : path_(std::move(path)) {
  try {
    tmp_ = create_new_file(path_ + ".tmp", fd_, mode);
  } catch (const OutputError& e) { // named by the file it stands for
    const std::string what = e.what();
    throw OutputError(path_ + what.substr(what.find(": cannot write")));
  }
}

AtomicFile::~AtomicFile() {
  if (fd_ >= 0) {
    ::close(fd_);
    unlink_at(tmp_);
  }
}

void AtomicFile::fail(const std::string& what) {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  unlink_at(tmp_);
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
    unlink_at(tmp_);
    throw OutputError(fmt::format("{}: cannot flush: {}", path_, std::strerror(err)));
  }
  const At from = at(tmp_), to = at(path_);
  if (::renameat(from.fd, from.name.c_str(), to.fd, to.name.c_str()) != 0) {
    const int err = errno;
    unlink_at(tmp_);
    throw OutputError(fmt::format("{}: cannot rename into place: {}", path_, std::strerror(err)));
  }
  // Make the rename itself durable: a crash after this leaves the new file, never none.
  const auto slash = to.name.find_last_of('/');
  const std::string dir = slash == std::string::npos ? "." : to.name.substr(0, slash + 1);
  if (const int dfd = ::openat(to.fd, dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC); dfd >= 0) {
    ::fsync(dfd);
    ::close(dfd);
  }
}

} // namespace talus
