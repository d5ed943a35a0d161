// RunWriter (output/run_writer.hpp): the run folder's tables, a row per frame, the frame list, the
// summary, and a restart's rewrite that drops the rows written after the checkpoint.
#include "talus/output/run_writer.hpp"
#include "two_bodies.hpp"

#include <gtest/gtest.h>

#include <fmt/format.h>
#include <fstream>
#include <sstream>

using namespace talus;

namespace {

std::string read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::size_t lines(const std::string& text) {
  return static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
}

} // namespace

// The folder's fixed files at the start; a header and a row per body (bodies.csv) or per frame
// (energy.csv) at each frame; contacts.csv and interfaces.csv with two bodies and an interface;
// the frames listed in particles.pvd with their times.
TEST(RunWriter, WritesARowPerFrameAndListsTheFrames) {
  const std::string dir = test::temp_dir("run_writer_rows");
  Simulation<2> sim(test::case_from(test::two_blocks(R"(
[[interface]]
bodies = ["upper", "lower"]
friction = { initial = 0.5 }
cohesion = { initial = 0 }
)")));
  RunWriter<2> writer(dir, sim, {});
  for (const char* f : {"case.toml", "case_as_run.toml", "legend.json"})
    EXPECT_TRUE(std::filesystem::exists(dir + "/" + f)) << f;
  EXPECT_EQ(read(dir + "/case.toml"), sim.case_().text);

  EXPECT_EQ(writer.next_particle_frame(), dir + "/particles_000000.vtu");
  writer.write_frame(sim, frame_totals(sim, {}), {});
  for (int i = 0; i < 10; ++i)
    sim.step();
  EXPECT_EQ(writer.next_particle_frame(), dir + "/particles_000001.vtu");
  writer.write_frame(sim, frame_totals(sim, {}), {});

  EXPECT_EQ(lines(read(dir + "/energy.csv")), 1u + 2u);
  EXPECT_EQ(lines(read(dir + "/bodies.csv")), 1u + 2u * 2u);
  EXPECT_EQ(lines(read(dir + "/interfaces.csv")), 1u + 2u);
  EXPECT_TRUE(std::filesystem::exists(dir + "/contacts.csv"));
  EXPECT_FALSE(std::filesystem::exists(dir + "/probes.csv")); // no probe
  const std::string bodies = read(dir + "/bodies.csv");
  EXPECT_EQ(bodies.rfind("time,body,mass,centroid_x,centroid_y,velocity_x,velocity_y,", 0), 0u);
  EXPECT_NE(bodies.find(fmt::format("{:.10g},upper,", sim.time())), std::string::npos);
  const std::string pvd = read(dir + "/particles.pvd");
  EXPECT_NE(pvd.find("particles_000000.vtu"), std::string::npos);
  EXPECT_NE(pvd.find("particles_000001.vtu"), std::string::npos);
  std::filesystem::remove_all(dir);
}

// A writer copied at a frame (what a checkpoint keeps) rewrites the tables as they were then: the
// rows and frames written after it are gone, as after a restart from that checkpoint.
TEST(RunWriter, RewritingFromAnEarlierCopyDropsLaterRows) {
  const std::string dir = test::temp_dir("run_writer_restart");
  Simulation<2> sim(test::case_from(test::two_blocks()));
  RunWriter<2> writer(dir, sim, {});
  writer.write_frame(sim, frame_totals(sim, {}), {});
  const std::string energy = read(dir + "/energy.csv"), pvd = read(dir + "/particles.pvd");
  const RunWriter<2> checkpoint = writer;
  sim.step();
  writer.write_frame(sim, frame_totals(sim, {}), {});
  EXPECT_GT(lines(read(dir + "/energy.csv")), lines(energy));
  checkpoint.write_tables(sim);
  EXPECT_EQ(read(dir + "/energy.csv"), energy);
  EXPECT_EQ(read(dir + "/particles.pvd"), pvd);
  std::filesystem::remove_all(dir);
}

// summary.json: the status and message, the particle and step counts, and the throughput
// (particles x steps / stepping seconds).
TEST(RunWriter, SummaryNamesTheStatusAndThroughput) {
  const std::string dir = test::temp_dir("run_writer_summary");
  Simulation<2> sim(test::case_from(test::two_blocks()));
  RunWriter<2> writer(dir, sim, {});
  for (int i = 0; i < 5; ++i)
    sim.step();
  writer.write_summary(sim, "failed", 3.0, 2.0, 2, "went bad", {{"x", 1}});
  const nlohmann::json j = nlohmann::json::parse(read(dir + "/summary.json"));
  EXPECT_EQ(j["status"], "failed");
  EXPECT_EQ(j["message"], "went bad");
  EXPECT_EQ(j["steps"], 5);
  EXPECT_EQ(j["particles"], sim.case_particles());
  EXPECT_EQ(j["bodies"]["upper"]["particles"], sim.body_particles(1));
  EXPECT_DOUBLE_EQ(j["particle_updates_per_second"].get<double>(),
                   static_cast<double>(sim.case_particles()) * 5.0 / 2.0);
  EXPECT_EQ(j["results"]["x"], 1);
  EXPECT_EQ(j["dimension"], 2);
  std::filesystem::remove_all(dir);
}
