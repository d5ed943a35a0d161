// Each body's field box: the nodes its particles (and the orphans it hosts) reach this step.
#include "talus/setup/interface.hpp"
#include "talus/solver/detail.hpp"
#include "talus/solver/simulation.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <variant>

namespace talus {

// Reads the bounds bin_particles_by_slab took; writes each body's field box and clears it.
// Each body's field covers the nodes its particles and the orphans it hosts reach (GIMP: one
// cell beyond the particle's cell on each side), refitted and cleared every step.
template <int D>
void Simulation<D>::fit_body_fields() {
  const int B = particles_.num_bodies();
  std::vector<double>& bounds = plan_.box_bounds; // B x D minima, then B x D maxima
  if (bounds.size() != static_cast<std::size_t>(2 * B * D))
    throw std::logic_error("fit_body_fields needs the bounds of bin_particles_by_slab");
  double* lo_ = bounds.data();
  double* hi_ = bounds.data() + B * D;
  // The nodes [cell(lo) - 1, cell(hi) + 3) hold the support of every point in [lo, hi].
  auto node_range = [&](const double* lo, const double* hi, Index<D>& first, Index<D>& last) {
    first = grid_.cell_of(Eigen::Map<const Vec<D>>(lo));
    last = grid_.cell_of(Eigen::Map<const Vec<D>>(hi));
    for (int d = 0; d < D; ++d) {
      first[d] = std::clamp<std::int64_t>(first[d] - 1, 0, grid_.nodes[d]);
      last[d] = std::clamp<std::int64_t>(last[d] + 3, 0, grid_.nodes[d]);
    }
  };
  // On several processes each frame spans every process's particles: the frames, and with them
  // the shape weights (relative to the frame) and the contact rows, are one process's. Each
  // process stores the part of the frame its own and ghost particles reach.
  std::vector<double>& mine = plan_.box_bounds_local;
  mine.assign(bounds.begin(), bounds.end());
  if (exchange_) exchange_->min_max(lo_, hi_, B * D);
  for (int b = 0; b < B; ++b) {
    if (field_held_[b]) continue; // its box and sums stand
    Index<D> frame_first, frame_last, first, last;
    node_range(lo_ + b * D, hi_ + b * D, frame_first, frame_last);
    const double *l = mine.data() + b * D, *h = mine.data() + (B + b) * D;
    if (!exchange_)
      first = frame_first, last = frame_last;
    else if (l[0] <= h[0]) // the process holds particles of the body
      node_range(l, h, first, last);
    else
      first = last = frame_first; // none: one empty node
    fields_[b].fit(grid_, frame_first, frame_last, first, last);
  }
}

#define TALUS_INSTANTIATE(D) template void Simulation<D>::fit_body_fields();
TALUS_INSTANTIATE(2)
TALUS_INSTANTIATE(3)

} // namespace talus
