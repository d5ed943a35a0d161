// An elastic column under its own weight, damped to rest
// (cases/benchmarks/self_weight_column.toml): sigma_yy = -rho g (H - y) and sigma_xx = nu / (1 -
// nu) sigma_yy within 2 % of rho g H.
#include "talus/solver/simulation.hpp"
#include "test_support.hpp"

#include <cmath>
#include <gtest/gtest.h>

namespace talus {
namespace {

TEST(SelfWeightColumn, StressMatchesTheOverburden) {
  const Case c =
      parse_case_file(std::string(TALUS_SOURCE_DIR) + "/cases/benchmarks/self_weight_column.toml");
  Simulation<2> sim(c);
  while (sim.time() < c.simulation.end_time)
    sim.step(c.simulation.end_time - sim.time());
  const auto& mat = std::get<LinearElastic>(c.materials[0].model);
  const double rho = mat.density, g = 9.81, H = 4.0, nu = mat.poisson_ratio;
  const auto& P = sim.particles();
  double worst_yy = 0.0, worst_xx = 0.0, ke = 0.0;
  for (std::size_t p = 0; p < P.size(); ++p) {
    // Depth in the reference configuration (the overburden mass above the particle is fixed).
    const double sigma_yy = -rho * g * (H - P.x0[p][1]);
    worst_yy = std::max(worst_yy, std::abs(P.stress[p][1] - sigma_yy));
    worst_xx = std::max(worst_xx, std::abs(P.stress[p][0] - nu / (1.0 - nu) * sigma_yy));
    ke += 0.5 * P.m[p] * P.v[p].squaredNorm();
  }
  std::printf(
      "self-weight column: max stress error / (rho g H): yy %.4f, xx %.4f; kinetic energy %.3g J\n",
      worst_yy / (rho * g * H), worst_xx / (rho * g * H), ke);
  EXPECT_LT(worst_yy / (rho * g * H), 0.02);
  EXPECT_LT(worst_xx / (rho * g * H), 0.02);
  EXPECT_LT(ke, 1e-6 * rho * g * H * H); // at rest
}

} // namespace
} // namespace talus
