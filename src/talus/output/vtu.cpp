#include "talus/output/vtu.hpp"

#include "talus/output/files.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fcntl.h>
#include <fmt/format.h>
#include <lzma.h>
#include <stdexcept>
#include <unistd.h>
#include <zlib.h>

namespace talus {

bool VtuFields::wants(const std::string& f) const {
  return names.empty() || std::find(names.begin(), names.end(), f) != names.end();
}

namespace {

// The appended block: in memory, or in a scratch file beside the frame (unlinked as soon as it
// is open, so that nothing is left behind) for a frame written chunk by chunk. A scratch file's
// first error is kept, and reported once the arrays are written.
class Appended {
public:
  Appended() = default;
  explicit Appended(const std::string& scratch) : to_file_(true) {
    try {
      remove_file(create_new_file(scratch, fd_, 0600)); // nothing left behind
    } catch (const OutputError& e) {
      error_ = e.what();
    }
  }
  Appended(const Appended&) = delete;
  Appended& operator=(const Appended&) = delete;
  ~Appended() {
    if (fd_ >= 0) ::close(fd_);
  }
  std::size_t size() const { return size_; }
  const std::string& memory() const { return mem_; }
  const std::string& error() const { return error_; }
  void write(const void* data, std::size_t n) {
    write_at(size_, data, n);
    size_ += n;
  }
  void write_at(std::size_t at, const void* data, std::size_t n) {
    if (!to_file_) {
      if (mem_.size() < at + n) mem_.resize(at + n);
      std::memcpy(mem_.data() + at, data, n);
      return;
    }
    for (std::size_t done = 0; done < n && error_.empty();) {
      const ssize_t w = ::pwrite(fd_, static_cast<const char*>(data) + done, n - done,
                                 static_cast<off_t>(at + done));
      if (w < 0 && errno == EINTR) continue;
      if (w <= 0)
        error_ = fmt::format("write failed: {}", std::strerror(w < 0 ? errno : ENOSPC));
      else
        done += static_cast<std::size_t>(w);
    }
  }
  void copy_to(AtomicFile& out) const {
    std::string buf(std::size_t{8} << 20, '\0');
    for (std::size_t at = 0; at < size_;) {
      const ssize_t r =
          ::pread(fd_, buf.data(), std::min(buf.size(), size_ - at), static_cast<off_t>(at));
      if (r < 0 && errno == EINTR) continue;
      if (r <= 0)
        throw OutputError(fmt::format("reading the frame's scratch file: {}",
                                      std::strerror(r < 0 ? errno : EIO)));
      out.write(std::string_view(buf.data(), static_cast<std::size_t>(r)));
      at += static_cast<std::size_t>(r);
    }
  }

private:
  bool to_file_ = false;
  std::string mem_, error_;
  int fd_ = -1;
  std::size_t size_ = 0;
};

// A VTK XML UnstructuredGrid of vertices built in two parts: the XML, where each DataArray gives
// its offset into the appended block, and the appended block of raw binary arrays, each cut into
// blocks of 256 KiB compressed one by one as VTK's vtkLZMADataCompressor (an xz stream, LZMA2 at
// preset 0) or vtkZLibDataCompressor (zlib at level 1) reads them: a UInt64 header (number of
// blocks, block size, size of the last block, then each block's compressed size) followed by the
// blocks. An array's bytes may arrive in pieces (begin, append..., end); up to `batch` blocks are
// staged and compressed at once, in parallel, each on its own, so that the bytes do not depend on
// the thread count.
class VtuBuilder {
public:
  VtuBuilder(std::size_t n, Appended& out, FrameCompression compression)
      : out_(out), compression_(compression) {
    xml_ = fmt::format("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" "
                       "version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\" "
                       "compressor=\"{}\">\n  <UnstructuredGrid>\n",
                       compression == FrameCompression::lzma ? "vtkLZMADataCompressor"
                                                             : "vtkZLibDataCompressor");
    xml_ += fmt::format("    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", n, n);
    xml_ += "      <Points>\n";
  }

  void xml(const char* text) { xml_ += text; }

  void begin(const char* type, const std::string& name, int components, std::size_t bytes) {
    xml_ += fmt::format("        <DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\" "
                        "format=\"appended\" offset=\"{}\"/>\n",
                        type, name, components, out_.size());
    const std::size_t blocks = (bytes + block - 1) / block;
    header_ = {blocks, block, blocks ? bytes - (blocks - 1) * block : 0};
    header_at_ = out_.size();
    const std::vector<std::uint64_t> room(3 + blocks, 0); // the header, written at end()
    out_.write(room.data(), room.size() * sizeof(std::uint64_t));
    body_ = 0;
    stage_.clear();
  }
  void append(const void* data, std::size_t bytes) {
    const char* c = static_cast<const char*>(data);
    while (bytes > 0) {
      const std::size_t take = std::min(bytes, batch * block - stage_.size());
      stage_.insert(stage_.end(), c, c + take);
      c += take, bytes -= take;
      if (stage_.size() == batch * block) flush();
    }
  }
  void end() {
    if (!stage_.empty()) flush();
    // Bytes after the last block's stream (readers stop at the stream's end) make every
    // array's offset but the first 1 mod 4: meshio 5 looks arrays up by offset while it
    // rewrites the offsets to multiples of 4, and an offset equal to a rewritten one made it
    // read the wrong array. After an xz stream they are 0xFF, which no LZMA decoder takes for
    // the start of a further stream (Python's lzma, which meshio uses, looks for one and stops
    // at a byte it cannot start with; a zero byte it would wait on).
    const std::size_t size = header_.size() * sizeof(std::uint64_t) + body_;
    const std::size_t want = header_at_ == 0 ? 1 : 0; // this array's size mod 4
    if (header_[0] > 0) {
      const std::size_t pad = (want + 4 - size % 4) % 4;
      const char fill = compression_ == FrameCompression::lzma ? '\xff' : '\0';
      const char bytes[4] = {fill, fill, fill, fill};
      out_.write(bytes, pad);
      header_.back() += pad;
    }
    out_.write_at(header_at_, header_.data(), header_.size() * sizeof(std::uint64_t));
  }
  template <class T>
  void array(const char* type, const std::string& name, int components,
             const std::vector<T>& values) {
    begin(type, name, components, values.size() * sizeof(T));
    append(values.data(), values.size() * sizeof(T));
    end();
  }

  std::string head() const {
    return xml_ + "      </PointData>\n    </Piece>\n  </UnstructuredGrid>\n"
                  "  <AppendedData encoding=\"raw\">\n   _";
  }
  static constexpr const char* tail = "\n  </AppendedData>\n</VTKFile>\n";
  const std::string& error() const { return error_; }

private:
  static constexpr std::size_t block = 1 << 18; // uncompressed bytes per block
  static constexpr std::size_t batch = 16;      // blocks staged and compressed together
  // The staged bytes' blocks compressed in parallel, then written in order. A failure is kept
  // (error()) and the frame's remaining blocks are dropped: the writer reports it once every
  // array is gathered, so that on several processes none is left waiting in a gather.
  void flush() {
    const std::size_t count = (stage_.size() + block - 1) / block;
    if (z_.size() < count) z_.resize(count);
    bool failed = false;
#pragma omp parallel for schedule(static, 1) reduction(|| : failed) if (count > 1)
    for (std::size_t i = 0; i < count; ++i) {
      const std::size_t at = i * block, n = std::min(block, stage_.size() - at);
      bool ok = false;
      try {
        ok = compress_block(stage_.data() + at, n, z_[i]);
      } catch (...) { // out of memory: no exception may leave the parallel region
      }
      failed = !ok || failed;
    }
    if (failed && error_.empty())
      error_ = compression_ == FrameCompression::lzma ? "LZMA compression failed"
                                                      : "zlib compression failed";
    if (!error_.empty()) {
      stage_.clear();
      return;
    }
    for (std::size_t i = 0; i < count; ++i) {
      out_.write(z_[i].data(), z_[i].size());
      header_.push_back(z_[i].size());
      body_ += z_[i].size();
    }
    stage_.clear();
  }
  // One block as its own xz stream (LZMA2 preset 0, a CRC32 check: what VTK's LZMA compressor
  // writes, at its fastest preset) or zlib stream (level 1).
  bool compress_block(const char* in, std::size_t n, std::vector<char>& z) const {
    const auto* bytes = reinterpret_cast<const std::uint8_t*>(in);
    if (compression_ == FrameCompression::lzma) {
      z.resize(lzma_stream_buffer_bound(n));
      std::size_t size = 0;
      if (lzma_easy_buffer_encode(0, LZMA_CHECK_CRC32, nullptr, bytes, n,
                                  reinterpret_cast<std::uint8_t*>(z.data()), &size,
                                  z.size()) != LZMA_OK)
        return false;
      z.resize(size);
      return true;
    }
    uLongf size = compressBound(n);
    z.resize(size);
    if (compress2(reinterpret_cast<Bytef*>(z.data()), &size, bytes, n, Z_BEST_SPEED) != Z_OK)
      return false;
    z.resize(size);
    return true;
  }
  Appended& out_;
  FrameCompression compression_;
  std::string xml_;
  std::vector<std::uint64_t> header_;
  std::size_t header_at_ = 0, body_ = 0;
  std::vector<char> stage_;
  std::vector<std::vector<char>> z_; // each staged block's compressed bytes
  std::string error_;                // the first compression failure
};

// The particle arrays, each gathered in `order`'s order (out: where order.receives()).
template <int D>
void particle_arrays(VtuBuilder* out, const Particles<D>& P, const std::vector<int>& body_material,
                     const VtuFields& fields, const std::vector<ScalarField>& extra,
                     ParticleOrder& order, const ParticleOrder::Spans& spans) {
  const std::size_t n = ParticleOrder::count(spans);
  auto column = [&](const char* type, const std::string& name, int components, std::size_t width,
                    const ParticleOrder::Fill& fill) {
    if (out) out->begin(type, name, components, width * n);
    order.gather(
        width, fill, [&](const char* data, std::size_t count) { out->append(data, count * width); },
        spans);
    if (out) out->end();
  };
  // Doubles per particle as Float64 or, rounded to nearest, as Float32.
  auto write_reals = [&](const std::string& name, int components, bool f64, auto value) {
    if (f64)
      column("Float64", name, components, 8 * components, [&](std::size_t p, char* o) {
        for (int k = 0; k < components; ++k) {
          const double v = value(p, k);
          std::memcpy(o + 8 * k, &v, 8);
        }
      });
    else
      column("Float32", name, components, 4 * components, [&](std::size_t p, char* o) {
        for (int k = 0; k < components; ++k) {
          const float v = static_cast<float>(value(p, k));
          std::memcpy(o + 4 * k, &v, 4);
        }
      });
  };
  // v rounded to the nearest multiple of the power of two q (ties to even): exact arithmetic, so
  // every process and thread count writes the same bits; |error| <= q / 2.
  auto quantise = [](double v, double q) {
    return q > 0.0 && std::isfinite(v) ? std::nearbyint(v / q) * q : v;
  };
  // A field's values per body kept to 2^-field_bits of the body's largest finite magnitude m_b:
  // q_b = 2^(floor(log2 m_b) - field_bits), so m_b / q_b < 2^(field_bits + 1) and the rounded
  // values are exact in float32 (field_bits <= 22) and compress (their low bits are zero).
  const int bodies = P.num_bodies();
  auto reals = [&](const std::string& name, int components, bool f64, auto value) {
    if (fields.field_bits <= 0) return write_reals(name, components, f64, value);
    std::vector<double> largest(static_cast<std::size_t>(bodies), 0.0);
    order.reduce_max(
        spans,
        [&](std::size_t p) {
          double& m = largest[static_cast<std::size_t>(P.body_of(p))];
          for (int k = 0; k < components; ++k)
            if (const double v = std::abs(value(p, k)); std::isfinite(v)) m = std::max(m, v);
        },
        largest);
    // In float32 no step below its smallest subnormal, 2^-149, of which every float32 is a
    // multiple (a body whose values are all below about 1e-38 keeps float32's own rounding).
    std::vector<double> q(largest.size(), 0.0);
    for (std::size_t b = 0; b < q.size(); ++b)
      if (largest[b] > 0.0 && std::isfinite(largest[b]))
        q[b] = std::max(std::ldexp(1.0, std::ilogb(largest[b]) - fields.field_bits),
                        f64 ? 0.0 : std::ldexp(1.0, -149));
    write_reals(name, components, f64, [&](std::size_t p, int k) {
      return quantise(value(p, k), q[static_cast<std::size_t>(P.body_of(p))]);
    });
  };
  auto ints = [&](const char* type, const std::string& name, auto value) {
    column(type, name, 1, 4, [&](std::size_t p, char* o) {
      const auto v = value(p);
      static_assert(sizeof v == 4);
      std::memcpy(o, &v, 4);
    });
  };
  // A vector in three components (zero out of plane).
  auto vec3 = [](auto get) {
    return [get](std::size_t p, int k) { return k < D ? get(p)[k] : 0.0; };
  };
  write_reals("position", 3, !fields.float32_positions, [&](std::size_t p, int k) {
    return k < D ? quantise(P.x[p][k], fields.position_quantum) : 0.0;
  });
  // Vertices numbered in order: the cells need no gathering. Int32 indices up to 2^31 - 1
  // particles (half the bytes of Int64 before compression), Int64 beyond.
  if (out) {
    out->xml("      </Points>\n      <Cells>\n");
    auto indices = [&](auto zero, const char* type) {
      using Int = decltype(zero);
      std::vector<Int> v;
      for (const char* name : {"connectivity", "offsets"}) {
        out->begin(type, name, 1, sizeof(Int) * n);
        const std::size_t shift = name[0] == 'o';
        for (std::size_t at = 0; at < n; at += v.size()) {
          v.resize(std::min<std::size_t>(n - at, std::size_t{1} << 19));
          for (std::size_t k = 0; k < v.size(); ++k)
            v[k] = static_cast<Int>(at + k + shift);
          out->append(v.data(), sizeof(Int) * v.size());
        }
        out->end();
      }
    };
    if (n < std::size_t{1} << 31)
      indices(std::int32_t{0}, "Int32");
    else
      indices(std::int64_t{0}, "Int64");
    out->begin("UInt8", "types", 1, n);
    const std::vector<std::uint8_t> vertex(std::size_t{1} << 20, 1); // VTK_VERTEX
    for (std::size_t at = 0; at < n; at += vertex.size())
      out->append(vertex.data(), std::min(vertex.size(), n - at));
    out->end();
    out->xml("      </Cells>\n      <PointData>\n");
  }
  const bool f64 = fields.float64_fields;
  ints("Int32", "body", [&](std::size_t p) { return std::int32_t{P.body_of(p)}; });
  if (fields.wants("material"))
    ints("Int32", "material",
         [&](std::size_t p) { return std::int32_t{body_material[P.body_of(p)]}; });
  ints("UInt32", "id", [&](std::size_t p) { return P.id[p]; });
  if (fields.wants("velocity"))
    reals("velocity", 3, f64, vec3([&](std::size_t p) { return P.v[p]; }));
  if (fields.wants("displacement"))
    reals("displacement", 3, f64, vec3([&](std::size_t p) { return Vec<D>(P.x[p] - P.x0[p]); }));
  // VTK's symmetric tensor order: xx, yy, zz, xy, yz, xz (ours).
  if (fields.wants("stress"))
    reals("stress", 6, f64, [&](std::size_t p, int k) { return P.stress[p][k]; });
  auto scalar = [](const auto& a) { return [&a](std::size_t p, int) { return double(a[p]); }; };
  if (fields.wants("mass")) write_reals("mass", 1, f64, scalar(P.m)); // exact: it sums to the body
  if (fields.wants("volume")) reals("volume", 1, f64, scalar(P.vol));
  if (fields.wants("plastic_strain")) reals("plastic_strain", 1, f64, scalar(P.eps_p));
  if (fields.wants("field")) ints("Int32", "field", [&](std::size_t p) { return P.field[p]; });
  if (fields.wants("interface")) {
    ints("Int32", "interface", [&](std::size_t p) { return P.iface[p]; });
    reals("interface_slip", 1, f64, scalar(P.slip));
    reals("interface_cohesion", 1, f64, scalar(P.cohesion));
    reals("interface_friction", 1, f64, scalar(P.friction));
  }
  for (const ScalarField& e : extra)
    if (fields.wants(e.first))
      reals(e.first, 1, f64, [&](std::size_t p, int) { return e.second(p); });
}

} // namespace

template <int D>
std::string particles_to_vtu(const Particles<D>& P, const std::vector<int>& body_material,
                             const VtuFields& fields, const std::vector<ScalarField>& extra,
                             const ParticleOrder::Spans& spans) {
  LocalOrder order(P.size());
  const ParticleOrder::Spans all = spans.empty() ? ParticleOrder::Spans{{0, P.size()}} : spans;
  Appended data;
  VtuBuilder out(ParticleOrder::count(all), data, fields.compression);
  particle_arrays<D>(&out, P, body_material, fields, extra, order, all);
  if (!out.error().empty()) throw OutputError("frame: " + out.error());
  return out.head() + data.memory() + VtuBuilder::tail;
}

template <int D>
void write_particles_vtu(const std::string& path, const Particles<D>& P,
                         const std::vector<int>& body_material, const VtuFields& fields,
                         const std::vector<ScalarField>& extra, ParticleOrder& order,
                         const ParticleOrder::Spans& spans) {
  if (!order.receives()) {
    particle_arrays<D>(nullptr, P, body_material, fields, extra, order, spans);
    return;
  }
  Appended data(path + ".body.tmp");
  VtuBuilder out(ParticleOrder::count(spans), data, fields.compression);
  particle_arrays<D>(&out, P, body_material, fields, extra, order, spans);
  if (!data.error().empty()) throw OutputError(path + ": " + data.error());
  if (!out.error().empty()) throw OutputError(path + ": " + out.error());
  AtomicFile file(path);
  file.write(out.head());
  data.copy_to(file);
  file.write(VtuBuilder::tail);
  file.commit();
}

std::string vertices_to_vtu(const std::vector<double>& xyz, const std::vector<VtuArray>& arrays) {
  const std::size_t n = xyz.size() / 3;
  Appended data;
  VtuBuilder out(n, data, FrameCompression::zlib);
  out.array("Float64", "position", 3, xyz);
  out.xml("      </Points>\n      <Cells>\n");
  std::vector<std::int64_t> conn(n), offsets(n);
  for (std::size_t p = 0; p < n; ++p)
    conn[p] = static_cast<std::int64_t>(p), offsets[p] = static_cast<std::int64_t>(p + 1);
  out.array("Int64", "connectivity", 1, conn);
  out.array("Int64", "offsets", 1, offsets);
  out.array("UInt8", "types", 1, std::vector<std::uint8_t>(n, 1)); // VTK_VERTEX
  out.xml("      </Cells>\n      <PointData>\n");
  for (const VtuArray& a : arrays) {
    if (!a.f64.empty())
      out.array("Float64", a.name, a.components, a.f64);
    else
      out.array("Int32", a.name, a.components, a.i32);
  }
  return out.head() + data.memory() + VtuBuilder::tail;
}

std::string pvd_collection(const std::vector<std::pair<double, std::string>>& frames,
                           const std::string& fixed) {
  std::string out = "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\" "
                    "byte_order=\"LittleEndian\">\n  <Collection>\n";
  for (const auto& [t, file] : frames) {
    out += fmt::format("    <DataSet timestep=\"{:.17g}\" part=\"0\" file=\"{}\"/>\n", t, file);
    if (!fixed.empty())
      out += fmt::format("    <DataSet timestep=\"{:.17g}\" part=\"1\" file=\"{}\"/>\n", t, fixed);
  }
  out += "  </Collection>\n</VTKFile>\n";
  return out;
}

#define TALUS_INSTANTIATE(D)                                                                       \
  template std::string particles_to_vtu<D>(const Particles<D>&, const std::vector<int>&,           \
                                           const VtuFields&, const std::vector<ScalarField>&,      \
                                           const ParticleOrder::Spans&);                           \
  template void write_particles_vtu<D>(                                                            \
      const std::string&, const Particles<D>&, const std::vector<int>&, const VtuFields&,          \
      const std::vector<ScalarField>&, ParticleOrder&, const ParticleOrder::Spans&);
TALUS_INSTANTIATE(2)
TALUS_INSTANTIATE(3)
#undef TALUS_INSTANTIATE

} // namespace talus
