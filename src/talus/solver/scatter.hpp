// Simulation<D>::scatter, the coloured slab loop that P2G and MUSL's re-map share (a member
// template: defined where those phases are compiled).
#pragma once

#include "talus/solver/simulation.hpp"

namespace talus {

template <int D>
template <class F>
void Simulation<D>::scatter(F&& f) {
  const int B = particles_.num_bodies();
  for (int colour = 0; colour < 2; ++colour) {
#pragma omp parallel for schedule(dynamic, 1)
    for (std::int64_t s = colour; s < plan_.num_slabs; s += 2)
      for (int b = 0; b < B; ++b)
        for (std::size_t k = plan_.bin_offset[s * B + b]; k < plan_.bin_offset[s * B + b + 1]; ++k)
          f(plan_.bin_index[k], b);
  }
}

} // namespace talus
