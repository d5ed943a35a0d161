#include "talus/parallel/decomposition.hpp"

#include <algorithm>
#include <fmt/format.h>

namespace talus {

std::vector<std::int64_t> slab_bounds(const std::vector<std::int64_t>& counts, int procs,
                                      std::int64_t min_width) {
  const auto columns = static_cast<std::int64_t>(counts.size());
  if (procs < 1) throw DecompositionError("the number of processes must be at least 1");
  if (columns < procs * min_width)
    throw DecompositionError(fmt::format(
        "the grid has {} cell columns along x; {} processes need at least {} ({} each: the "
        "reach of a particle's ghosts). Use fewer processes or a finer grid",
        columns, procs, procs * min_width, min_width));
  __int128 total = 0;
  for (const std::int64_t n : counts)
    total += n;
  std::vector<std::int64_t> bounds(procs + 1, 0);
  bounds[procs] = columns;
  // Boundary r: the first column c with (count of columns [0, c)) * procs >= r * total.
  __int128 prefix = 0;
  std::int64_t c = 0;
  for (int r = 1; r < procs; ++r) {
    while (c < columns && prefix * procs < static_cast<__int128>(r) * total)
      prefix += counts[c++];
    bounds[r] = c;
  }
  // Each slab at least min_width wide: pushed up from the left, then down from the right
  // (columns >= procs * min_width, so both passes fit).
  for (int r = 1; r < procs; ++r)
    bounds[r] = std::max(bounds[r], bounds[r - 1] + min_width);
  for (int r = procs - 1; r >= 1; --r)
    bounds[r] = std::min(bounds[r], bounds[r + 1] - min_width);
  return bounds;
}

int slab_owner(const std::vector<std::int64_t>& bounds, std::int64_t c) {
  const auto it = std::upper_bound(bounds.begin() + 1, bounds.end() - 1, c);
  return static_cast<int>(it - (bounds.begin() + 1));
}

} // namespace talus
