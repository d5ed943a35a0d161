// Checkpoints: the whole state of a run (particles, clocks, the run folder's tables, the results
// being tracked) as one binary file, so that a restarted run continues bitwise as if it had never
// stopped. Each class with state has one `serialize(Archive&)` that both saves and loads, so the
// two directions cannot drift apart.
//
// File layout: "TALUSCKP", format version (u32), payload size (u64), payload, FNV-1a 64 of the
// payload. A truncated or corrupted file fails its checksum and is skipped for the older one.
#pragma once

#include "talus/core/particles.hpp"
#include "talus/output/files.hpp"
#include "talus/output/particle_order.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
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

// Writes values into a byte buffer or, with a sink, hands them on as they come; made with
// Mode::count, only counts their bytes (so that a buffer or a file's header can be sized first).
// On several processes the particle arrays are the whole state's, gathered in one process's
// order (set_order): rank 0 saves or counts, the others only send (Mode::send).
class SaveArchive {
public:
  static constexpr bool loading = false;
  enum class Mode { save, count, send };
  using Sink = std::function<void(const char* data, std::size_t n)>;
  explicit SaveArchive(Mode mode = Mode::save) : mode_(mode) {}
  void set_sink(Sink sink) { sink_ = std::move(sink); }
  void set_order(ParticleOrder* order, std::vector<std::size_t> body_begin) {
    order_ = order, body_begin_ = std::move(body_begin);
  }

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
  // The body ranges, then every particle array (LoadArchive reads them with io()).
  // `optional_in_use` says whether the case uses the optional arrays (APIC's C): on several
  // processes a share may be empty either way, and the gather is collective.
  template <int D>
  void particles(Particles<D>& P, bool optional_in_use) {
    if (!order_) {
      io(P.body_begin);
      P.for_each_array([&](auto& a) { io(a); });
      P.for_each_optional([&](auto& a) { io(a); });
      return;
    }
    io(body_begin_);
    // One array of the whole state: its length, then its values in one process's order.
    auto gathered = [&](auto& a, std::uint64_t n) {
      using T = typename std::decay_t<decltype(a)>::value_type;
      io(n);
      if (n == 0) return;
      if (mode_ == Mode::count) {
        counted_ += n * sizeof(T);
        return;
      }
      order_->gather(
          sizeof(T), [&](std::size_t p, char* out) { std::memcpy(out, &a[p], sizeof(T)); },
          [&](const char* data, std::size_t count) { raw(data, count * sizeof(T)); });
    };
    P.for_each_array([&](auto& a) { gathered(a, order_->total()); });
    P.for_each_optional([&](auto& a) {
      if (!optional_in_use && !a.empty())
        throw CheckpointError("an optional particle array the case does not use");
      gathered(a, optional_in_use ? order_->total() : 0);
    });
  }

  std::string& bytes() { return buf_; }
  std::size_t size() const { return mode_ == Mode::count ? counted_ : buf_.size(); }
  void reserve(std::size_t n) { buf_.reserve(n); }

private:
  void raw(const void* p, std::size_t n) {
    if (mode_ == Mode::count)
      counted_ += n;
    else if (mode_ == Mode::send)
      return;
    else if (sink_)
      sink_(static_cast<const char*>(p), n);
    else
      buf_.append(static_cast<const char*>(p), n);
  }
  std::string buf_;
  Mode mode_;
  std::size_t counted_ = 0;
  Sink sink_;
  ParticleOrder* order_ = nullptr;
  std::vector<std::size_t> body_begin_; // the whole state's, with order_
};

// A checkpoint file's payload: where it starts and its size (open_checkpoint verified it).
struct CheckpointPayload {
  std::string path;
  std::uint64_t offset = 0, size = 0;
};

// Reads values back, from memory or from a checkpoint file as they are needed (the payload is
// never held whole); any read past the end throws CheckpointError.
class LoadArchive {
public:
  static constexpr bool loading = true;
  LoadArchive(std::string_view bytes, std::string source)
      : data_(bytes), size_(bytes.size()), source_(std::move(source)) {}
  explicit LoadArchive(const CheckpointPayload& payload);

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
  bool done() const { return pos_ == size_; }

  // On several processes a restart keeps one process's share of the particles: `choose` is
  // handed the particle count and a scan of every position (chunks of raw Vec<D>: the first
  // particle's row, the bytes, the count) and returns the rows to keep, ascending.
  using Chunk = std::function<void(std::size_t first, const char* data, std::size_t count)>;
  using Scan = std::function<void(const Chunk&)>;
  using Choose = std::function<std::vector<std::uint32_t>(std::size_t total, const Scan& x)>;
  void set_choose(Choose choose) { choose_ = std::move(choose); }
  // The most bytes a scan or a read of chosen rows holds at once (16 MiB; tests set less).
  void set_chunk_bytes(std::size_t n) { chunk_bytes_ = std::max<std::size_t>(n, 1); }

  // The particle arrays SaveArchive::particles wrote for the whole state's body ranges
  // `body_begin`: all of them, or the rows `choose` keeps (P's body ranges are then theirs).
  // Returns whether the optional arrays (APIC's C) were stored: on several processes a slab
  // may keep no rows, so P's own arrays cannot say.
  template <int D>
  bool particles(Particles<D>& P, const std::vector<std::size_t>& body_begin) {
    const std::size_t n = body_begin.back();
    constexpr std::size_t absent = std::numeric_limits<std::size_t>::max();
    std::vector<std::size_t> at; // each array's first byte (absent: an optional one not stored)
    // One array of k entries: read whole, or its place kept for the chosen rows.
    auto take = [&](auto& a, std::uint64_t k, bool optional) {
      using T = typename std::decay_t<decltype(a)>::value_type;
      at.push_back(optional && k == 0 ? absent : pos_);
      a.resize(choose_ ? 0 : k);
      if (choose_)
        pos_ += k * sizeof(T);
      else
        raw(a.data(), k * sizeof(T));
    };
    P.for_each_array([&](auto& a) {
      using T = typename std::decay_t<decltype(a)>::value_type;
      if (count(sizeof(T)) != n)
        throw CheckpointError(source_ + ": corrupt checkpoint (particle array length)");
      take(a, n, false);
    });
    bool optional_stored = false;
    P.for_each_optional([&](auto& a) { // empty, or one entry per particle
      using T = typename std::decay_t<decltype(a)>::value_type;
      const std::uint64_t k = count(sizeof(T));
      if (k != 0 && k != n)
        throw CheckpointError(source_ + ": corrupt checkpoint (particle array length)");
      optional_stored = optional_stored || k != 0;
      take(a, k, true);
    });
    P.body_begin = body_begin;
    if (!choose_) return optional_stored;
    // The positions are the first array (Particles::arrays).
    const std::vector<std::uint32_t> rows =
        choose_(n, [&](const Chunk& f) { scan(at[0], sizeof(Vec<D>), n, f); });
    std::size_t k = 0;
    auto read_chosen = [&](auto& a) {
      using T = typename std::decay_t<decltype(a)>::value_type;
      if (at[k] == absent) return void(++k);
      a.resize(rows.size());
      read_rows(at[k++], sizeof(T), rows, reinterpret_cast<char*>(a.data()));
    };
    P.for_each_array(read_chosen);
    P.for_each_optional(read_chosen);
    for (std::size_t& b : P.body_begin)
      b = static_cast<std::size_t>(std::lower_bound(rows.begin(), rows.end(), b) - rows.begin());
    return optional_stored;
  }

private:
  std::size_t count(std::size_t element_size);
  void raw(void* p, std::size_t n);
  void read_at(std::size_t at, char* out, std::size_t n); // n bytes from byte `at`
  // n elements of `width` bytes from byte `at`, to f in chunks.
  void scan(std::size_t at, std::size_t width, std::size_t n, const Chunk& f);
  // The elements `rows` (ascending) of an array of `width`-byte elements at byte `at`, to out.
  void read_rows(std::size_t at, std::size_t width, const std::vector<std::uint32_t>& rows,
                 char* out);
  std::string_view data_;           // in memory
  std::optional<std::ifstream> in_; // or the file, from byte `base_`
  std::uint64_t base_ = 0, size_ = 0;
  std::size_t pos_ = 0;
  std::string source_;
  Choose choose_;
  std::size_t chunk_bytes_ = std::size_t{16} << 20;
  std::vector<char> chunk_;
};

// Requires a loaded value to equal the current one (e.g. the dimension or a particle count).
template <class Ar, class T>
void io_expect(Ar& ar, const T& current, const char* what, const std::string& source) {
  T v = current;
  ar.io(v);
  if (Ar::loading && !(v == current))
    throw CheckpointError(source + ": the checkpoint's " + what + " differs from the case's");
}

// A checkpoint file written as its payload comes (atomically: temporary, fsync, rename), the
// payload's size given first. A write error is kept until finish() throws it (OutputError), so
// that a writer on rank 0 still takes part in the gathers that feed it.
class CheckpointFile {
public:
  CheckpointFile(const std::string& path, std::uint64_t payload_size);
  void write(const char* data, std::size_t n);
  void finish(); // the checksum, then into place; throws the first error

private:
  std::optional<AtomicFile> file_;
  std::string path_, error_;
  std::uint64_t size_ = 0, written_ = 0, sum_;
};

// Writes `payload` as a checkpoint file.
void write_checkpoint_file(const std::string& path, const std::string& payload);
// A checkpoint file's payload, its header and size verified and, with `checksum`, its checksum
// (one streaming pass); throws CheckpointError if it is not a complete one.
CheckpointPayload open_checkpoint(const std::string& path, bool checksum = true);
// Reads and verifies a checkpoint file's payload whole.
std::string read_checkpoint_file(const std::string& path);

// The checkpoints of a run folder (RUN/checkpoints/step_NNNNNNNNNN.ckpt), newest first.
std::vector<std::string> list_checkpoints(const std::string& run_dir);
// Path of the checkpoint of step `step` in a run folder.
std::string checkpoint_path(const std::string& run_dir, std::int64_t step);
// Deletes all but the newest `keep` checkpoints.
void prune_checkpoints(const std::string& run_dir, int keep);

} // namespace talus
