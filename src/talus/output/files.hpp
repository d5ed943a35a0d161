// Writing files so that no reader ever sees half of one: write a temporary beside the target,
// flush it to disk, then rename it over the target.
#pragma once

#include <initializer_list>
#include <stdexcept>
#include <string>
#include <string_view>

namespace talus {

class OutputError : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

// A run folder that a run must not write into (another run's, or not a run folder at all).
class RunFolderError : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

// The run folder held open: every file operation below on a path under `dir` (dir + "/...")
// goes through `dirfd`, into the folder the run took, even after that path was renamed, removed
// or replaced by another folder (which then receives nothing). One folder at a time; -1 lets
// it go.
void anchor_folder(const std::string& dir, int dirfd);
// Removes a file (never a folder, never through a link's target), quietly if it is not there.
void remove_file(const std::string& path);
// Creates the folder `path` if it is not there; throws OutputError naming it otherwise.
void make_folder(const std::string& path);

// Creates a new file for writing at `path` or, if that name is taken (a temporary left by a
// killed run, or a link someone planted), at path.1, path.2, ...: exclusively, never through a
// link. Returns the name used and sets fd; throws OutputError naming `path` if none can be made.
std::string create_new_file(const std::string& path, int& fd, unsigned mode = 0644);

// A file written in pieces that replaces `path` only at commit(): until then its content is in
// a new temporary beside it (path + ".tmp", create_new_file), which the destructor removes if
// commit() was not reached. `mode`: the file's permissions (less the umask). Errors throw
// OutputError naming the file and the reason.
class AtomicFile {
public:
  explicit AtomicFile(std::string path, unsigned mode = 0644);
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  ~AtomicFile();
  void write(std::string_view content);
  void commit(); // flushes to disk, renames into place, makes the rename durable

private:
  [[noreturn]] void fail(const std::string& what); // removes the temporary, throws
  std::string path_, tmp_;
  int fd_ = -1;
};

// Replaces `path` with `content` atomically. Throws OutputError naming the file and the reason.
void write_file_atomic(const std::string& path, std::string_view content);
// The same with the parts written one after another (no copy of them joined).
void write_file_atomic(const std::string& path, std::initializer_list<std::string_view> parts);

} // namespace talus
