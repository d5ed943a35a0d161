// Output: atomic writes, the VTU layout (compressed appended arrays, float32 fields) and the
// ParaView series.
#include "talus/case/size.hpp"
#include "talus/output/files.hpp"
#include "talus/output/vtu.hpp"
#include "test_support.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <lzma.h>
#include <random>
#include <sstream>
#include <stdexcept>
#include <zlib.h>
#ifdef _OPENMP
#include <omp.h>
#endif

namespace talus {
namespace {

TEST(WriteFileAtomic, ReplacesTheFileAndLeavesNoTemporary) {
  const std::string dir = test::temp_dir("atomic");
  const std::string path = dir + "/a.txt";
  write_file_atomic(path, "one");
  write_file_atomic(path, "two");
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  EXPECT_EQ(ss.str(), "two");
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
}

TEST(WriteFileAtomic, AnUnwritableFolderIsAClearError) {
  try {
    write_file_atomic("/nonexistent_dir/x.txt", "x");
    FAIL();
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent_dir/x.txt: cannot write"),
              std::string::npos);
  }
}

TEST(Vtu, DeclaresOnePointAndOneVertexPerParticle) {
  Particles<2> P;
  P.push_back(Vec<2>(0.5, 1.0), Vec<2>(1.0, 0.0), 2.0, 0.01);
  P.push_back(Vec<2>(1.5, 1.0), Vec<2>(0.0, 0.0), 2.0, 0.01);
  P.body_begin.push_back(2);
  const std::string vtu = particles_to_vtu<2>(P, {0}, VtuFields{});
  EXPECT_NE(vtu.find("NumberOfPoints=\"2\" NumberOfCells=\"2\""), std::string::npos);
  EXPECT_NE(vtu.find("type=\"Float32\" Name=\"stress\" NumberOfComponents=\"6\""),
            std::string::npos);
  EXPECT_NE(vtu.find("type=\"Float64\" Name=\"position\""), std::string::npos);
  EXPECT_NE(vtu.find("header_type=\"UInt64\" compressor=\"vtkLZMADataCompressor\""),
            std::string::npos);
  EXPECT_NE(vtu.find("<AppendedData encoding=\"raw\">"), std::string::npos);
  VtuFields doubles;
  doubles.float64_fields = true, doubles.float32_positions = true;
  const std::string d = particles_to_vtu<2>(P, {0}, doubles);
  EXPECT_NE(d.find("type=\"Float64\" Name=\"stress\""), std::string::npos);
  EXPECT_NE(d.find("type=\"Float32\" Name=\"position\""), std::string::npos);
  const std::string only = particles_to_vtu<2>(P, {0}, VtuFields{{"velocity"}});
  EXPECT_EQ(only.find("Name=\"stress\""), std::string::npos);
  EXPECT_NE(only.find("Name=\"velocity\""), std::string::npos);
}

// Frames store positions in float32 unless that rounds them by more than a 2,000th of a cell
// somewhere on the grid: checked against float32's actual rounding of 100,000 positions spread
// over grids from 1.5 m to 3,000 km from the origin, with cells from 1 cm to 100 m. Where float32
// is refused, it rounds some position by more than a 4,000th of a cell (the test is not loose).
TEST(Vtu, PositionsAreFloat32WhereTheyRoundWithinA2000thOfACell) {
  std::mt19937_64 random(7);
  for (const double largest : {1.5, 7.3, 2500.0, 6.1e5, 3.0e6})
    for (const double h : {0.01, 0.1, 1.0, 4.0, 16.0, 100.0}) {
      if (h > largest) continue;
      GridSettings g;
      g.origin = {-0.5 * largest, 0.25 * largest, 0.0};
      g.extent = {1.5 * largest, 0.5 * largest, 0.0};
      g.cell_size = h;
      std::uniform_real_distribution<double> x(-0.5 * largest, largest);
      double worst = 0.0;
      for (int k = 0; k < 100000; ++k) {
        const double v = x(random);
        worst = std::max(worst, std::abs(v - static_cast<double>(static_cast<float>(v))));
      }
      const bool f32 = float32_positions_suffice(g, 2);
      if (f32)
        EXPECT_LE(worst, h / 2000.0) << largest << " m, cell " << h << " m";
      else
        EXPECT_GT(worst, h / 4000.0) << largest << " m, cell " << h << " m";
    }
  GridSettings edge; // the far face a whole cell past origin + extent, beyond 2^18 m
  edge.origin = {5.0, 0.0, 0.0}, edge.extent = {262135.0, 100.0, 0.0}, edge.cell_size = 16.0;
  EXPECT_FALSE(float32_positions_suffice(edge, 2));
  edge.extent[0] = 262000.0; // the far face at 262,005 m, below 2^18: half spacing h / 2048
  EXPECT_TRUE(float32_positions_suffice(edge, 2));
  GridSettings vaiont; // cases/vaiont's grid at the paper's 2 m cells (1 m particle spacing)
  vaiont.origin = {-32.0, -316.0, 0.0}, vaiont.extent = {1808.0, 944.0, 0.0};
  vaiont.cell_size = 2.0;
  EXPECT_TRUE(float32_positions_suffice(vaiont, 2));
}

// The values of a frame's array `name` (Float32 or Float64), decoded as VTK's reader does.
std::vector<double> vtu_array(const std::string& vtu, const std::string& name) {
  const std::size_t at = vtu.find("Name=\"" + name + "\"");
  if (at == std::string::npos) throw std::runtime_error("no array " + name);
  const std::size_t tag = vtu.rfind("<DataArray", at);
  const bool f64 = vtu.compare(tag, 25, "<DataArray type=\"Float64\"") == 0;
  const bool lzma = vtu.find("compressor=\"vtkLZMADataCompressor\"") != std::string::npos;
  const std::size_t off = vtu.find("offset=\"", at) + 8;
  const std::size_t data = vtu.find("<AppendedData encoding=\"raw\">");
  const char* base = vtu.data() + vtu.find('_', data) + 1 + std::stoull(vtu.substr(off));
  std::uint64_t head[3];
  std::memcpy(head, base, sizeof head);
  std::uint64_t total = 0; // the bytes the header declares
  std::string raw;
  const char* block = base + 8 * (3 + head[0]);
  for (std::uint64_t b = 0; b < head[0]; ++b) {
    std::uint64_t size = 0;
    std::memcpy(&size, base + 8 * (3 + b), 8);
    uLongf n = b + 1 < head[0] ? head[1] : head[2];
    std::string out(n, '\0');
    if (lzma) { // an xz stream (and the padding after the last one, which the decoder skips)
      std::uint64_t memory = UINT64_MAX;
      std::size_t in = 0, got = 0;
      const lzma_ret r = lzma_stream_buffer_decode(
          &memory, 0, nullptr, reinterpret_cast<const std::uint8_t*>(block), &in, size,
          reinterpret_cast<std::uint8_t*>(out.data()), &got, n);
      EXPECT_EQ(r, LZMA_OK);
      EXPECT_EQ(got, n);
      // The stream fills its block but for the alignment padding after the last one: 0xFF.
      EXPECT_TRUE(in == size || (b + 1 == head[0] && size - in < 4));
      for (std::size_t k = in; k < size; ++k)
        EXPECT_EQ(static_cast<unsigned char>(block[k]), 0xFF);
    } else {
      EXPECT_EQ(uncompress(reinterpret_cast<Bytef*>(out.data()), &n,
                           reinterpret_cast<const Bytef*>(block), size),
                Z_OK);
    }
    raw += out, block += size, total += n;
  }
  // Every block but the last is whole; the last holds the rest.
  EXPECT_EQ(total, head[0] == 0 ? 0 : (head[0] - 1) * head[1] + head[2]);
  EXPECT_TRUE(head[0] == 0 || (head[2] > 0 && head[2] <= head[1]));
  std::vector<double> v(raw.size() / (f64 ? 8 : 4));
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (f64) {
      std::memcpy(&v[i], raw.data() + 8 * i, 8);
    } else {
      float x = 0.0f;
      std::memcpy(&x, raw.data() + 4 * i, 4);
      v[i] = x;
    }
  }
  return v;
}

// output.field_bits: each value within half its body's quantum q_b = 2^(floor(log2 m_b) - bits)
// of the value (m_b the body's largest magnitude in the array), a whole multiple of it, and the
// bound is reached (rounding does happen); two bodies 10^6 apart in scale each keep their own
// precision; NaN stays NaN; mass is exact; positions within half their quantum. Field bits 8 to
// 22, values spread over six decades; with 0 every value exact to float32.
TEST(Vtu, FieldBitsKeepEachBodysValuesToItsOwnRange) {
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Particles<3> P;
  const std::size_t n = 3000;
  for (std::size_t i = 0; i < n; ++i) {
    const double scale = i < n / 2 ? 1.0e3 : 1.0e-3;       // body 0 fast, body 1 slow
    const double spread = std::pow(10.0, 3.0 * u(random)); // values over six decades
    P.push_back(Vec<3>(100.0 * u(random), 3.0 + u(random), 7.0e3 + u(random)),
                Vec<3>(scale * spread * u(random), scale * u(random), 0.0), 1.0 + u(random), 0.01);
    for (int k = 0; k < 6; ++k)
      P.stress.back()[k] = 1.0e6 * scale * spread * u(random);
  }
  P.body_begin.push_back(n / 2);
  P.body_begin.push_back(n);
  const std::vector<ScalarField> extra = {
      {"band_temperature", [](std::size_t p) { return p % 3 ? NAN : 20.0 + 0.37 * p; }}};
  for (const int bits : {8, 12, 16, 22}) {
    VtuFields f;
    f.float32_positions = true, f.field_bits = bits, f.position_quantum = 1.0 / 256;
    const std::string vtu = particles_to_vtu<3>(P, {0, 0}, f, extra);
    auto check = [&](const std::string& name, int comps, auto exact) {
      const std::vector<double> got = vtu_array(vtu, name);
      ASSERT_EQ(got.size(), n * comps);
      for (std::size_t b = 0; b < 2; ++b) {
        double m = 0.0, worst = 0.0;
        for (std::size_t p = P.body_begin[b]; p < P.body_begin[b + 1]; ++p)
          for (int k = 0; k < comps; ++k)
            if (std::isfinite(exact(p, k))) m = std::max(m, std::abs(exact(p, k)));
        const double q = std::ldexp(1.0, std::ilogb(m) - bits);
        EXPECT_LE(q, std::ldexp(m, -bits));
        for (std::size_t p = P.body_begin[b]; p < P.body_begin[b + 1]; ++p)
          for (int k = 0; k < comps; ++k) {
            const double e = exact(p, k), g = got[comps * p + k];
            if (!std::isfinite(e)) {
              EXPECT_TRUE(std::isnan(g));
              continue;
            }
            EXPECT_EQ(g, std::nearbyint(g / q) * q) << name << " " << p;
            worst = std::max(worst, std::abs(g - e));
          }
        EXPECT_LE(worst, 0.5 * q) << name << ", body " << b << ", " << bits << " bits";
        EXPECT_GT(worst, 0.4 * q) << name << ", body " << b << ", " << bits << " bits";
      }
    };
    check("velocity", 3, [&](std::size_t p, int k) { return P.v[p][k]; });
    check("stress", 6, [&](std::size_t p, int k) { return P.stress[p][k]; });
    check("band_temperature", 1, [&](std::size_t p, int) { return extra[0].second(p); });
    const std::vector<double> mass = vtu_array(vtu, "mass"), x = vtu_array(vtu, "position");
    double worst_x = 0.0;
    for (std::size_t p = 0; p < n; ++p) {
      EXPECT_EQ(mass[p], static_cast<double>(static_cast<float>(P.m[p])));
      for (int k = 0; k < 3; ++k)
        worst_x = std::max(worst_x, std::abs(x[3 * p + k] - P.x[p][k]));
    }
    EXPECT_LE(worst_x, 0.5 / 256);
    EXPECT_GT(worst_x, 0.4 / 256);
  }
  // field_bits = 0: every value is float32's own rounding of it.
  VtuFields exact;
  exact.float32_positions = true;
  const std::string vtu = particles_to_vtu<3>(P, {0, 0}, exact, extra);
  const std::vector<double> v = vtu_array(vtu, "velocity"), s = vtu_array(vtu, "stress"),
                            x = vtu_array(vtu, "position");
  for (std::size_t p = 0; p < n; ++p)
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(v[3 * p + k], static_cast<double>(static_cast<float>(P.v[p][k])));
      EXPECT_EQ(s[6 * p + k], static_cast<double>(static_cast<float>(P.stress[p][k])));
      EXPECT_EQ(x[3 * p + k], static_cast<double>(static_cast<float>(P.x[p][k])));
    }
}

// An order that hands the writer one particle at a time, in reverse slices of the buffer, as a
// gather across processes may cut it anywhere.
class OneByOne final : public ParticleOrder {
public:
  explicit OneByOne(std::size_t n) : n_(n) {}
  std::size_t total() const override { return n_; }
  bool receives() const override { return true; }
  using ParticleOrder::gather;
  void gather(std::size_t width, const Fill& fill, const Take& take, const Spans& spans) override {
    std::vector<char> one(width);
    for (const auto& [begin, end] : spans)
      for (std::size_t p = begin; p < end; ++p) {
        fill(p, one.data());
        take(one.data(), 1);
      }
  }
  void reduce_max(const Spans& spans, const std::function<void(std::size_t p)>& f,
                  std::vector<double>&) override {
    for (auto s = spans.rbegin(); s != spans.rend(); ++s) // any order gives the same maxima
      for (std::size_t p = s->second; p-- > s->first;)
        f(p);
  }

private:
  std::size_t n_;
};

// A frame streamed to its file in pieces is the frame built whole in memory, byte for byte, with
// arrays of several compressed blocks (256 KiB each) and batches of blocks; nothing is left beside
// it.
TEST(Vtu, AFrameStreamedInPiecesIsTheFrameBuiltWhole) {
  Particles<3> P;
  const std::size_t n = 200000; // 4.8 MB of positions: 19 blocks, in two batches
  for (std::size_t i = 0; i < n; ++i) {
    const double x = 0.001 * static_cast<double>(i);
    P.push_back(Vec<3>(x, std::sin(x), std::cos(3 * x)), Vec<3>(std::cos(x), 0.0, x), 2.0, 0.01);
    P.stress.back()[3] = x;
  }
  P.body_begin.push_back(n / 2);
  P.body_begin.push_back(n);
  const std::vector<ScalarField> extra = {
      {"pore_pressure", [](std::size_t p) { return 0.5 * static_cast<double>(p); }}};
  const std::string whole = particles_to_vtu<3>(P, {1, 0}, VtuFields{}, extra);
  const std::string dir = test::temp_dir("vtu_stream");
  OneByOne order(n);
  write_particles_vtu<3>(dir + "/f.vtu", P, {1, 0}, VtuFields{}, extra, order, {{0, n}});
  auto read = [&](const std::string& name) {
    std::ifstream in(dir + "/" + name, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), {});
  };
  const std::string streamed = read("f.vtu");
  EXPECT_EQ(streamed.size(), whole.size());
  EXPECT_TRUE(streamed == whole);
  // The positions (Float64, 19 blocks in two batches) decode to the particles' own, in order.
  const std::vector<double> x = vtu_array(whole, "position");
  ASSERT_EQ(x.size(), 3 * n);
  for (std::size_t p = 0; p < n; ++p)
    for (int k = 0; k < 3; ++k)
      ASSERT_EQ(x[3 * p + k], P.x[p][k]) << p;
  // Rounded to each body's range (field_bits), whose maxima the order reduces: the same too.
  VtuFields compact;
  compact.field_bits = 12, compact.position_quantum = 1.0 / 1024;
  write_particles_vtu<3>(dir + "/c.vtu", P, {1, 0}, compact, extra, order, {{0, n}});
  const std::string compact_whole = particles_to_vtu<3>(P, {1, 0}, compact, extra);
  EXPECT_TRUE(read("c.vtu") == compact_whole);
  EXPECT_LT(compact_whole.size(), whole.size());
  std::filesystem::remove(dir + "/c.vtu");
  EXPECT_NE(whole.find("Name=\"pore_pressure\""), std::string::npos);
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), {}), 1);
  // A frame of some runs of the particles (a frame's parts): the same streamed and built whole,
  // with only those particles.
  const ParticleOrder::Spans spans{{10, 20}, {n / 2, n / 2 + 7}, {n - 3, n}};
  write_particles_vtu<3>(dir + "/g.vtu", P, {1, 0}, VtuFields{}, extra, order, spans);
  const std::string part = particles_to_vtu<3>(P, {1, 0}, VtuFields{}, extra, spans);
  EXPECT_TRUE(read("g.vtu") == part);
  EXPECT_NE(part.find("NumberOfPoints=\"20\""), std::string::npos);
}

// output.compression: an LZMA frame and a zlib frame carry the same values (arrays of several
// 256-KiB blocks), the LZMA one in fewer bytes; each is the same bytes on 1 and 2 threads (the
// blocks are compressed in parallel, each on its own).
TEST(Vtu, LzmaAndZlibFramesCarryTheSameValuesInAnyThreadCount) {
  Particles<2> P;
  const std::size_t n = 50000; // stress: 1.2 MB, five blocks
  std::mt19937_64 random(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (std::size_t i = 0; i < n; ++i) {
    const double x = 0.01 * static_cast<double>(i % 500), y = 0.01 * static_cast<double>(i / 500);
    P.push_back(Vec<2>(x, y), Vec<2>(std::sin(x) + 1e-3 * u(random), y), 2.0, 0.01);
    for (int k = 0; k < 4; ++k)
      P.stress.back()[k] = -1.0e5 * y + 1.0e3 * u(random);
  }
  P.body_begin.push_back(n);
  VtuFields lz, zl;
  lz.field_bits = zl.field_bits = 12;
  zl.compression = FrameCompression::zlib;
  auto frame = [&](const VtuFields& f, int threads) {
#ifdef _OPENMP
    const int before = omp_get_max_threads();
    omp_set_num_threads(threads);
#endif
    std::string s = particles_to_vtu<2>(P, {0}, f);
#ifdef _OPENMP
    omp_set_num_threads(before);
#endif
    return s;
  };
  const std::string a = frame(lz, 1), b = frame(zl, 1);
  EXPECT_TRUE(a == frame(lz, 2));
  EXPECT_TRUE(b == frame(zl, 2));
  EXPECT_NE(a.find("compressor=\"vtkLZMADataCompressor\""), std::string::npos);
  EXPECT_NE(b.find("compressor=\"vtkZLibDataCompressor\""), std::string::npos);
  for (const char* name : {"position", "velocity", "stress", "mass", "volume"}) {
    const std::vector<double> va = vtu_array(a, name), vb = vtu_array(b, name);
    EXPECT_EQ(va.size(), vb.size()) << name;
    EXPECT_TRUE(va == vb) << name;
  }
  EXPECT_EQ(vtu_array(a, "stress").size(), 6 * n);
  EXPECT_LT(a.size(), b.size());
}

TEST(Vtu, AFrameThatCannotBeWrittenIsAClearError) {
  Particles<2> P;
  P.push_back(Vec<2>(0.5, 1.0), Vec<2>(1.0, 0.0), 2.0, 0.01);
  P.body_begin.push_back(1);
  LocalOrder order(1);
  try {
    write_particles_vtu<2>("/nonexistent_dir/f.vtu", P, {0}, VtuFields{}, {}, order, {{0, 1}});
    FAIL();
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent_dir/f.vtu"), std::string::npos);
  }
}

TEST(Pvd, ListsTheFramesInOrder) {
  const std::string pvd =
      pvd_collection({{0.0, "particles_000000.vtu"}, {0.5, "particles_000001.vtu"}});
  EXPECT_LT(pvd.find("particles_000000.vtu"), pvd.find("particles_000001.vtu"));
  EXPECT_NE(pvd.find("timestep=\"0.5\""), std::string::npos);
  EXPECT_EQ(pvd.find("part=\"1\""), std::string::npos);
  // With a part written once: listed at every time, after that time's own part.
  const std::string two = pvd_collection(
      {{0.0, "particles_000000.vtu"}, {0.5, "particles_000001.vtu"}}, "particles_fixed.vtu");
  const std::string at_half =
      "<DataSet timestep=\"0.5\" part=\"0\" file=\"particles_000001.vtu\"/>\n"
      "    <DataSet timestep=\"0.5\" part=\"1\" file=\"particles_fixed.vtu\"/>";
  EXPECT_NE(two.find(at_half), std::string::npos) << two;
  EXPECT_NE(two.find("<DataSet timestep=\"0\" part=\"1\" file=\"particles_fixed.vtu\"/>"),
            std::string::npos);
}

} // namespace
} // namespace talus
