// A case of two 2D bodies for the unit tests: block `upper` resting on block `lower`, one
// material, with an interface (or a contact pair) between them.
#pragma once

#include "test_support.hpp"

#include <string>

namespace talus::test {

inline std::string two_blocks(const std::string& extra = "", bool rigid_lower = false) {
  return std::string(R"(
[simulation]
dimension = 2
end_time = 1.0
gravity = [0, -9.81]
[grid]
extent = [2.0, 1.0]
cell_size = 0.1
[[material]]
name = "m"
density = 2000
youngs_modulus = 1e7
poisson_ratio = 0.25
[[body]]
name = "lower"
material = "m"
box = { min = [0.2, 0.2], max = [1.8, 0.4] }
rigid = )") +
         (rigid_lower ? "true" : "false") + R"(
[[body]]
name = "upper"
material = "m"
box = { min = [0.6, 0.4], max = [1.0, 0.6] }
)" + extra;
}

} // namespace talus::test
