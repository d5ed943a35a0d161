// The size of a case before anything is allocated: particles from the shapes' areas (no filling),
// grid nodes, and the memory they need, so a case that cannot fit is refused at parse time with
// the key to change, never by the kernel's OOM killer hours later.
#pragma once

#include "talus/case/case.hpp"

#include <cstddef>
#include <string>
#include <vector>

namespace talus {

// Bytes each particle holds while a run steps, counted from the types the solver allocates:
// every Particles<D> array, its shape-weight cache entry, its slab bin, bin index and id index,
// and the particle sort's scratch (order, key and mark); with `apic`, APIC's affine velocity too.
double bytes_per_particle(int dim, bool apic = false);
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

// Whether float32 positions round within a 2,000th of a cell over the whole grid: half float32's
// spacing at the grid's largest |coordinate| x, 2^(floor(log2 x) - 24), is at most h / 2000.
bool float32_positions_suffice(const GridSettings& grid, int dim);
// The frames' position precision: the case's, else float32 where float32_positions_suffice.
bool frame_float32_positions(const Case& c);
// The power of two the frames' positions are rounded to (0: none): output.field_bits > 0 with
// float32 positions that float32_positions_suffice.
double frame_position_quantum(const Case& c);

// Bytes per particle of one VTU frame before compression: positions, the vertex cells, body
// and id, and each field of output.fields at output.precision.
double frame_bytes_per_particle(const Case& c);

// Physical memory of this machine in bytes (the limit a case must fit in).
double machine_memory();

// The most steps a run may take: a case planned past it is refused, and a run whose time step
// collapses so far that it would need more stops.
inline constexpr double max_run_steps = 1e9;

// What a run of case c will take, with `particles[b]` particles in body b, from the state at
// rest: what `talus check` prints, and what `talus run` warns of and refuses before it starts.
struct RunPlan {
  std::size_t particles = 0;
  double dt = 0.0;          // the time step (fixed, or CFL at rest)
  double cfl_dt = 0.0;      // the CFL step of the stiffest body at rest
  double steps = 0.0;       // to end_time, settling included (output times add steps)
  double frames = 0.0;      // particle frames
  double frame_bytes = 0.0; // per particle per frame, before compression
  double output_bytes = 0.0;
  double memory_bytes = 0.0;
  double free_disk_bytes = -1.0;     // where the run folder goes (-1: unknown)
  std::vector<std::string> warnings; // what may go wrong but is allowed
  std::string refusal;               // why the case cannot run (empty: it can)
  std::string disk_full;             // why its output cannot fit (empty: it may; --force runs)
};
// `out_dir`: where the output goes (its free space; the nearest existing parent).
RunPlan plan_run(const Case& c, const std::vector<std::size_t>& particles,
                 const std::string& out_dir = ".");
// Bytes a compressed frame takes at least, per byte before compression: below the smallest share
// either compressor reached on the Vaiont's frames (its bodies at rest at t = 0, K0 stresses:
// 0.022 with LZMA, 0.10 with zlib; with positions and displacement alone 0.032 and 0.16; a
// moving frame 0.15 and 0.26).
inline double best_compression(const Case& c) {
  return c.output.zlib_frames ? 0.08 : 0.02;
}

} // namespace talus
