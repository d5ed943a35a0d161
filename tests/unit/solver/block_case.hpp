// A block of particles for the solver's unit tests, in 2D or 3D, with a chosen shape function,
// scheme and FLIP fraction; and random velocities and stresses for it.
#pragma once

#include "talus/core/particles.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <random>
#include <string>
#include <type_traits>

namespace talus::test {

template <int D>
std::string block_case(const std::string& shape, const std::string& scheme, double flip) {
  const std::string v0 = D == 2 ? "[0, 0]" : "[0, 0, 0]";
  const std::string lo = D == 2 ? "[0.2, 0.3]" : "[0.2, 0.3, 0.25]";
  const std::string hi = D == 2 ? "[1.3, 0.9]" : "[1.3, 0.9, 0.75]";
  const std::string ext = D == 2 ? "[1.6, 1.2]" : "[1.6, 1.2, 1.0]";
  const std::string g = D == 2 ? "[0, -9.81]" : "[0, 0, -9.81]";
  return fmt::format(R"(
[simulation]
dimension = {}
end_time = 1.0
gravity = {}
scheme = "{}"
flip = {}
[grid]
extent = {}
cell_size = 0.1
shape_function = "{}"
[[material]]
name = "m"
density = 1500
youngs_modulus = 1e6
poisson_ratio = 0.3
[[body]]
name = "a"
material = "m"
box = {{ min = {}, max = {} }}
particles_per_cell = 2
velocity = {}
)",
                     D, g, scheme, flip, ext, shape, lo, hi, v0);
}

// Random velocities and stresses so the transfers see a non-trivial state.
template <int D>
void randomise(Particles<D>& P, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (std::size_t p = 0; p < P.size(); ++p) {
    for (int d = 0; d < D; ++d)
      P.v[p][d] = u(rng), P.x[p][d] += 0.02 * u(rng);
    for (int k = 0; k < 6; ++k)
      P.stress[p][k] = 1e3 * u(rng);
  }
}

// Both dimensions, for typed tests.
using Dims = ::testing::Types<std::integral_constant<int, 2>, std::integral_constant<int, 3>>;

} // namespace talus::test
