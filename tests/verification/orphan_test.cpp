// Orphan particles (contact.orphan_fraction, docs/formulation.md): a particle of one body cut
// off from it inside another deformable body maps to that body's field and moves with it; the
// particles of a clean interface between two bodies never do; momentum is conserved throughout.
#include "talus/setup/seeding.hpp"
#include "talus/solver/simulation.hpp"
#include "test_support.hpp"

#include <cmath>
#include <fmt/format.h>
#include <gtest/gtest.h>
#ifdef _OPENMP
#include <omp.h>
#endif

namespace talus {
namespace {

// A 0.5 m x 1 m elastic column ("host", body 0) with its base at y0 and a one-particle body
// ("lone", body 1) seeded in the air above it. The test swaps the lone particle with the host
// particle nearest the column's middle, so that it sits inside the column, cut off from its body.
struct ColumnCase {
  double fraction = 0.1;
  std::string scheme = "musl";
  std::string gravity = "[0, -9.81]";
  double damping = 0.0;
  double extent_x = 0.5, x0 = 0.0, y0 = 0.0;
  std::string boundary = "x_min = \"slip\"\nx_max = \"slip\"\ny_min = \"fixed\"";
};

std::string column_case(const ColumnCase& k) {
  return fmt::format(R"(
[simulation]
end_time = 1.0
gravity = {}
scheme = "{}"
flip = 0.99
damping = {}
[grid]
extent = [{}, 1.5]
cell_size = 0.05
[grid.boundary]
{}
[[material]]
name = "m"
density = 2000
youngs_modulus = 1e6
poisson_ratio = 0.3
[[body]]
name = "host"
material = "m"
box = {{ min = [{}, {}], max = [{}, {}] }}
[[body]]
name = "lone"
material = "m"
box = {{ min = [{}, 1.3], max = [{}, 1.325] }}
[[contact]]
friction = 0.0
orphan_fraction = {}
)",
                     k.gravity, k.scheme, k.damping, k.extent_x, k.boundary, k.x0, k.y0, k.x0 + 0.5,
                     k.y0 + 1.0, k.x0, k.x0 + 0.025, k.fraction);
}

// Builds the column with the lone particle inside; returns the lone particle's index.
std::size_t embed_lone_particle(Simulation<2>& sim) {
  auto& P = sim.particles_mut();
  EXPECT_EQ(P.body_begin[2] - P.body_begin[1], 1u) << "the lone body must be one particle";
  const std::size_t lone = P.body_begin[1];
  const Vec<2> middle = 0.5 * (P.x[0] + P.x[P.body_begin[1] - 1]);
  const std::size_t host = nearest_particle(sim.particles(), 0, middle);
  std::swap(P.x[lone], P.x[host]);
  std::swap(P.x0[lone], P.x0[host]);
  return lone;
}

// The lone particle joins the column's field after the first step and then settles with it: its
// displacement and stress are those of the column around it. The host particle moved to the air
// stays in its own body's field (nothing of another body is around it).
class OrphansIn : public ::testing::TestWithParam<const char*> {};

TEST_P(OrphansIn, EmbeddedParticleJoinsTheBodyAroundItAndMovesWithIt) {
  const Case c = test::case_from(column_case({.scheme = GetParam(), .damping = 0.3}));
  Simulation<2> sim(c);
  const std::size_t lone = embed_lone_particle(sim);
  const std::uint32_t lone_id = sim.particles().id[lone];
  sim.step();
  EXPECT_EQ(sim.orphans(), 1);
  while (sim.time() < 1.0)
    sim.step();
  const auto& P = sim.particles();
  const std::size_t p = sim.index_of(lone_id);
  EXPECT_EQ(P.field[p], 0) << "the lone particle maps to the column's field";
  EXPECT_EQ(sim.orphans(), 1);
  for (std::size_t q = 0; q < P.body_begin[1]; ++q)
    EXPECT_EQ(P.field[q], 0);
  // The column's particles around it (within 1.5 spacings).
  double uy = 0.0, syy = 0.0;
  int n = 0;
  for (std::size_t q = 0; q < P.body_begin[1]; ++q)
    if ((P.x0[q] - P.x0[p]).norm() < 1.5 * 0.025)
      uy += P.x[q][1] - P.x0[q][1], syy += P.stress[q][1], ++n;
  ASSERT_EQ(n, 8);
  uy /= n, syy /= n;
  // Settled under its own weight between slip walls (uniaxial strain): at y = 0.5,
  // u_y = -rho g (y - y^2 / 2) / M = -5.47 mm with M = E (1 - nu) / ((1 + nu)(1 - 2 nu)), and
  // sigma_yy = -rho g (1 - y) = -9.81 kPa.
  EXPECT_NEAR(uy, -5.47e-3, 0.3e-3);
  EXPECT_NEAR(syy, -9.81e3, 0.5e3);
  const double lone_uy = P.x[p][1] - P.x0[p][1];
  EXPECT_NEAR(lone_uy, uy, 0.02 * std::abs(uy)) << "it moves with the column";
  EXPECT_NEAR(P.stress[p][1], syy, 0.15 * std::abs(syy)) << "and carries the column's stress";
}

INSTANTIATE_TEST_SUITE_P(Schemes, OrphansIn, ::testing::Values("musl", "usl", "usf"));

#ifdef _OPENMP
// The decision pass and the orphan's transfers run in parallel: 1 and 2 threads agree bit for bit.
TEST(Orphans, OneAndTwoThreadsAreBitwiseIdentical) {
  const Case c = test::case_from(column_case({.damping = 0.3}));
  auto run = [&](int threads) {
    const int before = omp_get_max_threads();
    omp_set_num_threads(threads);
    Simulation<2> sim(c);
    embed_lone_particle(sim);
    for (int s = 0; s < 200; ++s)
      sim.step();
    omp_set_num_threads(before);
    EXPECT_EQ(sim.orphans(), 1);
    return sim.particles();
  };
  const Particles<2> one = run(1), two = run(2);
  ASSERT_EQ(one.size(), two.size());
  for (std::size_t p = 0; p < one.size(); ++p) {
    ASSERT_TRUE(one.x[p] == two.x[p]) << p;
    ASSERT_TRUE(one.v[p] == two.v[p]) << p;
    ASSERT_TRUE(one.stress[p] == two.stress[p]) << p;
    ASSERT_EQ(one.field[p], two.field[p]) << p;
  }
}
#endif

// With no gravity and no floor, the column moving at 1 m/s and the lone particle inside it at
// rest: the particle is carried along at the column's speed, and the total momentum stays that
// of the start to round-off (the orphan's field is the column's: one field, no contact).
TEST(Orphans, MomentumIsConservedWhileTheOrphanIsCarried) {
  const Case c = test::case_from(
      column_case({.gravity = "[0, 0]", .extent_x = 1.5, .x0 = 0.2, .y0 = 0.2, .boundary = ""}));
  Simulation<2> sim(c);
  const std::size_t lone = embed_lone_particle(sim);
  auto& P = sim.particles_mut();
  for (std::size_t q = 0; q < P.size(); ++q)
    P.v[q] = Vec<2>(q == lone ? 0.0 : 1.0, 0.0);
  const std::uint32_t lone_id = P.id[lone];
  auto momentum = [&] {
    Vec<2> m = Vec<2>::Zero();
    for (std::size_t q = 0; q < sim.particles().size(); ++q)
      m += sim.particles().m[q] * sim.particles().v[q];
    return m;
  };
  const Vec<2> p0 = momentum();
  while (sim.time() < 0.5)
    sim.step();
  EXPECT_EQ(sim.orphans(), 1);
  const Vec<2> p1 = momentum();
  EXPECT_NEAR(p1[0], p0[0], 1e-12 * p0[0]);
  EXPECT_NEAR(p1[1], 0.0, 1e-12 * p0[0]);
  EXPECT_NEAR(sim.particles().v[sim.index_of(lone_id)][0], 1.0, 0.02)
      << "the orphan is carried at the column's speed";
}

} // namespace
} // namespace talus
