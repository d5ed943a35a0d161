// Simulation<D>::scatter, the coloured slab loop that P2G and MUSL's re-map share (a member
// template: defined where those phases are compiled).
#pragma once

#include "talus/solver/simulation.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace talus {

// Slabs of one colour never share a node, so any thread may take any of them; the nodes two
// slabs share are summed colour 0 first, each slab in particle order: the same sums on any team.
// Each thread takes one run of the colour's slabs, in x order, holding about 1/T of the
// colour's particles: every step it scatters the same stretch of x, which is about the stretch
// the later passes (static over the particle order, which is by cell column) give it, so the
// particles' shape weights and state stay in that core's cache.
template <int D>
template <class F>
void Simulation<D>::scatter(F&& f) {
  const int B = particles_.num_bodies();
  const std::int64_t S = plan_.num_slabs;
  const std::size_t* offset = plan_.bin_offset.data();
  for (int colour = 0; colour < 2; ++colour) {
    std::size_t total = 0;
    for (std::int64_t s = colour; s < S; s += 2)
      total += offset[(s + 1) * B] - offset[s * B];
#pragma omp parallel
    {
#ifdef _OPENMP
      const std::size_t T = static_cast<std::size_t>(omp_get_num_threads());
      const std::size_t t = static_cast<std::size_t>(omp_get_thread_num());
#else
      const std::size_t T = 1, t = 0;
#endif
      // Slab s goes to the thread whose share of the colour's particles holds its middle.
      std::size_t before = 0;
      for (std::int64_t s = colour; s < S; s += 2) {
        const std::size_t n = offset[(s + 1) * B] - offset[s * B];
        const std::size_t owner =
            total == 0 ? 0 : std::min(T - 1, (2 * before + n) * T / (2 * total));
        before += n;
        if (owner != t) continue;
        for (int b = 0; b < B; ++b)
          for (std::size_t k = offset[s * B + b]; k < offset[s * B + b + 1]; ++k)
            f(plan_.bin_index[k], b);
      }
    }
  }
}

} // namespace talus
