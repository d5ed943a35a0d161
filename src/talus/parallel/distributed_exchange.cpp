// Distributed<D>'s collective points (solver/exchange.hpp): the calls Simulation makes on
// every process at the same places of a step, each giving every process the same bits.
#include "talus/parallel/decomposition.hpp"
#include "talus/parallel/distributed.hpp"

#include <algorithm>
#include <vector>

namespace talus {

template <int D>
double Distributed<D>::max(double local) {
  double out = local;
  MPI_Allreduce(&local, &out, 1, MPI_DOUBLE, MPI_MAX, comm_);
  return out;
}

template <int D>
void Distributed<D>::min_max(double* lo, double* hi, int n) {
  // One reduction: min lo = -max(-lo), exactly (negation is exact).
  std::vector<double> both(2 * static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i)
    both[i] = -lo[i], both[n + i] = hi[i];
  MPI_Allreduce(MPI_IN_PLACE, both.data(), 2 * n, MPI_DOUBLE, MPI_MAX, comm_);
  for (int i = 0; i < n; ++i)
    lo[i] = -both[i], hi[i] = both[n + i];
}

template <int D>
bool Distributed<D>::owns_plane(std::int64_t i) const {
  return slab_owner(bounds_, i) == rank_;
}

// The share holds the cell columns [lo - w, hi + w) of slab [lo, hi); node plane i's sum takes
// particles of the columns next to it, so no plane outside [lo - w, hi + w + 1) is complete.
template <int D>
void Distributed<D>::plane_reach(std::int64_t& lo, std::int64_t& hi) const {
  lo = bounds_[rank_] - ghost_width_, hi = bounds_[rank_ + 1] + ghost_width_ + 1;
}

template <int D>
void Distributed<D>::sum_disjoint(double* data, std::size_t n) {
  MPI_Allreduce(MPI_IN_PLACE, data, static_cast<int>(n), MPI_DOUBLE, MPI_SUM, comm_);
}

// Each sum's words added as integers (core/exact_sum.hpp): normalized, they cannot overflow.
template <int D>
void Distributed<D>::sum_exact(ExactSum* sums, std::size_t n) {
  std::vector<std::int64_t> words(n * ExactSum::words);
  for (std::size_t i = 0; i < n; ++i) {
    sums[i].normalize();
    std::copy_n(sums[i].data(), ExactSum::words, words.data() + i * ExactSum::words);
  }
  MPI_Allreduce(MPI_IN_PLACE, words.data(), static_cast<int>(words.size()), MPI_INT64_T, MPI_SUM,
                comm_);
  for (std::size_t i = 0; i < n; ++i) {
    std::copy_n(words.data() + i * ExactSum::words, ExactSum::words, sums[i].data());
    sums[i].normalize();
  }
}

template <int D>
void Distributed<D>::sum_integers(std::int64_t* data, std::size_t n) {
  // MPI counts are int: a longer array goes in pieces.
  constexpr std::size_t piece = std::size_t{1} << 28;
  for (std::size_t at = 0; at < n; at += piece)
    MPI_Allreduce(MPI_IN_PLACE, data + at, static_cast<int>(std::min(piece, n - at)), MPI_INT64_T,
                  MPI_SUM, comm_);
}

// A chunk whose particles are all here is summed here; one split between processes has each
// particle's value sent to its place in the chunk, and every process sums it in index order.
template <int D>
void Distributed<D>::chunk_sums(int b, std::size_t begin, std::size_t end, const double* value,
                                std::int64_t chunk, std::vector<double>& sums) {
  const std::int64_t first = static_cast<std::int64_t>(body_begin_[b]);
  const std::int64_t n = static_cast<std::int64_t>(body_begin_[b + 1]) - first;
  const std::int64_t chunks = (n + chunk - 1) / chunk;
  auto length = [&](std::int64_t c) { return std::min(chunk, n - c * chunk); };
  std::vector<std::int64_t> here(chunks, 0);
  for (std::size_t p = begin; p < end; ++p)
    if (share_own_[p]) ++here[(share_index_[p] - first) / chunk];
  std::vector<int> whole(chunks);
  for (std::int64_t c = 0; c < chunks; ++c)
    whole[c] = here[c] == length(c);
  MPI_Allreduce(MPI_IN_PLACE, whole.data(), static_cast<int>(chunks), MPI_INT, MPI_MAX, comm_);
  std::vector<std::int64_t> slot(chunks, -1); // a split chunk's first slot
  std::int64_t slots = 0;
  for (std::int64_t c = 0; c < chunks; ++c)
    if (!whole[c]) slot[c] = slots, slots += length(c);
  // One buffer, one sum: the whole chunks' sums, then the split chunks' slots.
  std::vector<double> both(static_cast<std::size_t>(chunks + slots), 0.0);
  double* split = both.data() + chunks;
  for (std::size_t p = begin; p < end; ++p) {
    if (!share_own_[p]) continue;
    const std::int64_t g = share_index_[p] - first, c = g / chunk;
    if (here[c] == length(c))
      both[c] += value[p];
    else
      split[slot[c] + (g - c * chunk)] = value[p];
  }
  sum_disjoint(both.data(), both.size());
  sums.assign(both.begin(), both.begin() + chunks);
  for (std::int64_t c = 0; c < chunks; ++c) {
    if (whole[c]) continue;
    double s = 0.0;
    for (std::int64_t k = 0; k < length(c); ++k)
      s += split[slot[c] + k];
    sums[c] = s;
  }
}

template class Distributed<2>;
template class Distributed<3>;

} // namespace talus
