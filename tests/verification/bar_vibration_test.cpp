// Axial vibration of an elastic bar in its first mode (cases/benchmarks/bar_vibration.toml): the
// centre-of-mass velocity follows (2 v0 / pi) cos(omega t) within 2 % of its amplitude over about
// three periods, in 2D (plane strain, nu = 0) and in 3D.
#include "talus/solver/simulation.hpp"
#include "test_support.hpp"

#include <cmath>
#include <gtest/gtest.h>
#include <numbers>

namespace talus {
namespace {

template <int D>
double max_error_over_amplitude(const std::vector<std::string>& overrides) {
  const Case c = parse_case_file(
      std::string(TALUS_SOURCE_DIR) + "/cases/benchmarks/bar_vibration.toml", overrides);
  Simulation<D> sim(c);
  const double L = 1.0, v0 = 0.01;
  const auto& mat = std::get<LinearElastic>(c.materials[0].model);
  const double beta = std::numbers::pi / (2.0 * L);
  const double omega = beta * std::sqrt(mat.youngs_modulus / mat.density);
  auto& P = sim.particles_mut();
  for (std::size_t p = 0; p < P.size(); ++p)
    P.v[p][0] = v0 * std::sin(beta * P.x[p][0]);
  const double amplitude = 2.0 * v0 / std::numbers::pi;
  double worst = 0.0;
  while (sim.time() < c.simulation.end_time) {
    sim.step(c.simulation.end_time - sim.time());
    double m = 0.0, mv = 0.0;
    for (std::size_t p = 0; p < P.size(); ++p)
      m += P.m[p], mv += P.m[p] * P.v[p][0];
    worst = std::max(worst, std::abs(mv / m - amplitude * std::cos(omega * sim.time())));
  }
  return worst / amplitude;
}

TEST(BarVibration, TwoDimensionsWithinTwoPercent) {
  const double e = max_error_over_amplitude<2>({});
  RecordProperty("max_error_over_amplitude", std::to_string(e));
  std::printf("bar vibration 2D: max |v_cm - exact| / amplitude = %.4f\n", e);
  EXPECT_LT(e, 0.02);
}

TEST(BarVibration, ThreeDimensionsWithinTwoPercent) {
  const double e = max_error_over_amplitude<3>(
      {"simulation.dimension=3", "grid.origin=[0.0, 0.0, 0.0]", "grid.extent=[1.2, 0.2, 0.2]",
       "body.bar.box.min=[0.0, 0.06, 0.06]", "body.bar.box.max=[1.0, 0.14, 0.14]"});
  std::printf("bar vibration 3D: max |v_cm - exact| / amplitude = %.4f\n", e);
  EXPECT_LT(e, 0.02);
}

} // namespace
} // namespace talus
