// The stress update (solver/stress_update.cpp, eq. 24-28): the volume limit keeps J at the limit
// and the particle's shape.
#include "block_case.hpp"
#include "talus/solver/simulation.hpp"
#include "test_support.hpp"

#include <cmath>
#include <gtest/gtest.h>
#include <memory>

namespace talus {
namespace {

using test::block_case;
using test::randomise;

template <class T>
class StressUpdate : public ::testing::Test {};
TYPED_TEST_SUITE(StressUpdate, test::Dims);

// material.max_volume_ratio: a particle stretched past the limit keeps J = limit, its deformation
// gradient scaled back isotropically (its shape, F / J^(1/D), and its stress are those of the
// unlimited run); a particle below the limit is untouched. (Drucker-Prager with a cohesion far
// above the stresses reached: elastic, as the option is for the plastic models only.)
TYPED_TEST(StressUpdate, VolumeLimitKeepsTheLimitAndTheShape) {
  constexpr int D = TypeParam::value;
  auto stretch = [](const std::string& limit) {
    std::string text = block_case<D>("gimp", "usf", 1.0);
    text.replace(text.find("poisson_ratio = 0.3"), 19,
                 "poisson_ratio = 0.3\nmodel = \"drucker_prager\"\nfriction_angle = 30\n"
                 "cohesion = 1e9\n" +
                     limit);
    auto sim = std::make_unique<Simulation<D>>(test::case_from(text));
    auto& P = sim->particles_mut();
    for (std::size_t p = 0; p < P.size(); ++p) { // opens along x, fastest at the right end
      P.v[p] = Vec<D>::Zero();
      P.v[p][0] = 2.0 * (P.x[p][0] - 0.2) * (P.x[p][0] - 0.2);
      P.v[p][1] = 0.1 * P.x[p][0];
    }
    sim->bin_particles_by_slab();
    sim->fit_body_fields();
    sim->map_particles_to_nodes(false);
    sim->compute_node_velocities();
    sim->update_stress(&BodyField<D>::v, 0.2);
    return sim;
  };
  const auto free = stretch(""), limited = stretch("max_volume_ratio = 1.2");
  const auto &U = free->particles(), &C = limited->particles();
  int above = 0, below = 0;
  for (std::size_t p = 0; p < U.size(); ++p) {
    const double J = U.F[p].determinant();
    ASSERT_TRUE(U.stress[p] == C.stress[p]) << p;
    if (J > 1.2) {
      ++above;
      EXPECT_NEAR(C.F[p].determinant(), 1.2, 1e-12) << p;
      EXPECT_NEAR(C.vol[p], 1.2 * C.vol0[p], 1e-12 * C.vol0[p]) << p;
      EXPECT_LT((C.F[p] / std::pow(1.2, 1.0 / D) - U.F[p] / std::pow(J, 1.0 / D)).norm(), 1e-12)
          << p;
    } else {
      ++below;
      ASSERT_TRUE(C.F[p] == U.F[p]) << p;
      ASSERT_EQ(C.vol[p], U.vol[p]) << p;
    }
  }
  EXPECT_GT(above, 10);
  EXPECT_GT(below, 10);
}

} // namespace
} // namespace talus
