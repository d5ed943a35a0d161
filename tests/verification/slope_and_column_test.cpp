// The two large-deformation benchmarks of the paper (sections 3.5 and 3.6), at CI resolution.
// Cohesive slope: the slope must fail along a deep, circular-like band that starts behind the crest
// and passes at toe level, at two resolutions. Column collapse: the block must keep an undisturbed
// wedge against the wall (height there stays 0.1 m) while the rest runs out. Measured figures
// are printed and recorded in docs/verification.md.
#include "talus/solver/simulation.hpp"
#include "test_support.hpp"

#include <cmath>
#include <gtest/gtest.h>
#include <numbers>

namespace talus {
namespace {

Simulation<2> run(const std::string& file, const std::vector<std::string>& overrides) {
  const Case c =
      parse_case_file(std::string(TALUS_SOURCE_DIR) + "/cases/benchmarks/" + file, overrides);
  Simulation<2> sim(c);
  while (sim.time() < c.simulation.end_time - 1e-12)
    sim.step(c.simulation.end_time - sim.time());
  return sim;
}

struct SlopeFigures {
  double crest_settlement, runout, band_top_x, band_depth;
};

SlopeFigures slope_figures(const Simulation<2>& sim) {
  const auto& P = sim.particles();
  SlopeFigures f{0, 0, 1e9, 1e9};
  double crest_d = 1e9;
  for (std::size_t p = 0; p < P.size(); ++p) {
    const Vec<2> x0 = P.x0[p];
    const double d = (x0 - Vec<2>(30.0, 35.0)).norm();
    if (d < crest_d) crest_d = d, f.crest_settlement = x0[1] - P.x[p][1];
    if (x0[1] > 15.0)
      f.runout = std::max(f.runout, P.x[p][0] - 50.0); // slope material past the toe
    if (P.eps_p[p] > 0.3) {
      if (x0[1] > 34.0) f.band_top_x = std::min(f.band_top_x, x0[0]); // where the band daylights
      if (x0[0] > 30.0 && x0[0] < 50.0) f.band_depth = std::min(f.band_depth, x0[1]);
    }
  }
  return f;
}

TEST(CohesiveSlope, FailsAlongADeepBandAtTwoResolutions) {
  for (double h : {2.0, 1.0}) {
    const SlopeFigures f =
        slope_figures(run("cohesive_slope.toml", {"grid.cell_size=" + std::to_string(h)}));
    std::printf(
        "cohesive slope, cell %.1f m: crest settlement %.2f m, run-out past the toe %.2f m, "
        "band daylights at x = %.1f m, band reaches y = %.1f m\n",
        h, f.crest_settlement, f.runout, f.band_top_x, f.band_depth);
    // The slope fails: measured crest settlement 6.7 and 8.2 m at 2 and 1 m cells. The run-out
    // is not converged in the cell size (4.2 and 10.0 m): it only has to pass the toe.
    EXPECT_GT(f.crest_settlement, 6.0);
    EXPECT_LT(f.crest_settlement, 11.0);
    EXPECT_GT(f.runout, 3.0);
    EXPECT_LT(f.band_top_x, 30.0); // the band starts behind the crest edge ...
    EXPECT_LT(f.band_depth, 17.0); // ... and passes at toe level (y = 15 m): a deep mechanism
  }
}

TEST(ColumnCollapse, KeepsAWedgeAtTheWallAndRunsOut) {
  const Simulation<2> sim = run("column_collapse.toml", {"grid.cell_size=0.005"});
  const auto& P = sim.particles();
  double runout = 0, wall_height = 0, top_x = 1;
  for (std::size_t p = 0; p < P.size(); ++p) {
    runout = std::max(runout, P.x[p][0]);
    if (P.x[p][0] < 0.01) wall_height = std::max(wall_height, P.x[p][1]);
    if (P.x0[p][1] > 0.09 && (P.x[p] - P.x0[p]).norm() > 0.02) top_x = std::min(top_x, P.x0[p][0]);
  }
  const double angle = std::atan2(0.1, 0.2 - top_x) * 180.0 / std::numbers::pi;
  std::printf("column collapse, cell 5 mm: run-out %.3f m, height at the wall %.4f m, failure line "
              "%.1f deg (Rankine 45 + phi/2 = %.1f deg); experiment 0.442 m, 0.099 m, 32 deg\n",
              runout, wall_height, angle, 45.0 + 19.8 / 2.0);
  // Bui et al. 2008's experiment (its final surface and failure line as digitised in the
  // documentation of LandslideSIM/MaterialPointSolver.jl): the wall keeps 0.099 m, the toe is at
  // 0.442 m and the failure line runs at 32 degrees from (0.021, 0.099) to (0.179, 0), far
  // flatter than Rankine's 54.9. Here, at the CI's 5 mm cells: 0.0985 m, 0.384 m (-13 %; -8 % at
  // 2.5 mm) and 36 degrees (33 at 2.5 mm).
  EXPECT_GT(wall_height, 0.095);
  EXPECT_NEAR(runout, 0.442, 0.15 * 0.442);
  EXPECT_NEAR(angle, 32.0, 5.0);
  // Kinetic energy at the end: the deposit has stopped.
  double ke = 0;
  for (std::size_t p = 0; p < P.size(); ++p)
    ke += 0.5 * P.m[p] * P.v[p].squaredNorm();
  EXPECT_LT(ke, 1e-4);
}

} // namespace
} // namespace talus
