// P2G (solver/p2g.cpp): the scatter conserves mass and momentum to round-off, and the nodal
// forces sum to the weight (the internal forces cancel).
#include "block_case.hpp"
#include "talus/solver/simulation.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

namespace talus {
namespace {

using test::block_case;
using test::randomise;

template <class T>
class P2G : public ::testing::Test {};
TYPED_TEST_SUITE(P2G, test::Dims);

TYPED_TEST(P2G, ScatterConservesMassAndMomentum) {
  constexpr int D = TypeParam::value;
  for (const char* shape : {"linear", "gimp", "bspline"}) {
    Simulation<D> sim(test::case_from(block_case<D>(shape, "usl", 1.0)));
    randomise(sim.particles_mut(), 3);
    sim.bin_particles_by_slab();
    sim.fit_body_fields();
    sim.map_particles_to_nodes(true);
    const auto& P = sim.particles();
    const auto& N = sim.fields()[0];
    double m_p = 0.0, m_I = 0.0;
    Vec<D> p_p = Vec<D>::Zero(), p_I = Vec<D>::Zero(), f_I = Vec<D>::Zero();
    for (std::size_t p = 0; p < P.size(); ++p)
      m_p += P.m[p], p_p += P.m[p] * P.v[p];
    for (std::size_t i = 0; i < N.size(); ++i)
      m_I += N.m[i], p_I += N.p[i], f_I += N.f[i];
    EXPECT_NEAR(m_I, m_p, 1e-12 * m_p) << shape;
    EXPECT_LT((p_I - p_p).norm(), 1e-12 * m_p) << shape;
    // Internal forces sum to zero (gradients sum to zero); external force is the total weight.
    Vec<D> weight = Vec<D>::Zero();
    weight[D - 1] = -9.81 * m_p;
    EXPECT_LT((f_I - weight).norm(), 1e-9 * m_p * 9.81) << shape;
  }
}

} // namespace
} // namespace talus
