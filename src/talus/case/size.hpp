// The size of a case before anything is allocated: particles from the shapes' areas (no filling),
// grid nodes, and the memory they need, so a case that cannot fit is refused at parse time with
// the key to change, never by the kernel's OOM killer hours later.
#pragma once

#include "talus/case/case.hpp"

#include <cstddef>
#include <vector>

namespace talus {

// Bytes each particle holds while a run steps, counted from the types the solver allocates:
// every Particles<D> array, its shape-weight cache entry, its slab bin, bin index and id index,
// and the particle sort's scratch (order, key and mark).
double bytes_per_particle(int dim);
// Bytes per node of a body's velocity field (BodyField<D>): mass, momentum, force, v^n, v^{n+1},
// with contact the mass gradient and position, with MUSL the re-mapped velocity, and six
// doubles per interface slot.
double bytes_per_field_node(int dim, bool contact, bool remap, int interface_slots);
constexpr double bytes_per_grid_node = 16.0; // the grid conditions

// Area (2D) or volume (3D) of a shape, and the particles it holds at `per_cell` particles per
// cell per direction (an estimate: exact up to the particles along the boundary).
double shape_measure(const Geometry& g, int dim);
double estimate_particles(const Geometry& g, int dim, double cell_size, int per_cell);
// Nodes of the whole grid, and of the node box a body's velocity field spans.
double grid_nodes(const GridSettings& grid, int dim);
double field_nodes(const Vec3a& lo, const Vec3a& hi, int dim, double cell_size);

// Bounding box of a geometry (the first dim components are meaningful).
void geometry_bounds(const Geometry& g, int dim, Vec3a& lo, Vec3a& hi);

// The memory a run of case c allocates, in bytes, with `particles[b]` particles in body b: the
// particles, each body's velocity field over its geometry's box and the grid conditions (the
// geometric normals cached at contact nodes scale with the contact surface: left out).
double estimate_memory(const Case& c, const std::vector<std::size_t>& particles);

// Bytes per particle of one VTU frame before compression: positions, the vertex cells, body
// and id, and each field of output.fields at output.precision.
double frame_bytes_per_particle(const Case& c);

// Physical memory of this machine in bytes (the limit a case must fit in).
double machine_memory();

} // namespace talus
