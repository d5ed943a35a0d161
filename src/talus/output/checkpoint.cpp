#include "talus/output/checkpoint.hpp"

#include <algorithm>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>

namespace talus {

namespace {

constexpr char magic[8] = {'T', 'A', 'L', 'U', 'S', 'C', 'K', 'P'};
// 10: optional particle arrays (APIC's affine velocities); 9: frames rounded to output.field_bits
// (an older folder's frames are exact); 8: fixed bodies written once (an older folder's frames are
// whole); 7: run-up probes; 6: waves.csv; 5: contact nodes
constexpr std::uint32_t format_version = 10;

constexpr std::uint64_t fnv_basis = 14695981039346656037ull;
std::uint64_t fnv1a(std::string_view s, std::uint64_t h = fnv_basis) {
  for (const char c : s)
    h = (h ^ static_cast<unsigned char>(c)) * 1099511628211ull;
  return h;
}

template <class T>
void append(std::string& out, const T& v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof(T));
}

} // namespace

LoadArchive::LoadArchive(const CheckpointPayload& payload)
    : base_(payload.offset), size_(payload.size), source_(payload.path) {
  in_.emplace(payload.path, std::ios::binary);
  if (!*in_) throw CheckpointError(fmt::format("{}: cannot open the checkpoint", payload.path));
}

std::size_t LoadArchive::count(std::size_t element_size) {
  std::uint64_t n = 0;
  io(n);
  if (n > (size_ - pos_) / element_size)
    throw CheckpointError(
        fmt::format("{}: corrupt checkpoint (a length of {} at byte {})", source_, n, pos_));
  return static_cast<std::size_t>(n);
}

void LoadArchive::raw(void* p, std::size_t n) {
  if (n > size_ - pos_)
    throw CheckpointError(fmt::format("{}: corrupt checkpoint (ends at byte {})", source_, pos_));
  read_at(pos_, static_cast<char*>(p), n);
  pos_ += n;
}

void LoadArchive::read_at(std::size_t at, char* out, std::size_t n) {
  if (n == 0) return;
  if (!in_) {
    std::memcpy(out, data_.data() + at, n);
    return;
  }
  in_->seekg(static_cast<std::streamoff>(base_ + at));
  if (!in_->read(out, static_cast<std::streamsize>(n)))
    throw CheckpointError(fmt::format("{}: cannot read the checkpoint at byte {}", source_, at));
}

void LoadArchive::scan(std::size_t at, std::size_t width, std::size_t n, const Chunk& f) {
  const std::size_t per_chunk = std::max<std::size_t>(chunk_bytes_ / width, 1);
  for (std::size_t first = 0; first < n; first += per_chunk) {
    const std::size_t count = std::min(per_chunk, n - first);
    chunk_.resize(count * width);
    read_at(at + first * width, chunk_.data(), count * width);
    f(first, chunk_.data(), count);
  }
}

// Rows close together are read as one span of up to chunk_bytes_; a gap wider than that is
// skipped. A restart's memory is its share of the particles, not the file's.
void LoadArchive::read_rows(std::size_t at, std::size_t width,
                            const std::vector<std::uint32_t>& rows, char* out) {
  const std::size_t per_chunk = std::max<std::size_t>(chunk_bytes_ / width, 1);
  for (std::size_t i = 0; i < rows.size();) {
    const std::size_t first = rows[i];
    std::size_t j = i;
    while (j < rows.size() && rows[j] - first < per_chunk)
      ++j;
    const std::size_t span = rows[j - 1] - first + 1;
    chunk_.resize(span * width);
    read_at(at + first * width, chunk_.data(), span * width);
    for (; i < j; ++i)
      std::memcpy(out + i * width, chunk_.data() + (rows[i] - first) * width, width);
  }
}

CheckpointFile::CheckpointFile(const std::string& path, std::uint64_t payload_size)
    : path_(path), size_(payload_size), sum_(fnv_basis) {
  try {
    file_.emplace(path);
    std::string head(magic, sizeof magic);
    append(head, format_version);
    append(head, payload_size);
    file_->write(head);
  } catch (const OutputError& e) {
    error_ = e.what();
  }
}

void CheckpointFile::write(const char* data, std::size_t n) {
  written_ += n;
  if (!error_.empty()) return;
  try {
    sum_ = fnv1a(std::string_view(data, n), sum_);
    file_->write(std::string_view(data, n));
  } catch (const OutputError& e) {
    error_ = e.what();
  }
}

void CheckpointFile::finish() {
  if (!error_.empty()) throw OutputError(error_);
  if (written_ != size_)
    throw OutputError(fmt::format("{}: internal error: {} payload bytes written, {} counted", path_,
                                  written_, size_));
  std::string tail;
  append(tail, sum_);
  file_->write(tail);
  file_->commit();
}

void write_checkpoint_file(const std::string& path, const std::string& payload) {
  CheckpointFile file(path, payload.size());
  file.write(payload.data(), payload.size());
  file.finish();
}

CheckpointPayload open_checkpoint(const std::string& path, bool checksum) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw CheckpointError(fmt::format("{}: cannot open the checkpoint", path));
  const auto file_size = static_cast<std::uint64_t>(in.tellg());
  in.seekg(0);
  constexpr std::size_t header = sizeof magic + sizeof(std::uint32_t) + sizeof(std::uint64_t);
  char head[header] = {};
  if (file_size < header + sizeof(std::uint64_t) || !in.read(head, header) ||
      std::memcmp(head, magic, sizeof magic) != 0)
    throw CheckpointError(fmt::format("{}: not a Talus checkpoint", path));
  std::uint32_t version = 0;
  std::uint64_t size = 0, sum = 0;
  std::memcpy(&version, head + sizeof magic, sizeof version);
  std::memcpy(&size, head + sizeof magic + sizeof version, sizeof size);
  if (version != format_version)
    throw CheckpointError(fmt::format("{}: checkpoint format {}, this Talus reads {}", path,
                                      version, format_version));
  if (size != file_size - header - sizeof sum)
    throw CheckpointError(fmt::format("{}: truncated checkpoint ({} of {} bytes)", path, file_size,
                                      size + header + sizeof sum));
  if (!checksum) return {path, header, size};
  // The checksum, over the payload in chunks.
  std::vector<char> chunk(std::min<std::uint64_t>(size, std::uint64_t{16} << 20));
  std::uint64_t h = fnv_basis;
  for (std::uint64_t done = 0; done < size;) {
    const std::size_t n =
        static_cast<std::size_t>(std::min<std::uint64_t>(chunk.size(), size - done));
    if (!in.read(chunk.data(), static_cast<std::streamsize>(n)))
      throw CheckpointError(fmt::format("{}: cannot read the checkpoint", path));
    h = fnv1a(std::string_view(chunk.data(), n), h);
    done += n;
  }
  if (!in.read(reinterpret_cast<char*>(&sum), sizeof sum))
    throw CheckpointError(fmt::format("{}: cannot read the checkpoint", path));
  if (h != sum)
    throw CheckpointError(fmt::format("{}: corrupt checkpoint (checksum mismatch)", path));
  return {path, header, size};
}

std::string read_checkpoint_file(const std::string& path) {
  const CheckpointPayload payload = open_checkpoint(path);
  std::string bytes(payload.size, '\0');
  std::ifstream in(path, std::ios::binary);
  in.seekg(static_cast<std::streamoff>(payload.offset));
  if (!in.read(bytes.data(), static_cast<std::streamsize>(bytes.size())))
    throw CheckpointError(fmt::format("{}: cannot read the checkpoint", path));
  return bytes;
}

std::string checkpoint_path(const std::string& run_dir, std::int64_t step) {
  return fmt::format("{}/checkpoints/step_{:010d}.ckpt", run_dir, step);
}

std::vector<std::string> list_checkpoints(const std::string& run_dir) {
  namespace fs = std::filesystem;
  std::vector<std::string> found;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(run_dir + "/checkpoints", ec)) {
    // Only regular files talus could have written: a folder, link or FIFO named like a
    // checkpoint is neither read (a FIFO would block) nor counted or deleted by pruning.
    const std::string name = e.path().filename().string();
    const std::string digits = name.size() == 20 ? name.substr(5, 10) : std::string();
    if (name.starts_with("step_") && name.ends_with(".ckpt") && !digits.empty() &&
        digits.find_first_not_of("0123456789") == std::string::npos &&
        e.symlink_status(ec).type() == fs::file_type::regular)
      found.push_back(e.path().string());
  }
  std::sort(found.rbegin(), found.rend()); // zero-padded step numbers: newest first
  return found;
}

void prune_checkpoints(const std::string& run_dir, int keep) {
  const auto all = list_checkpoints(run_dir);
  for (std::size_t i = static_cast<std::size_t>(std::max(keep, 1)); i < all.size(); ++i) {
    remove_file(all[i]);
  }
}

} // namespace talus
