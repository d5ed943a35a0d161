// G2P (solver/g2p.cpp): a PIC gather returns the grid's momentum to the particles; walls keep
// particles in.
#include "block_case.hpp"
#include "talus/solver/simulation.hpp"
#include "test_support.hpp"

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

} // namespace
} // namespace talus
