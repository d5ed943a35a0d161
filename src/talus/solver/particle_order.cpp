// The particle order that makes the scatter deterministic: particles sorted by cell within each
// body, and binned by slab of cells along x for the coloured scatter.
#include "talus/core/particle_sort.hpp"
#include "talus/core/threads.hpp"
#include "talus/solver/simulation.hpp"

#include <algorithm>
#include <limits>
#include <numeric>

namespace talus {

// Reads the positions; writes the particle order (every array permuted, by cell within each
// body) and index_of_id_. Invalidates the shape-weight cache.
template <int D>
void Simulation<D>::sort_particles_by_cell() {
  auto& P = particles_;
  invalidate_shape(); // shape_ is indexed by particle
  apply_order(P, order_by_cell(grid_, P.x, P.body_begin));
  index_of_id_.resize(std::max(index_of_id_.size(), P.size())); // a process's share: ids of all
  for (std::size_t p = 0; p < P.size(); ++p)
    index_of_id_[P.id[p]] = static_cast<std::uint32_t>(p);
}

// Reads the positions; writes each particle's slab bin (slabs of plan_.slab_width cells along x, by
// body) and the bins' index, in particle order; a held field's particles get no bin. The same
// pass takes each body's bounds for fit_body_fields (plan_.box_bounds): its particles' and the
// orphans' it hosts; a held body keeps the bounds it has.
template <int D>
void Simulation<D>::bin_particles_by_slab() {
  const auto& P = particles_;
  const int B = P.num_bodies();
  const std::size_t n = P.size();
  plan_.particle_bin.resize(n);
  plan_.bin_index.resize(n);
  std::fill(plan_.bin_offset.begin(), plan_.bin_offset.end(), 0);
  const double inv_h = 1.0 / grid_.h;
  constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();
  std::vector<double>& bounds = plan_.box_bounds; // B x D minima, then B x D maxima
  bounds.resize(2 * B * D);
  double* lo_ = bounds.data();
  double* hi_ = bounds.data() + B * D;
  for (int b = 0; b < B; ++b) { // a held body's field stands: no scatter visits its particles
    if (field_held_[b])
      std::fill(plan_.particle_bin.begin() + P.body_begin[b],
                plan_.particle_bin.begin() + P.body_begin[b + 1], none);
    else
      std::fill_n(lo_ + b * D, D, inf), std::fill_n(hi_ + b * D, D, -inf);
  }
  // One parallel region for every body. A held body is a fixed rigid one, whose particles are
  // never orphans (update_orphans leaves rigid bodies alone): it has nothing to bin or bound.
  // A minimum and a maximum do not depend on the order they are taken in.
#pragma omp parallel reduction(min : lo_[:B * D]) reduction(max : hi_[:B * D])
  for (int b = 0; b < B; ++b) {
    if (field_held_[b]) continue;
    const std::int64_t begin = P.body_begin[b], end = P.body_begin[b + 1];
#pragma omp for schedule(static) nowait
    for (std::int64_t p = begin; p < end; ++p) {
      const double xi = (P.x[p][0] - grid_.origin[0]) * inv_h;
      const std::int64_t s = std::clamp<std::int64_t>(
          static_cast<std::int64_t>(xi) / plan_.slab_width, 0, plan_.num_slabs - 1);
      plan_.particle_bin[p] = static_cast<std::uint32_t>(s * B + b);
      auto stretch = [&](int k) { // body k's bounds take in x_p
        for (int d = 0; d < D; ++d) {
          lo_[k * D + d] = std::min(lo_[k * D + d], P.x[p][d]);
          hi_[k * D + d] = std::max(hi_[k * D + d], P.x[p][d]);
        }
      };
      stretch(b);
      if (const int f = P.field[p]; f != b) stretch(f); // an orphan stretches its host's box
    }
  }
  // A counting sort by bin, stable in p, over `chunks` contiguous ranges of particles: each
  // range's bins are counted, a bin's start for range u is its start plus the counts of the
  // ranges before u, and each range is filed from there. Within a bin the particles stay in
  // increasing p, the one-thread order, whatever team OpenMP gives (the ranges are shared out,
  // not tied to thread numbers).
  const std::size_t bins = plan_.bin_offset.size() - 1;
  const int chunks = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(team_size()),
                                                            std::max<std::size_t>(n / 65536, 1)));
  std::vector<std::size_t> count(static_cast<std::size_t>(chunks) * bins, 0);
  auto range = [&](int u) {
    return std::pair{n * static_cast<std::size_t>(u) / static_cast<std::size_t>(chunks),
                     n * static_cast<std::size_t>(u + 1) / static_cast<std::size_t>(chunks)};
  };
  auto row = [&](int u) { return count.data() + static_cast<std::size_t>(u) * bins; };
#pragma omp parallel num_threads(chunks)
  {
#pragma omp for schedule(static)
    for (int u = 0; u < chunks; ++u) {
      const auto [begin, end] = range(u);
      std::size_t* mine = row(u);
      for (std::size_t p = begin; p < end; ++p)
        if (plan_.particle_bin[p] != none) ++mine[plan_.particle_bin[p]];
    }
#pragma omp single
    {
      std::size_t at = 0;
      for (std::size_t bin = 0; bin < bins; ++bin) {
        plan_.bin_offset[bin] = at;
        for (int u = 0; u < chunks; ++u) {
          const std::size_t c = row(u)[bin];
          row(u)[bin] = at;
          at += c;
        }
      }
      plan_.bin_offset[bins] = at;
    }
#pragma omp for schedule(static)
    for (int u = 0; u < chunks; ++u) {
      const auto [begin, end] = range(u);
      std::size_t* mine = row(u);
      for (std::size_t p = begin; p < end; ++p)
        if (plan_.particle_bin[p] != none)
          plan_.bin_index[mine[plan_.particle_bin[p]]++] = static_cast<std::uint32_t>(p);
    }
  }
}

#define TALUS_INSTANTIATE(D)                                                                       \
  template void Simulation<D>::sort_particles_by_cell();                                           \
  template void Simulation<D>::bin_particles_by_slab();
TALUS_INSTANTIATE(2)
TALUS_INSTANTIATE(3)

} // namespace talus
