// Checkpoints: values round-trip through the archives; a file that is truncated or has one byte
// changed is refused (its checksum), never read as a state.
#include "talus/output/checkpoint.hpp"
#include "test_support.hpp"

#include <fstream>
#include <gtest/gtest.h>
#include <iterator>
#include <numeric>

namespace talus {
namespace {

TEST(Checkpoint, ArchivesRoundTrip) {
  double x = 1.25;
  std::vector<Vec<3>> v = {Vec<3>(1, 2, 3), Vec<3>(-1, 0.5, 7)};
  std::string s = "bodies";
  std::vector<std::string> names = {"a", "bc"};
  SaveArchive out;
  out.io(x), out.io(v), out.io(s), out.io(names);
  double x2 = 0;
  std::vector<Vec<3>> v2;
  std::string s2;
  std::vector<std::string> names2;
  LoadArchive in(out.bytes(), "memory");
  in.io(x2), in.io(v2), in.io(s2), in.io(names2);
  EXPECT_TRUE(in.done());
  EXPECT_EQ(x2, x);
  EXPECT_EQ(v2, v);
  EXPECT_EQ(s2, s);
  EXPECT_EQ(names2, names);
  double past_the_end = 0;
  EXPECT_THROW(in.io(past_the_end), CheckpointError);
}

TEST(Checkpoint, ATruncatedOrChangedFileIsRefused) {
  const std::string dir = test::temp_dir("checkpoint");
  const std::string path = dir + "/c.ckp", payload(1000, 'x');
  write_checkpoint_file(path, payload);
  EXPECT_EQ(read_checkpoint_file(path), payload);
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  auto write = [&](const std::string& b) { std::ofstream(path, std::ios::binary) << b; };
  std::string changed = bytes;
  changed[bytes.size() / 2] ^= 1;
  write(changed);
  EXPECT_THROW(read_checkpoint_file(path), CheckpointError);
  write(bytes.substr(0, bytes.size() - 3));
  EXPECT_THROW(read_checkpoint_file(path), CheckpointError);
  write(bytes);
  EXPECT_EQ(read_checkpoint_file(path), payload);
}

// Particles of two bodies whose every array holds values of its row, saved as a checkpoint's
// particles; read back from the file whole, and as one process's share: the rows the chooser
// keeps, read in spans small enough that gaps are skipped and spans split.
// With `affine`, the particles carry APIC's C (an optional array), which is read whole or by
// the chosen rows as the others are; without, it stays empty.
void share_is_read(bool affine) {
  constexpr std::size_t n = 5000;
  Particles<2> P;
  for (std::size_t p = 0; p < n; ++p) {
    if (p == 3000) P.body_begin.push_back(p);
    P.push_back(Vec<2>(0.5 * static_cast<double>(p), 1.0), Vec<2>(1.0, -static_cast<double>(p)),
                2.0 + static_cast<double>(p), 0.25);
    P.eps_p.back() = 1e-3 * static_cast<double>(p);
    P.id.back() = static_cast<std::uint32_t>(n - 1 - p);
    P.stress.back().fill(static_cast<double>(p));
  }
  P.body_begin.push_back(n);
  if (affine) {
    P.C.resize(n);
    for (std::size_t p = 0; p < n; ++p)
      P.C[p] << 1.0, -static_cast<double>(p), 0.5 * static_cast<double>(p), 3.0;
  }
  const std::vector<std::size_t> whole = P.body_begin;
  SaveArchive out;
  double tail = 7.5;
  out.particles(P, affine), out.io(tail);
  const std::string path =
      test::temp_dir(affine ? "checkpoint_share_affine" : "checkpoint_share") + "/c.ckpt";
  write_checkpoint_file(path, out.bytes());

  auto expect_rows = [&](const Particles<2>& got, const std::vector<std::uint32_t>& rows) {
    ASSERT_EQ(got.size(), rows.size());
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const std::size_t r = rows[i];
      EXPECT_EQ(got.x[i], P.x[r]);
      EXPECT_EQ(got.v[i], P.v[r]);
      EXPECT_EQ(got.m[i], P.m[r]);
      EXPECT_EQ(got.eps_p[i], P.eps_p[r]);
      EXPECT_EQ(got.id[i], P.id[r]);
      EXPECT_EQ(got.stress[i], P.stress[r]);
      if (affine) {
        EXPECT_EQ(got.C[i], P.C[r]);
      }
    }
    EXPECT_EQ(got.C.size(), affine ? rows.size() : 0);
  };
  // The body ranges, the particles, then the value after them, to the end.
  auto read = [&](LoadArchive& in) {
    std::vector<std::size_t> begin;
    in.io(begin);
    EXPECT_EQ(begin, whole);
    Particles<2> got;
    EXPECT_EQ(in.particles(got, whole), affine) << "whether the optional arrays were stored";
    double t = 0;
    in.io(t);
    EXPECT_TRUE(in.done());
    EXPECT_EQ(t, tail);
    return got;
  };
  std::vector<std::uint32_t> all(n);
  std::iota(all.begin(), all.end(), 0u);
  {
    LoadArchive in(open_checkpoint(path));
    const Particles<2> got = read(in);
    EXPECT_EQ(got.body_begin, whole);
    expect_rows(got, all);
  }
  // A share: rows 0-9, every 7th of [2000, 4000) and the last one, chosen from the positions
  // (x = row / 2), which the chooser sees in chunks of 10 rows.
  std::vector<std::uint32_t> rows;
  LoadArchive in(open_checkpoint(path));
  in.set_chunk_bytes(10 * sizeof(Vec<2>));
  std::size_t scanned = 0, chunks = 0;
  in.set_choose([&](std::size_t total, const LoadArchive::Scan& scan) {
    EXPECT_EQ(total, n);
    scan([&](std::size_t first, const char* data, std::size_t count) {
      EXPECT_EQ(first, scanned);
      EXPECT_LE(count, 10u);
      ++chunks;
      for (std::size_t i = 0; i < count; ++i, ++scanned) {
        Vec<2> x;
        std::memcpy(static_cast<void*>(&x), data + i * sizeof(Vec<2>), sizeof x);
        const auto r = static_cast<std::uint32_t>(2.0 * x[0]);
        EXPECT_EQ(r, scanned);
        if (r < 10 || (r >= 2000 && r < 4000 && r % 7 == 0) || r == n - 1) rows.push_back(r);
      }
    });
    return rows;
  });
  const Particles<2> got = read(in);
  EXPECT_EQ(scanned, n);
  EXPECT_EQ(chunks, n / 10);
  // Body 1 (rows 3000 on) starts at the first kept row from 3000.
  const auto first_of_body1 =
      static_cast<std::size_t>(std::lower_bound(rows.begin(), rows.end(), 3000u) - rows.begin());
  EXPECT_EQ(got.body_begin, (std::vector<std::size_t>{0, first_of_body1, rows.size()}));
  expect_rows(got, rows);
}

TEST(Checkpoint, AShareOfTheParticlesIsReadFromTheFile) {
  share_is_read(false);
}

TEST(Checkpoint, AShareOfTheParticlesIsReadFromTheFileWithApicsAffineVelocities) {
  share_is_read(true);
}

} // namespace
} // namespace talus
