// Checkpoints: values round-trip through the archives; a file that is truncated or has one byte
// changed is refused (its checksum), never read as a state.
#include "talus/output/checkpoint.hpp"
#include "test_support.hpp"

#include <fstream>
#include <gtest/gtest.h>
#include <iterator>

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

} // namespace
} // namespace talus
