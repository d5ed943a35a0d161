// G2P (solver/g2p.cpp): a PIC gather returns the grid's momentum to the particles; walls keep
// particles in; XPIC(1) is PIC, and XPIC(m) keeps the momentum with contact and removes the
// velocities the grid cannot represent.
#include "block_case.hpp"
#include "talus/solver/detail.hpp"
#include "talus/solver/simulation.hpp"
#include "test_support.hpp"
#include "two_bodies.hpp"

#include <algorithm>
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <string>

namespace talus {
namespace {

using test::block_case;
using test::randomise;

template <class T>
class G2P : public ::testing::Test {};
TYPED_TEST_SUITE(G2P, test::Dims);

TYPED_TEST(G2P, PicGatherReturnsTheGridMomentum) {
  constexpr int D = TypeParam::value;
  Simulation<D> sim(test::case_from(block_case<D>("gimp", "usl", 0.0)));
  randomise(sim.particles_mut(), 5);
  sim.bin_particles_by_slab();
  sim.fit_body_fields();
  sim.map_particles_to_nodes(true);
  const double dt = 1e-4;
  sim.compute_node_velocities();
  sim.integrate_node_forces(dt);
  Vec<D> grid_momentum = Vec<D>::Zero();
  const auto& N = sim.fields()[0];
  for (std::size_t i = 0; i < N.size(); ++i)
    grid_momentum += N.m[i] * N.v_new[i];
  sim.update_particles(dt); // moving does not change the momentum
  Vec<D> particle_momentum = Vec<D>::Zero();
  double mass = 0.0;
  for (std::size_t p = 0; p < sim.particles().size(); ++p)
    particle_momentum += sim.particles().m[p] * sim.particles().v[p], mass += sim.particles().m[p];
  EXPECT_LT((particle_momentum - grid_momentum).norm(), 1e-12 * mass);
}

// A face that is a wall (fixed, slip or friction) keeps particles in: a block thrown at it at
// 2 km/s, FLIP 1 (its velocity kept), one step of 1 ms (2 m), ends on the wall with no velocity
// into it, where a free face lets it leave (BadState.StopsWithTheStepThatMadeIt); a rigid body
// driven through the wall is stopped as having left the grid.
TYPED_TEST(G2P, WallsKeepParticlesIn) {
  constexpr int D = TypeParam::value;
  for (const char* wall : {"\"fixed\"", "\"slip\"", "{ friction = 0.3 }"})
    for (const char* scheme : {"usl", "musl"}) {
      const std::string text =
          block_case<D>("gimp", scheme, 1.0) + fmt::format("[grid.boundary]\nx_min = {}\n", wall);
      Simulation<D> sim(test::case_from(text, {"simulation.dt=1e-3"}));
      for (auto& v : sim.particles_mut().v)
        v.setZero(), v[0] = -2000.0;
      ASSERT_NO_THROW(sim.step()) << wall << ", " << scheme;
      const auto& P = sim.particles();
      for (std::size_t p = 0; p < P.size(); ++p) {
        ASSERT_GE(P.x[p][0], 0.0) << wall << ", " << scheme << ", particle " << p;
        ASSERT_GE(P.v[p][0], 0.0) << wall << ", " << scheme << ", particle " << p;
      }
    }
  // A rigid body driven through a wall keeps its prescribed motion: it has left the grid.
  const std::string rigid =
      block_case<D>("gimp", "musl", 1.0) + "rigid = true\n[grid.boundary]\nx_min = \"slip\"\n";
  Simulation<D> sim(
      test::case_from(rigid, {"simulation.dt=1e-3", D == 2 ? "body.a.velocity=[-2000, 0]"
                                                           : "body.a.velocity=[-2000, 0, 0]"}));
  try {
    sim.step();
    ADD_FAILURE() << "a rigid body driven through a wall was not stopped";
  } catch (const SimulationError& e) {
    EXPECT_NE(std::string(e.what()).find("left the grid"), std::string::npos) << e.what();
  }
}

// XPIC(1) carries S v* = S v_c, which is PIC: the same bits as flip = 0, under each scheme.
TYPED_TEST(G2P, XpicOfOrderOneIsPic) {
  constexpr int D = TypeParam::value;
  for (const char* scheme : {"usl", "musl"}) {
    Simulation<D> pic(test::case_from(block_case<D>("gimp", scheme, 0.0)));
    Simulation<D> xpic(test::case_from(block_case<D>("gimp", scheme, 1.0), {"simulation.xpic=1"}));
    randomise(pic.particles_mut(), 7);
    randomise(xpic.particles_mut(), 7);
    for (int s = 0; s < 5; ++s)
      pic.step(), xpic.step();
    EXPECT_EQ(pic.particles().v, xpic.particles().v) << scheme;
    EXPECT_EQ(pic.particles().x, xpic.particles().x) << scheme;
  }
}

// XPIC(m) keeps the momentum: the series' terms (I - S^+ S)^k v_c carry none, and contact
// exchanges it between the bodies. Two blocks pressed together (the upper thrown down at
// 2 m/s onto the lower, random velocities on top), no gravity, away from the grid's faces: the
// particles' total momentum after 20 steps is the start's, for m = 2 and 4.
TEST(Xpic, KeepsMomentumThroughContact) {
  for (const int m : {2, 4}) {
    Simulation<2> sim(test::case_from(test::two_blocks("[[contact]]\nfriction = 0.3\n"),
                                      {"simulation.gravity=[0, 0]", "simulation.flip=1.0",
                                       fmt::format("simulation.xpic={}", m)}));
    auto& P = sim.particles_mut();
    randomise(P, 3);
    for (std::size_t p = P.body_begin[1]; p < P.body_begin[2]; ++p)
      P.v[p][1] -= 2.0;
    auto momentum = [&] {
      Vec<2> sum = Vec<2>::Zero();
      for (std::size_t p = 0; p < P.size(); ++p)
        sum += P.m[p] * P.v[p];
      return sum;
    };
    const Vec<2> before = momentum();
    double mass = 0.0;
    for (const double m_p : P.m)
      mass += m_p;
    for (int s = 0; s < 20; ++s)
      sim.step();
    EXPECT_LT((momentum() - before).norm(), 1e-12 * mass * 3.0) << "XPIC(" << m << ")";
  }
}

// XPIC(m) carries only what the grid represents: a block moving uniformly with a particle-scale
// checkerboard on top (each particle +-0.5 m/s, alternating, which maps to almost nothing on the
// nodes) loses the checkerboard in one step, where FLIP keeps it; the uniform part is kept.
TEST(Xpic, DropsTheVelocitiesTheGridCannotRepresent) {
  auto spread = [](int xpic, double flip) {
    Simulation<2> sim(
        test::case_from(block_case<2>("gimp", "musl", flip),
                        {"simulation.gravity=[0, 0]", fmt::format("simulation.xpic={}", xpic)}));
    auto& P = sim.particles_mut();
    for (std::size_t p = 0; p < P.size(); ++p) {
      const long i = std::lround(P.x[p][0] / 0.05 - 0.5), j = std::lround(P.x[p][1] / 0.05 - 0.5);
      P.v[p] = Vec<2>(1.0, 0.0) + Vec<2>(0.0, (i + j) % 2 == 0 ? 0.5 : -0.5);
    }
    sim.step();
    double m = 0.0, mvx = 0.0, rms = 0.0;
    for (std::size_t p = 0; p < P.size(); ++p)
      m += P.m[p], mvx += P.m[p] * P.v[p][0], rms += P.m[p] * P.v[p][1] * P.v[p][1];
    return std::pair{mvx / m, std::sqrt(rms / m)};
  };
  const auto [flip_vx, flip_noise] = spread(0, 1.0);
  const auto [xpic_vx, xpic_noise] = spread(3, 1.0);
  std::printf("checkerboard of 0.5 m/s after one step: FLIP %.4f m/s, XPIC(3) %.4f m/s; mean vx "
              "%.6f / %.6f\n",
              flip_noise, xpic_noise, flip_vx, xpic_vx);
  EXPECT_GT(flip_noise, 0.45);
  EXPECT_LT(xpic_noise, 0.05);
  EXPECT_NEAR(xpic_vx, 1.0, 1e-9);
  EXPECT_NEAR(flip_vx, 1.0, 1e-9);
}

// APIC keeps an affine velocity field v = A x + b through P2G and G2P: each node gets
// p_I = sum_p N_I m_p (A x_p + b + C_p (x_I - x_p)) = m_I (A x_I + b) when C_p = A, and the
// gather gives back v_p = A x_p + b and C_p = sum_I v_I grad N_I = A (every shape function here
// reproduces a linear field and its gradient), under USL and through MUSL's re-map (v_remap =
// A x_I + b at every node with mass). With linear weights and B-splines the block fills the grid,
// so the B-spline's open knots at every face are crossed (x_I their Greville points); GIMP drops
// a particle's weights beyond a face, so its block stays 2 cells in. PIC's gather averages
// instead: a rotation decays.
TYPED_TEST(G2P, ApicKeepsAnAffineVelocityField) {
  constexpr int D = TypeParam::value;
  Mat<D> A;
  for (int i = 0; i < D; ++i)
    for (int j = 0; j < D; ++j)
      A(i, j) = i == j ? 0.3 * (i + 1) : (i < j ? 1.5 : -1.1) + 0.2 * (i + j); // spin and strain
  Vec<D> b = Vec<D>::Constant(0.4);
  const double dt = 1e-4;
  Vec<D> g = Vec<D>::Zero();
  g[D - 1] = -9.81;
  const std::string box = D == 2 ? "min = [0.2, 0.3], max = [1.3, 0.9]"
                                 : "min = [0.2, 0.3, 0.25], max = [1.3, 0.9, 0.75]";
  const std::string grid = D == 2 ? "min = [0.0, 0.0], max = [1.6, 1.2]"
                                  : "min = [0.0, 0.0, 0.0], max = [1.6, 1.2, 1.0]";
  for (const std::string shape : {"linear", "gimp", "bspline"})
    for (const std::string scheme : {"usl", "musl"})
      for (const bool apic : {true, false}) {
        const std::string what = shape + ", " + scheme;
        std::string text = block_case<D>(shape, scheme, 0.0);
        if (apic) text.replace(text.find("flip = 0"), 8, "apic = true");
        if (shape != "gimp") text.replace(text.find(box), box.size(), grid);
        Simulation<D> sim(test::case_from(text));
        auto& P = sim.particles_mut();
        ASSERT_EQ(P.C.size(), apic ? P.size() : 0) << "C is kept only under APIC";
        for (std::size_t p = 0; p < P.size(); ++p) {
          P.v[p] = A * P.x[p] + b;
          if (apic) P.C[p] = A;
        }
        const auto x0 = P.x;
        sim.bin_particles_by_slab();
        sim.fit_body_fields();
        sim.map_particles_to_nodes(true);
        sim.compute_node_velocities();
        sim.integrate_node_forces(dt); // gravity alone: the stress is zero
        if (scheme == "musl")
          sim.update_particles_and_remap(dt);
        else
          sim.update_particles(dt);
        double worst = 0.0, worst_C = 0.0, worst_node = 0.0;
        for (std::size_t p = 0; p < P.size(); ++p) {
          worst = std::max(worst, (P.v[p] - (A * x0[p] + b + g * dt)).norm());
          if (apic) worst_C = std::max(worst_C, (P.C[p] - A).norm());
        }
        const auto& N = sim.fields()[0];
        if (scheme == "musl")
          for (std::size_t i = 0; i < N.size(); ++i)
            if (N.m[i] > 0.0) {
              const Vec<D> x_I =
                  detail::apic_node_position(N, static_cast<std::int64_t>(i), shape == "bspline");
              worst_node = std::max(worst_node, (N.v_remap[i] - (A * x_I + b + g * dt)).norm());
            }
        if (apic) {
          EXPECT_LT(worst, 1e-12) << what;
          EXPECT_LT(worst_C, 1e-11) << what;
          EXPECT_LT(worst_node, 1e-12) << what << ": the re-map";
        } else {
          EXPECT_GT(worst, 1e-3) << what << ": PIC should not keep the field (the contrast)";
        }
      }
}

} // namespace
} // namespace talus
