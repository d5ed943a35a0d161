// A block sliding on a Coulomb wall (the grid's base face with friction mu) decelerates at mu g:
// x(t) = v0 t - mu g t^2 / 2 until it stops at v0^2 / (2 mu g).
// (The contact benchmarks of the multi-body issue use bodies, not this grid wall.)
#include "talus/solver/simulation.hpp"
#include "test_support.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

namespace talus {
namespace {

TEST(FrictionWall, SlidingBlockDeceleratesAtMuG) {
  const double mu = 0.3, v0 = 2.0, g = 9.81;
  const Case c = test::case_from(fmt::format(R"(
[simulation]
end_time = 1.0
gravity = [0, -{}]
scheme = "musl"
cfl = 0.3
[grid]
extent = [4, 1]
cell_size = 0.05
[grid.boundary]
y_min = {{ friction = {} }}
[[material]]
name = "m"
density = 2000
youngs_modulus = 5e7
poisson_ratio = 0.3
[[body]]
name = "block"
material = "m"
box = {{ min = [0.2, 0], max = [0.7, 0.25] }}
velocity = [{}, 0]
)",
                                             g, mu, v0));
  Simulation<2> sim(c);
  auto centroid_x = [&] {
    double m = 0, mx = 0;
    for (std::size_t p = 0; p < sim.particles().size(); ++p)
      m += sim.particles().m[p], mx += sim.particles().m[p] * sim.particles().x[p][0];
    return mx / m;
  };
  const double x0 = centroid_x();
  // Two times while sliding and one after the stop (t = v0 / (mu g) = 0.68 s), each within 0.5 %.
  for (double t : {0.25, 0.5, 0.9}) {
    while (sim.time() < t - 1e-12)
      sim.step(t - sim.time());
    const double t_stop = v0 / (mu * g);
    const double expected = t < t_stop ? v0 * t - 0.5 * mu * g * t * t : v0 * v0 / (2 * mu * g);
    const double got = centroid_x() - x0;
    std::printf("friction wall t = %.2f: %.5f m (closed form %.5f, error %.3f %%)\n", t, got,
                expected, 100 * std::abs(got - expected) / expected);
    EXPECT_NEAR(got, expected, 0.005 * expected);
  }
}

} // namespace
} // namespace talus
