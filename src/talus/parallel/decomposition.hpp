// Slab decomposition of the background grid along x (docs/architecture.md, "Processes"): process
// r owns the cell columns [bounds[r], bounds[r+1]) and every particle whose cell lies in them.
// The bounds come from the particle count per column with integer arithmetic only, so every
// process computes the same bounds from the same (globally summed) counts.
#pragma once

#include "talus/core/grid.hpp"

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace talus {

class DecompositionError : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

// How the first slabs are cut: by the particle count per column, or into equal numbers of
// columns (which the first rebalance then corrects: the tests' rebalance inside a run).
enum class SlabStart { by_count, even_columns };

// The columns of ghosts beyond a slab, each side: a node's sum takes the particles of 4 columns
// (GIMP), contact reads the mass gradient normal_smoothing columns further, and MUSL's re-map and
// stress pass, or USF's stress pass and force scatter, read a second layer of both (6 +
// smoothing); one more for the ownership column and one spare. XPIC(m)'s m - 1 gathers and
// scatters of v* read one layer more each.
inline int ghost_columns(int normal_smoothing, int xpic = 0) {
  return 8 + normal_smoothing + 2 * (xpic > 1 ? xpic - 1 : 0);
}

// The column that decides a particle's owner: that of its cell index (x slowest), so that every
// process's sort keys lie above the previous process's. A cell inside the grid across x has
// cell_index / cells_per_column = its x index (after the clamp also for x outside); only a cell
// outside across x needs the division. cells_per_column: the grid's cells across x.
template <int D>
std::int64_t owner_column(const Grid<D>& G, const Vec<D>& x, std::int64_t cells_per_column) {
  const Index<D> c = G.cell_of(x);
  bool across = true;
  for (int d = 1; d < D; ++d)
    across = across && c[d] >= 0 && c[d] < G.cells[d];
  return std::clamp<std::int64_t>(across ? c[0] : G.cell_index(c) / cells_per_column, 0,
                                  G.cells[0] - 1);
}

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
