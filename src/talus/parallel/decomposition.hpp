// Slab decomposition of the background grid along x (docs/architecture.md, "Processes"): process
// r owns the cell columns [bounds[r], bounds[r+1]) and every particle whose cell lies in them.
// The bounds come from the particle count per column with integer arithmetic only, so every
// process computes the same bounds from the same (globally summed) counts.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <vector>

namespace talus {

class DecompositionError : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

// Bounds (procs + 1 entries, bounds[0] = 0, bounds[procs] = columns) that split `counts`
// (particles per column) into procs slabs of near-equal count, each at least min_width columns
// wide. Slab r ends at the first column where the running count reaches r / procs of the total
// (exact: prefix * procs >= r * total in 128-bit integers). Throws DecompositionError when the
// grid has fewer than procs * min_width columns.
std::vector<std::int64_t> slab_bounds(const std::vector<std::int64_t>& counts, int procs,
                                      std::int64_t min_width);

// The process whose slab holds column c (columns outside the grid go to the first or last).
int slab_owner(const std::vector<std::int64_t>& bounds, std::int64_t c);

} // namespace talus
