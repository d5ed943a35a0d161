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

std::string create_new_file(const std::string& path, int& fd, unsigned mode) {
  constexpr int tries = 100;
  for (int k = 0; k < tries; ++k) {
    const std::string name = k == 0 ? path : fmt::format("{}.{}", path, k);
    fd = ::open(name.c_str(), O_RDWR | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, mode);
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

} // namespace talus
