// K0 initial stresses on a horizontal layer: sigma_v = -rho g (H - y) at each row's depth,
// sigma_h = K0 sigma_v with K0 = nu / (1 - nu) or the case's k0. The particles of a row that share
// a grid column are walked one after the other, so each carries the weight of the ones before it
// in the row: a particle is within a quarter of its own weight per column area (rho g s / 4, s
// the spacing, two per column) of the row's overburden, and the row's mean is exact.
#include "talus/case/geometry.hpp"
#include "talus/setup/initial_state.hpp"
#include "talus/setup/seeds.hpp"
#include "test_support.hpp"

#include <cmath>
#include <gtest/gtest.h>
#include <map>

namespace talus {
namespace {

std::string layer(const std::string& k0) {
  return R"(
[simulation]
dimension = 2
end_time = 1.0
gravity = [0, -9.81]
[grid]
extent = [1.0, 1.2]
cell_size = 0.1
[[material]]
name = "m"
density = 1800
youngs_modulus = 1e7
poisson_ratio = 0.3
[[body]]
name = "layer"
material = "m"
box = { min = [0.0, 0.0], max = [1.0, 0.8] }
[initial_state]
method = "k0"
)" + k0;
}

TEST(K0Stress, HorizontalLayerMatchesTheOverburden) {
  for (const std::string& k0 : {std::string(), std::string("k0 = 0.6\n")}) {
    const Case c = test::case_from(layer(k0));
    Particles<2> P = fill_particles<2>(c);
    apply_k0_stress<2>(c, P);
    const double K0 = k0.empty() ? 0.3 / 0.7 : 0.6, H = 0.8, rho = 1800, g = 9.81;
    const double s = 0.05, tol = 1e-9 * rho * g * H;
    std::map<long, std::pair<double, int>> rows; // row: sum of sigma_v, particles
    for (std::size_t p = 0; p < P.size(); ++p) {
      const double sv = -rho * g * (H - P.x[p][1]);
      EXPECT_NEAR(P.stress[p][1], sv, 0.25 * rho * g * s + tol) << p;
      EXPECT_NEAR(P.stress[p][0], K0 * P.stress[p][1], tol) << p;
      EXPECT_NEAR(P.stress[p][2], K0 * P.stress[p][1], tol) << p;
      EXPECT_EQ(P.stress[p][3], 0.0) << p;
      auto& row = rows[std::lround(P.x[p][1] / s - 0.5)];
      row.first += P.stress[p][1], ++row.second;
    }
    for (const auto& [k, row] : rows)
      EXPECT_NEAR(row.first / row.second, -rho * g * (H - (k + 0.5) * s), tol) << k;
  }
}

// Below a water level (here between two rows) the effective overburden: the buoyant unit weight
// (rho - rho_w) g below the level, rho g above it.
TEST(K0Stress, BelowAWaterLevelTheEffectiveOverburden) {
  const Case c = test::case_from(layer("[water]\nlevel = 0.4\ndensity = 1000\n"));
  Particles<2> P = fill_particles<2>(c);
  apply_k0_stress<2>(c, P);
  const double H = 0.8, level = 0.4, rho = 1800, rho_w = 1000, g = 9.81, s = 0.05;
  std::map<long, std::pair<double, int>> rows;
  for (std::size_t p = 0; p < P.size(); ++p) {
    auto& row = rows[std::lround(P.x[p][1] / s - 0.5)];
    row.first += P.stress[p][1], ++row.second;
  }
  for (const auto& [k, row] : rows) {
    const double y = (k + 0.5) * s;
    const double sv =
        y > level ? -rho * g * (H - y) : -(rho * g * (H - level) + (rho - rho_w) * g * (level - y));
    EXPECT_NEAR(row.first / row.second, sv, 1e-9 * rho * g * H) << k;
  }
}

} // namespace
} // namespace talus
