// RunWriter (output/run_writer.hpp): the run folder's tables, a row per frame, the frame list, the
// summary, and a restart's rewrite that drops the rows written after the checkpoint.
#include "talus/output/run_writer.hpp"
#include "two_bodies.hpp"

#include <gtest/gtest.h>

#include <fmt/format.h>
#include <fstream>
#include <map>
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

// A case with a fixed body (rigid, at rest) beside a moving one writes its frames in two parts:
// the fixed body's particles once (RunWriter::frame_parts), listed at every time of
// particles.pvd. What makes that lossless: the fixed part's bytes after 200 steps of the upper
// block sliding on it (an interface, a water level: every field a frame can carry) are those
// at the start. A case without fixed bodies keeps one part.
TEST(RunWriter, FixedBodiesAreWrittenOnceAndNeverChange) {
  const std::string dir = test::temp_dir("run_writer_fixed");
  Simulation<2> sim(test::case_from(test::two_blocks(R"(
[water]
level = 0.5
[[interface]]
bodies = ["upper", "lower"]
friction = { initial = 0.2 }
cohesion = { initial = 0 }
)",
                                                     true),
                                    {"simulation.gravity=[3.0,-9.81]"}));
  const std::size_t lower = sim.body_particles(0), upper = sim.body_particles(1);
  const auto parts = RunWriter<2>::frame_parts(sim);
  EXPECT_EQ(parts.fixed, (ParticleOrder::Spans{{0, lower}}));
  EXPECT_EQ(parts.moving, (ParticleOrder::Spans{{lower, lower + upper}}));
  LocalOrder order(sim.particles().size());
  auto part = [&](const ParticleOrder::Spans& spans) {
    RunWriter<2>::write_particles(dir + "/part.vtu", sim, order, spans);
    return read(dir + "/part.vtu");
  };
  const std::string moving0 = part(parts.moving);
  RunWriter<2> writer(dir, sim, {});
  writer.write_frame(sim, frame_totals(sim, {}), {});
  EXPECT_EQ(writer.missing_frames(),
            std::vector<std::string>({"particles_fixed.vtu", "particles_000000.vtu"}));
  // The first step sorts each body's particles by cell: from then on the fixed part's bytes stand;
  // before it, each particle (by id) already holds the values it keeps.
  auto by_id = [&] {
    const Particles<2>& P = sim.particles();
    std::map<std::uint32_t, std::vector<double>> state;
    for (std::size_t p = 0; p < lower; ++p) {
      std::vector<double>& v = state[P.id[p]];
      for (const double a :
           {P.x[p][0], P.x[p][1], P.v[p][0], P.v[p][1], P.m[p], P.vol[p], P.eps_p[p], P.slip[p],
            P.cohesion[p], P.friction[p], double(P.iface[p]), double(P.field[p])})
        v.push_back(a);
      v.insert(v.end(), P.stress[p].begin(), P.stress[p].end());
    }
    return state;
  };
  const auto state0 = by_id();
  sim.step();
  EXPECT_EQ(by_id(), state0);
  const std::string fixed1 = part(parts.fixed);
  for (int i = 0; i < 200; ++i)
    sim.step();
  EXPECT_TRUE(part(parts.fixed) == fixed1);
  EXPECT_EQ(by_id(), state0);
  EXPECT_FALSE(part(parts.moving) == moving0); // the upper block has moved
  writer.write_frame(sim, frame_totals(sim, {}), {});
  const std::string pvd = read(dir + "/particles.pvd");
  EXPECT_EQ(std::count(pvd.begin(), pvd.end(), '\n'), 5 + 2 * 2) << pvd; // 2 times x 2 parts
  EXPECT_NE(pvd.find("part=\"1\" file=\"particles_fixed.vtu\""), std::string::npos);

  Simulation<2> loose(test::case_from(test::two_blocks()));
  const auto one = RunWriter<2>::frame_parts(loose);
  EXPECT_TRUE(one.fixed.empty());
  EXPECT_EQ(one.moving, (ParticleOrder::Spans{{0, loose.particles().size()}}));
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
