// frame_totals (output/frame_totals.hpp): a frame's per-body sums, the whole momentum and kinetic
// energy, and the probes' particles, against the same sums taken here particle by particle.
#include "talus/output/frame_totals.hpp"
#include "talus/solver/diagnostics.hpp"
#include "two_bodies.hpp"

#include <cmath>
#include <gtest/gtest.h>

using namespace talus;

namespace {

const char* probes = R"(
[[probe]]
name = "top"
body = "upper"
near = [0.8, 0.6]
[[probe]]
name = "base"
body = "lower"
near = [0.2, 0.2]
)";

// Gives every particle a velocity that varies over the bodies, so that no sum is trivial.
template <int D>
void spin(Simulation<D>& sim) {
  Particles<D>& P = sim.particles_mut();
  for (std::size_t p = 0; p < P.size(); ++p)
    P.v[p] = Vec<D>(1.0 + P.x[p][1], -2.0 * P.x[p][0] + 0.3);
}

} // namespace

// Mass, centroid, mean velocity, speeds and kinetic energy per body, the total momentum and
// kinetic energy, and the particle and orphan counts, against sums taken here.
TEST(FrameTotals, BodySumsMatchTheParticles) {
  Simulation<2> sim(test::case_from(test::two_blocks(probes)));
  spin(sim);
  const FrameTotals<2> t = frame_totals(sim, {});
  const auto& P = sim.particles();
  ASSERT_EQ(t.bodies.size(), 2u);
  double ke_all = 0.0;
  Vec<2> momentum = Vec<2>::Zero();
  for (int b = 0; b < 2; ++b) {
    double m = 0.0, ms = 0.0, ke = 0.0, vmax = 0.0;
    Vec<2> mx = Vec<2>::Zero(), mv = Vec<2>::Zero();
    for (std::size_t p = P.body_begin[b]; p < P.body_begin[b + 1]; ++p) {
      const double s = P.v[p].norm();
      m += P.m[p], ms += P.m[p] * s, ke += 0.5 * P.m[p] * s * s, vmax = std::max(vmax, s);
      mx += P.m[p] * P.x[p], mv += P.m[p] * P.v[p];
    }
    const BodyTotals<2>& T = t.bodies[b];
    EXPECT_EQ(T.particles, P.body_begin[b + 1] - P.body_begin[b]);
    EXPECT_NEAR(T.mass, m, 1e-12 * m);
    EXPECT_LT((T.centroid - mx / m).norm(), 1e-12);
    EXPECT_LT((T.velocity - mv / m).norm(), 1e-12);
    EXPECT_NEAR(T.mean_speed, ms / m, 1e-12);
    EXPECT_EQ(T.max_speed, vmax); // a maximum is exact
    EXPECT_NEAR(T.kinetic_energy, ke, 1e-12 * ke);
    EXPECT_EQ(T.orphans, 0u);
    ke_all += ke, momentum += mv;
  }
  EXPECT_NEAR(t.kinetic_energy, ke_all, 1e-12 * ke_all);
  EXPECT_LT((t.momentum - momentum).norm(), 1e-12 * momentum.norm());
  // The upper block's centroid is its box's centre (uniform seeding).
  EXPECT_LT((t.bodies[1].centroid - Vec<2>(0.8, 0.5)).norm(), 1e-12);
}

// The totals are exact sums: the same bits whatever the order the particles are summed in, so a
// sort of the particles by cell (or their share between processes) leaves them unchanged.
TEST(FrameTotals, TheSumsDoNotDependOnParticleOrder) {
  Simulation<2> sim(test::case_from(test::two_blocks()));
  spin(sim);
  const FrameTotals<2> before = frame_totals(sim, {});
  Particles<2>& P = sim.particles_mut();
  // Reverse each body's velocities and positions together: the same set, another order.
  for (int b = 0; b < 2; ++b)
    for (std::size_t i = P.body_begin[b], j = P.body_begin[b + 1] - 1; i < j; ++i, --j) {
      std::swap(P.x[i], P.x[j]);
      std::swap(P.v[i], P.v[j]);
      std::swap(P.m[i], P.m[j]);
    }
  const FrameTotals<2> after = frame_totals(sim, {});
  for (int b = 0; b < 2; ++b) {
    EXPECT_EQ(after.bodies[b].mass, before.bodies[b].mass);
    EXPECT_EQ(after.bodies[b].centroid, before.bodies[b].centroid);
    EXPECT_EQ(after.bodies[b].kinetic_energy, before.bodies[b].kinetic_energy);
  }
  EXPECT_EQ(after.momentum, before.momentum);
}

// A probe reports its particle's position, velocity and starting position; ids are the nearest
// particles of the probe's body to its point.
TEST(FrameTotals, ProbesFollowTheirParticles) {
  Simulation<2> sim(test::case_from(test::two_blocks(probes)));
  spin(sim);
  const std::vector<std::uint32_t> ids = probe_ids(sim);
  ASSERT_EQ(ids.size(), 2u);
  const FrameTotals<2> t = frame_totals(sim, ids);
  ASSERT_EQ(t.probes.size(), 2u);
  const auto& P = sim.particles();
  for (std::size_t k = 0; k < 2; ++k) {
    const std::size_t p = sim.index_of(ids[k]);
    EXPECT_EQ(t.probes[k].x, P.x[p]);
    EXPECT_EQ(t.probes[k].v, P.v[p]);
    EXPECT_EQ(t.probes[k].x0, P.x0[p]);
  }
  EXPECT_EQ(P.body_of(sim.index_of(ids[0])), 1); // "top" is in the upper block
  EXPECT_LT((P.x[sim.index_of(ids[0])] - Vec<2>(0.8, 0.6)).norm(), 0.1);
  EXPECT_EQ(P.body_of(sim.index_of(ids[1])), 0);
}

// A surface gauge reads the top of the body's column over its point (lower's top at 0.4 m: its
// top particles at 0.375 m plus half their 0.05 m spacing; 0.1 m cells). A particle thrown clear
// of it (an empty grid row between) is spray and does not count; one in the row just above the
// top joins the column and does.
TEST(FrameTotals, GaugesReadTheContiguousSurface) {
  Simulation<2> sim(
      test::case_from(test::two_blocks("[[gauge]]\nname = \"g\"\nbody = \"lower\"\nat = 1.5\n")));
  EXPECT_DOUBLE_EQ(frame_totals(sim, {}).gauges.at(0), 0.4);
  Particles<2>& P = sim.particles_mut();
  std::size_t p = 0; // one of lower's particles under the gauge, near its bottom
  while (P.body_of(p) != 0 || std::abs(P.x[p][0] - 1.525) > 1e-9 || P.x[p][1] > 0.25)
    ++p;
  P.x[p][1] = 0.85; // spray: rows 4-7 (0.4-0.8 m) are empty under it
  EXPECT_DOUBLE_EQ(frame_totals(sim, {}).gauges.at(0), 0.4);
  P.x[p][1] = 0.45; // on the surface: row 4 (0.4-0.5 m) joins rows 2-3
  EXPECT_DOUBLE_EQ(frame_totals(sim, {}).gauges.at(0), 0.475);
}
