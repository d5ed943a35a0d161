// The time step (solver/time_step.cpp): the CFL step of the fastest wave.
#include "block_case.hpp"
#include "talus/solver/simulation.hpp"
#include "test_support.hpp"

#include <cmath>
#include <gtest/gtest.h>

namespace talus {
namespace {

using test::block_case;
using test::randomise;

// The CFL step follows the fastest particle, sqrt(M V / m) + |v|: one particle dilated fivefold
// shortens it by sqrt(5).
TEST(TimeStep, DilatedParticleSetsTheStep) {
  Simulation<2> sim(test::case_from(block_case<2>("gimp", "musl", 1.0)));
  const double dt0 = sim.compute_time_step();
  const double M = 1e6 * 0.7 / (1.3 * 0.4), c0 = std::sqrt(M / 1500.0); // nu = 0.3
  EXPECT_NEAR(dt0, 0.4 * 0.1 / c0, 1e-12);
  sim.particles_mut().vol[7] *= 5.0;
  EXPECT_NEAR(sim.compute_time_step(), dt0 / std::sqrt(5.0), 1e-12);
}

} // namespace
} // namespace talus
