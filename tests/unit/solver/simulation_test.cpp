// Simulation::step (solver/simulation.cpp): the coloured scatter and every phase after it give
// the same bits on one and two threads.
#include "block_case.hpp"
#include "talus/solver/simulation.hpp"
#include "test_support.hpp"

#include <algorithm>
#ifdef _OPENMP
#include <omp.h>
#endif
#include <gtest/gtest.h>

namespace talus {
namespace {

using test::block_case;
using test::randomise;

#ifdef _OPENMP
template <class T>
class ThreadDeterminism : public ::testing::Test {};
TYPED_TEST_SUITE(ThreadDeterminism, test::Dims);

template <int D>
void expect_same(const Particles<D>& a, const Particles<D>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t p = 0; p < a.size(); ++p) {
    ASSERT_EQ(a.id[p], b.id[p]);
    ASSERT_TRUE(a.x[p] == b.x[p]) << p;
    ASSERT_TRUE(a.v[p] == b.v[p]) << p;
    ASSERT_TRUE(a.stress[p] == b.stress[p]) << p;
    ASSERT_TRUE(a.slip[p] == b.slip[p]) << p;
  }
}

template <int D>
Particles<D> run_with_threads(const Case& c, int threads, int steps) {
  const int before = omp_get_max_threads();
  omp_set_num_threads(threads);
  Simulation<D> sim(c);
  randomise(sim.particles_mut(), 11);
  for (int s = 0; s < steps; ++s)
    sim.step();
  omp_set_num_threads(before);
  return sim.particles();
}

// The coloured scatter sums each node in a fixed order: 1 and 2 threads agree bit for bit.
TYPED_TEST(ThreadDeterminism, OneAndTwoThreadsAreBitwiseIdentical) {
  constexpr int D = TypeParam::value;
  for (const char* scheme : {"usf", "usl", "musl"}) { // each reads the cached weights its own way
    SCOPED_TRACE(scheme);
    const Case c = test::case_from(block_case<D>("gimp", scheme, 0.99));
    expect_same(run_with_threads<D>(c, 1, 30), run_with_threads<D>(c, 2, 30));
  }
}

// The same with two bodies in contact through a degrading cohesive interface (contact, slip
// gathering and the interface forces all run in parallel).
TEST(Determinism, ContactAndInterfacesAreBitwiseIdenticalOnOneAndTwoThreads) {
  const Case c = test::case_from(R"(
[simulation]
end_time = 1.0
gravity = [0, -9.81]
scheme = "musl"
flip = 0.99
[grid]
extent = [3.0, 1.5]
cell_size = 0.05
[[material]]
name = "m"
model = "mohr_coulomb"
density = 2000
youngs_modulus = 1e7
poisson_ratio = 0.3
friction_angle = 30
cohesion = 1000
[[body]]
name = "top"
material = "m"
box = { min = [0.5, 0.5], max = [1.5, 1.0] }
velocity = [1.0, 0.0]
[[body]]
name = "base"
material = "m"
box = { min = [0.1, 0.05], max = [2.9, 0.5] }
[[interface]]
bodies = ["top", "base"]
friction = { initial = 0.3, residual = 0.2, slip = 0.01 }
cohesion = { initial = 500.0, residual = 0.0, slip = 0.01 }
[grid.boundary]
y_min = "fixed"
)");
  const Particles<2> one = run_with_threads<2>(c, 1, 60);
  expect_same(one, run_with_threads<2>(c, 2, 60));
  EXPECT_GT(*std::max_element(one.slip.begin(), one.slip.end()), 0.0); // the interface slipped
}

#endif

} // namespace
} // namespace talus
