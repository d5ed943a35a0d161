// make_stepper (parallel/stepper.hpp) on one process: the stepper is the Simulation stepped as
// it is (the same bits as stepping it directly), its particle order is the particles' own, and
// the collectives reduce to the one process's values.
#include "talus/parallel/stepper.hpp"
#include "two_bodies.hpp"

#include <gtest/gtest.h>

#include <cstring>

using namespace talus;

// Stepping through the seam gives the bits of stepping the Simulation itself, at every step,
// releases included.
TEST(Stepper, OneProcessStepsTheSimulationAsItIs) {
  const Case c = test::case_from(test::two_blocks("[initial_state]\nsettle_time = 0.002\n"));
  const std::unique_ptr<Stepper<2>> stepper = make_stepper<2>(c);
  Simulation<2> direct(c);
  stepper->distribute(); // nothing on one process
  EXPECT_FALSE(stepper->share_counters().has_value());
  for (int i = 0; i < 30; ++i) {
    if (i == 10) stepper->release(), direct.release();
    stepper->step(inf);
    direct.step(inf);
  }
  const Particles<2>&A = stepper->sim().particles(), &B = direct.particles();
  ASSERT_EQ(A.size(), B.size());
  EXPECT_EQ(stepper->sim().time(), direct.time());
  EXPECT_EQ(std::memcmp(A.x.data(), B.x.data(), A.x.size() * sizeof(A.x[0])), 0);
  EXPECT_EQ(std::memcmp(A.v.data(), B.v.data(), A.v.size() * sizeof(A.v[0])), 0);
  EXPECT_EQ(std::memcmp(A.stress.data(), B.stress.data(), A.stress.size() * sizeof(A.stress[0])),
            0);
  EXPECT_EQ(stepper->contact_nodes().size(), direct.contact_nodes().size());
  stepper->check_particles(); // a sound state passes
}

// The particle order gathers every particle once, in the particles' order; with_whole_tables
// runs its function once, here.
TEST(Stepper, OneProcessOrderIsTheParticlesOwn) {
  const std::unique_ptr<Stepper<2>> stepper = make_stepper<2>(test::case_from(test::two_blocks()));
  const Particles<2>& P = stepper->sim().particles();
  ParticleOrder& order = stepper->particle_order();
  EXPECT_EQ(order.total(), P.size());
  EXPECT_TRUE(order.receives());
  std::vector<std::uint32_t> ids;
  order.gather(
      sizeof(std::uint32_t),
      [&](std::size_t p, char* out) { std::memcpy(out, &P.id[p], sizeof(std::uint32_t)); },
      [&](const char* data, std::size_t count) {
        for (std::size_t k = 0; k < count; ++k) {
          std::uint32_t id;
          std::memcpy(&id, data + k * sizeof id, sizeof id);
          ids.push_back(id);
        }
      });
  ASSERT_EQ(ids.size(), P.size());
  for (std::size_t p = 0; p < P.size(); ++p)
    EXPECT_EQ(ids[p], P.id[p]);
  int calls = 0;
  stepper->with_whole_tables([&] { ++calls; });
  EXPECT_EQ(calls, 1);
}
