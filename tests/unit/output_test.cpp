// Output: atomic writes, the VTU layout (compressed appended arrays, float32 fields) and the
// ParaView series.
#include "talus/output/files.hpp"
#include "talus/output/vtu.hpp"
#include "test_support.hpp"

#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <sstream>

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
  EXPECT_NE(vtu.find("header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\""),
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

TEST(Pvd, ListsTheFramesInOrder) {
  const std::string pvd =
      pvd_collection({{0.0, "particles_000000.vtu"}, {0.5, "particles_000001.vtu"}});
  EXPECT_LT(pvd.find("particles_000000.vtu"), pvd.find("particles_000001.vtu"));
  EXPECT_NE(pvd.find("timestep=\"0.5\""), std::string::npos);
}

} // namespace
} // namespace talus
