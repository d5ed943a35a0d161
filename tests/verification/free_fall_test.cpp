// Free fall: a body with no support falls x = g t^2 / 2 and v = g t to round-off, in 2D and 3D,
// for every scheme (the position update uses the mean of v^n and v^{n+1}).
#include "talus/solver/simulation.hpp"
#include "test_support.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

namespace talus {
namespace {

template <int D>
void check_free_fall(const std::string& scheme, const std::string& shape) {
  const std::string dims = D == 2 ? "[4, 4]" : "[4, 4, 4]";
  const std::string lo = D == 2 ? "[1.5, 2.5]" : "[1.5, 1.5, 2.5]";
  const std::string hi = D == 2 ? "[2.5, 3.5]" : "[2.5, 2.5, 3.5]";
  const std::string g = D == 2 ? "[0, -9.81]" : "[0, 0, -9.81]";
  const double dt = 1e-3;
  const Case c = test::case_from(fmt::format(R"(
[simulation]
dimension = {}
end_time = 0.5
dt = {}
gravity = {}
scheme = "{}"
[grid]
extent = {}
cell_size = 0.25
shape_function = "{}"
[[material]]
name = "m"
density = 1000
youngs_modulus = 1e6
poisson_ratio = 0.2
[[body]]
name = "b"
material = "m"
box = {{ min = {}, max = {} }}
)",
                                             D, dt, g, scheme, dims, shape, lo, hi));
  Simulation<D> sim(c);
  const auto x0 = sim.particles().x;
  const auto id0 = sim.particles().id;
  const int steps = 500;
  for (int s = 0; s < steps; ++s)
    sim.step();
  const double t = steps * dt;
  EXPECT_NEAR(sim.time(), t, 1e-12);
  const auto& P = sim.particles();
  for (std::size_t p = 0; p < P.size(); ++p) {
    const Vec<D> start = x0[P.id[p]];
    ASSERT_EQ(id0[P.id[p]], P.id[p]);
    Vec<D> expected = start;
    expected[D - 1] -= 0.5 * 9.81 * t * t;
    EXPECT_LT((P.x[p] - expected).norm(), 1e-11) << scheme << " " << shape << " particle " << p;
    EXPECT_NEAR(P.v[p][D - 1], -9.81 * t, 1e-11);
    EXPECT_LT(P.stress[p].norm(), 1e-6);
  }
}

TEST(FreeFall, TwoDimensions) {
  for (const char* scheme : {"usf", "usl", "musl"})
    for (const char* shape : {"linear", "gimp", "bspline"})
      check_free_fall<2>(scheme, shape);
}

TEST(FreeFall, ThreeDimensions) {
  for (const char* scheme : {"usl", "musl"})
    for (const char* shape : {"gimp", "bspline"})
      check_free_fall<3>(scheme, shape);
}

} // namespace
} // namespace talus
