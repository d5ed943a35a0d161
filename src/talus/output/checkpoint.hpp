// Checkpoints: the whole state of a run (particles, clocks, the run folder's tables, the results
// being tracked) as one binary file, so that a restarted run continues bitwise as if it had never
// stopped. Each class with state has one `serialize(Archive&)` that both saves and loads, so the
// two directions cannot drift apart.
//
// File layout: "TALUSCKP", format version (u32), payload size (u64), payload, FNV-1a 64 of the
// payload. A truncated or corrupted file fails its checksum and is skipped for the older one.
#pragma once

#include "talus/output/files.hpp"

#include <Eigen/Core>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

namespace talus {

class CheckpointError : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

// Types stored as their bytes: trivially copyable ones and Eigen's fixed-size matrices.
template <class T>
constexpr bool stored_raw = std::is_trivially_copyable_v<T>;
template <class S, int R, int C, int O, int MR, int MC>
constexpr bool stored_raw<Eigen::Matrix<S, R, C, O, MR, MC>> = (R > 0 && C > 0);

// Writes values into a byte buffer; or, made with Mode::count, only counts their bytes (so that
// the buffer can be reserved at once: growing it would copy the whole state).
class SaveArchive {
public:
  static constexpr bool loading = false;
  enum class Mode { save, count };
  explicit SaveArchive(Mode mode = Mode::save) : counting_(mode == Mode::count) {}

  template <class T>
  requires stored_raw<T>
  void io(T& v) { raw(&v, sizeof(T)); }
  void io(std::string& s) {
    std::uint64_t n = s.size();
    io(n);
    raw(s.data(), n);
  }
  template <class T>
  void io(std::vector<T>& v) {
    std::uint64_t n = v.size();
    io(n);
    if constexpr (stored_raw<T>)
      raw(v.data(), n * sizeof(T));
    else
      for (T& x : v)
        io(x);
  }
  template <class A, class B>
  void io(std::pair<A, B>& p) {
    io(p.first), io(p.second);
  }

  std::string& bytes() { return buf_; }
  std::size_t size() const { return counting_ ? counted_ : buf_.size(); }
  void reserve(std::size_t n) { buf_.reserve(n); }

private:
  void raw(const void* p, std::size_t n) {
    if (counting_)
      counted_ += n;
    else
      buf_.append(static_cast<const char*>(p), n);
  }
  std::string buf_;
  bool counting_ = false;
  std::size_t counted_ = 0;
};

// Reads values back; any read past the end throws CheckpointError.
class LoadArchive {
public:
  static constexpr bool loading = true;
  explicit LoadArchive(std::string_view bytes, std::string source)
      : data_(bytes), source_(std::move(source)) {}

  template <class T>
  requires stored_raw<T>
  void io(T& v) { raw(&v, sizeof(T)); }
  void io(std::string& s) {
    s.resize(count(1));
    raw(s.data(), s.size());
  }
  template <class T>
  void io(std::vector<T>& v) {
    v.resize(count(stored_raw<T> ? sizeof(T) : 1));
    if constexpr (stored_raw<T>)
      raw(v.data(), v.size() * sizeof(T));
    else
      for (T& x : v)
        io(x);
  }
  template <class A, class B>
  void io(std::pair<A, B>& p) {
    io(p.first), io(p.second);
  }
  bool done() const { return pos_ == data_.size(); }

private:
  std::size_t count(std::size_t element_size);
  void raw(void* p, std::size_t n);
  std::string_view data_;
  std::size_t pos_ = 0;
  std::string source_;
};

// Requires a loaded value to equal the current one (e.g. the dimension or a particle count).
template <class Ar, class T>
void io_expect(Ar& ar, const T& current, const char* what, const std::string& source) {
  T v = current;
  ar.io(v);
  if (Ar::loading && !(v == current))
    throw CheckpointError(source + ": the checkpoint's " + what + " differs from the case's");
}

// Writes `payload` as a checkpoint file (atomically: temporary, fsync, rename).
void write_checkpoint_file(const std::string& path, const std::string& payload);
// Reads and verifies a checkpoint file; throws CheckpointError if it is not a complete one.
std::string read_checkpoint_file(const std::string& path);

// The checkpoints of a run folder (RUN/checkpoints/step_NNNNNNNNNN.ckpt), newest first.
std::vector<std::string> list_checkpoints(const std::string& run_dir);
// Path of the checkpoint of step `step` in a run folder.
std::string checkpoint_path(const std::string& run_dir, std::int64_t step);
// Deletes all but the newest `keep` checkpoints.
void prune_checkpoints(const std::string& run_dir, int keep);

} // namespace talus
