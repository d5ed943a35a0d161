// Grid<D>: the structured background grid (quads in 2D, hexahedra in 3D) and its node indexing.
// Node (i, j[, k]) sits at origin + h * (i, j[, k]); the node index is row-major with x slowest,
// so cells sorted by index form slabs along x (the unit of the parallel scatter's colouring).
#pragma once

#include "talus/core/math.hpp"

#include <cmath>
#include <cstdint>

namespace talus {

template <int D>
struct Grid {
  Vec<D> origin = Vec<D>::Zero();
  double h = 1.0;   // cell size
  Index<D> cells{}; // number of cells per direction
  Index<D> nodes{}; // cells + 1 per direction

  Grid() = default;
  Grid(const Vec<D>& origin_, const Vec<D>& extent, double cell_size)
      : origin(origin_), h(cell_size) {
    for (int d = 0; d < D; ++d) {
      cells[d] = static_cast<std::int64_t>(std::ceil(extent[d] / h - 1e-9));
      nodes[d] = cells[d] + 1;
    }
  }

  std::int64_t num_nodes() const {
    std::int64_t n = 1;
    for (int d = 0; d < D; ++d)
      n *= nodes[d];
    return n;
  }
  std::int64_t num_cells() const {
    std::int64_t n = 1;
    for (int d = 0; d < D; ++d)
      n *= cells[d];
    return n;
  }

  std::int64_t node_index(const Index<D>& i) const {
    std::int64_t n = i[0];
    for (int d = 1; d < D; ++d)
      n = n * nodes[d] + i[d];
    return n;
  }
  std::int64_t cell_index(const Index<D>& i) const {
    std::int64_t n = i[0];
    for (int d = 1; d < D; ++d)
      n = n * cells[d] + i[d];
    return n;
  }
  Index<D> node_coords(std::int64_t n) const {
    Index<D> i{};
    for (int d = D - 1; d >= 0; --d) {
      i[d] = n % nodes[d];
      n /= nodes[d];
    }
    return i;
  }
  Vec<D> node_position(const Index<D>& i) const {
    Vec<D> x;
    for (int d = 0; d < D; ++d)
      x[d] = origin[d] + h * static_cast<double>(i[d]);
    return x;
  }
  Vec<D> upper() const {
    Vec<D> x;
    for (int d = 0; d < D; ++d)
      x[d] = origin[d] + h * static_cast<double>(cells[d]);
    return x;
  }
  // The cell holding x (may lie outside [0, cells) for points outside the grid).
  Index<D> cell_of(const Vec<D>& x) const {
    Index<D> c{};
    for (int d = 0; d < D; ++d)
      c[d] = static_cast<std::int64_t>(std::floor((x[d] - origin[d]) / h));
    return c;
  }
  bool contains(const Vec<D>& x) const {
    for (int d = 0; d < D; ++d)
      if (!(x[d] >= origin[d] && x[d] <= origin[d] + h * static_cast<double>(cells[d])))
        return false;
    return true;
  }
};

} // namespace talus
