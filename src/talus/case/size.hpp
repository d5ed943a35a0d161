// The size of a case before anything is allocated: particles from the shapes' areas (no filling),
// grid nodes, and the memory they need, so a case that cannot fit is refused at parse time with
// the key to change, never by the kernel's OOM killer hours later.
#pragma once

#include "talus/case/case.hpp"

namespace talus {

// Bytes per particle (Particles<D> arrays, slab bins and the sort's scratch) and per node of a
// body's velocity field (BodyField<D>), and per grid node (conditions).
constexpr double bytes_per_particle(int dim) {
  return dim == 2 ? 260.0 : 350.0;
}
constexpr double bytes_per_field_node(int dim) {
  return dim == 2 ? 160.0 : 216.0;
}
constexpr double bytes_per_grid_node = 16.0;

// Area (2D) or volume (3D) of a shape, and the particles it holds at `per_cell` particles per
// cell per direction (an estimate: exact up to the particles along the boundary).
double shape_measure(const Geometry& g, int dim);
double estimate_particles(const Geometry& g, int dim, double cell_size, int per_cell);
// Nodes of the whole grid, and of the node box a body's velocity field spans.
double grid_nodes(const GridSettings& grid, int dim);
double field_nodes(const Vec3a& lo, const Vec3a& hi, int dim, double cell_size);

// Physical memory of this machine in bytes (the limit a case must fit in).
double machine_memory();

} // namespace talus
