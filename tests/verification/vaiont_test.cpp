// The flagship case at a very coarse spacing (8 m: 16 m cells): after the geostatic settling the
// slide must be nearly at rest, then move, reach a peak speed and stop. The figures are printed;
// docs/vaiont.md compares them with the paper and the literature ranges (which they miss: the
// slide is slower and travels less, see there).
#include "talus/run/run.hpp"
#include "test_support.hpp"

#include <cmath>
#include <fstream>
#include <gtest/gtest.h>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

namespace talus {
namespace {

TEST(Vaiont, ThreeBodiesMoveAndStop) {
  const Case c = parse_case_file(std::string(TALUS_SOURCE_DIR) + "/cases/vaiont/three_bodies.toml",
                                 {"grid.cell_size=16", "interface.0.friction.slip=0.08",
                                  "interface.0.cohesion.slip=0.08", "output.particles=false"});
  RunOptions opt;
  opt.out_dir = test::temp_dir("vaiont");
  const RunResult r = run_case(c, opt);
  ASSERT_EQ(r.status, "completed") << r.message;
  nlohmann::json s;
  std::ifstream(opt.out_dir + "/summary.json") >> s;
  const auto& res = s["results"];
  std::printf("vaiont (8 m spacing): %s\n", res.dump().c_str());
  const double slide_mass = 160170.0 * 2400.0; // kg per m
  // At rest at release: kinetic energy below that of the slide moving at 0.2 m/s.
  EXPECT_LT(res["kinetic_energy_at_release_J"].get<double>(), 0.5 * slide_mass * 0.2 * 0.2);
  EXPECT_GT(res["peak_mean_speed_m_s"].get<double>(), 5.0);         // it fails and runs
  EXPECT_GT(res["centroid_displacement_x_m"].get<double>(), 100.0); // towards the north slope
  EXPECT_FALSE(res["still_moving_at_end"].get<bool>());             // and stops
  EXPECT_LT(res["runout_duration_s"].get<double>(), 45.0);
}

// The five-body case at 4 m: the slide's parts are cut off from their bodies here and there
// along the faults. Before the orphan rule (docs/formulation.md) such particles were squeezed to
// 960 MPa and chattered at up to 94 m/s to the end, and the energy budget of all bodies was off
// by -270 % of the gravity work at 45 s. Now: every particle is slow at the end and the budget of
// all bodies together closes to -2.3 % at 4 m. At 8 m it is off by 10 % (-9.9 % before the
// cohesive capacity was shared over the nodes where the pair meets, -10.8 % after): the coarse
// grid's own error, too loose to be worth a test.
TEST(Vaiont, FiveBodiesEndAtRestAndTheirBudgetCloses) {
  const Case c = parse_case_file(std::string(TALUS_SOURCE_DIR) + "/cases/vaiont/five_bodies.toml",
                                 {"grid.cell_size=8", "output.particles=false"});
  RunOptions opt;
  opt.out_dir = test::temp_dir("vaiont5");
  const RunResult r = run_case(c, opt);
  ASSERT_EQ(r.status, "completed") << r.message;
  // The last row of each body in bodies.csv.
  std::ifstream in(opt.out_dir + "/bodies.csv");
  std::string line;
  std::getline(in, line);
  std::vector<std::string> header;
  for (std::stringstream ss(line); std::getline(ss, line, ',');)
    header.push_back(line);
  std::map<std::string, std::map<std::string, std::string>> last;
  while (std::getline(in, line)) {
    std::map<std::string, std::string> row;
    std::stringstream ss(line);
    for (const std::string& h : header)
      std::getline(ss, row[h], ',');
    last[row["body"]] = row;
  }
  ASSERT_EQ(last.size(), 5u);
  double gravity = 0.0, unbalanced = 0.0;
  for (auto& [body, row] : last) {
    auto num = [&](const char* k) { return std::stod(row.at(k)); };
    EXPECT_DOUBLE_EQ(num("time"), 45.0);
    EXPECT_LT(num("max_speed"), 5.0) << body; // no chattering particle
    gravity += num("gravity_work");
    unbalanced +=
        num("gravity_work") + num("contact_work") - num("internal_work") - num("kinetic_energy");
  }
  std::printf("five bodies (4 m): all bodies' unbalanced energy %.3g J of %.3g J gravity work\n",
              unbalanced, gravity);
  EXPECT_LT(std::abs(unbalanced), 0.05 * gravity);
}

} // namespace
} // namespace talus
