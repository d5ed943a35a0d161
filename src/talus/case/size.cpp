#include "talus/case/size.hpp"

#include "talus/case/geometry.hpp"

#include "talus/core/particles.hpp"
#include "talus/core/shape.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fmt/format.h>
#include <numbers>
#include <type_traits>
#include <unistd.h>

namespace talus {

namespace {

template <int D>
double particle_bytes() {
  Particles<D> P;
  double bytes = 0.0;
  P.for_each_array(
      [&](auto& a) { bytes += sizeof(typename std::decay_t<decltype(a)>::value_type); });
  bytes += sizeof(ShapeWeights<D>);                          // the shape-weight cache
  bytes += 3 * sizeof(std::uint32_t);                        // slab bin, bin index, id index
  bytes += sizeof(std::uint32_t) + sizeof(std::int64_t) + 1; // the sort's order, key and mark
  return bytes;
}

} // namespace

double bytes_per_particle(int dim, bool apic) {
  const double affine = apic ? sizeof(double) * dim * dim : 0.0; // APIC's C (an optional array)
  return (dim == 2 ? particle_bytes<2>() : particle_bytes<3>()) + affine;
}

double bytes_per_field_node(int dim, bool contact, bool remap, int interface_slots) {
  const double vec = sizeof(double) * dim;
  return sizeof(double) + 4 * vec + (contact ? 2 * vec : 0.0) + (remap ? vec : 0.0) +
         6.0 * sizeof(double) * interface_slots;
}

double shape_measure(const Geometry& g, int dim) {
  switch (g.kind) {
  case Geometry::Kind::box: {
    double m = 1.0;
    for (int d = 0; d < dim; ++d)
      m *= std::max(0.0, g.max[d] - g.min[d]);
    return m;
  }
  case Geometry::Kind::disk:
    return dim == 2 ? std::numbers::pi * g.radius * g.radius
                    : 4.0 / 3.0 * std::numbers::pi * g.radius * g.radius * g.radius;
  case Geometry::Kind::polygon:
  case Geometry::Kind::prism: {
    double twice = 0.0; // shoelace; a self-crossing polygon gives at most its true area
    const auto& v = g.vertices;
    for (std::size_t i = 0; i < v.size(); ++i) {
      const auto& a = v[i];
      const auto& b = v[(i + 1) % v.size()];
      twice += a[0] * b[1] - b[0] * a[1];
    }
    const double area = 0.5 * std::abs(twice);
    return g.kind == Geometry::Kind::prism ? area * (g.max[g.axis] - g.min[g.axis]) : area;
  }
  case Geometry::Kind::terrain: {
    // The mean thickness over a 64 x 64 sample of columns in the plan bounds, times their area.
    constexpr int n = 64;
    double sum = 0.0;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        const double x = g.min[0] + (i + 0.5) / n * (g.max[0] - g.min[0]);
        const double y = g.min[1] + (j + 0.5) / n * (g.max[1] - g.min[1]);
        if (g.footprint && !point_in_polygon(g.vertices, x, y)) continue;
        const auto [top, bottom] = terrain_column(g, x, y);
        if (top > bottom) sum += top - bottom;
      }
    return sum / (n * n) * (g.max[0] - g.min[0]) * (g.max[1] - g.min[1]);
  }
  }
  return 0.0;
}

double estimate_particles(const Geometry& g, int dim, double cell_size, int per_cell) {
  return shape_measure(g, dim) * std::pow(per_cell / cell_size, dim);
}

double grid_nodes(const GridSettings& grid, int dim) {
  double n = 1.0;
  for (int d = 0; d < dim; ++d)
    n *= std::ceil(grid.extent[d] / grid.cell_size - 1e-9) + 1.0;
  return n;
}

double field_nodes(const Vec3a& lo, const Vec3a& hi, int dim, double cell_size) {
  double n = 1.0;
  for (int d = 0; d < dim; ++d)
    n *= (hi[d] - lo[d]) / cell_size + 4.0; // the field's box reaches a cell and a half beyond
  return n;
}

void geometry_bounds(const Geometry& g, int dim, Vec3a& lo, Vec3a& hi) {
  switch (g.kind) {
  case Geometry::Kind::box:
    lo = g.min, hi = g.max;
    break;
  case Geometry::Kind::disk:
    for (int d = 0; d < dim; ++d)
      lo[d] = g.center[d] - g.radius, hi[d] = g.center[d] + g.radius;
    break;
  case Geometry::Kind::prism:
  case Geometry::Kind::terrain:
    lo = g.min, hi = g.max;
    break;
  case Geometry::Kind::polygon:
    lo = {inf, inf, 0.0}, hi = {-inf, -inf, 0.0};
    for (const auto& v : g.vertices)
      for (int d = 0; d < 2; ++d)
        lo[d] = std::min(lo[d], v[d]), hi[d] = std::max(hi[d], v[d]);
    break;
  }
}

double estimate_memory(const Case& c, const std::vector<std::size_t>& particles) {
  const int dim = c.simulation.dimension;
  const double nodes = grid_nodes(c.grid, dim);
  const bool contact = c.bodies.size() > 1, remap = c.simulation.scheme == Scheme::musl;
  double memory = nodes * bytes_per_grid_node;
  // What grows with the number of bodies B: the pair tables (B x B: the contact forces and their
  // time means, the pairs' friction and interface index); per node row along x the contact
  // record's work per body and sums per interface; per slab of 4 rows the scatter's offsets.
  const double B = static_cast<double>(c.bodies.size());
  const double rows = std::floor(c.grid.extent[0] / c.grid.cell_size + 1e-9) + 2.0;
  memory += B * B * (2.0 * sizeof(double) * dim + sizeof(double) + sizeof(int));
  if (contact) memory += rows * (B * sizeof(double) + 3.0 * sizeof(double) * c.interfaces.size());
  memory += (rows / 4.0 + 1.0) * B * sizeof(std::size_t);
  for (std::size_t b = 0; b < c.bodies.size(); ++b) {
    const BodySpec& body = c.bodies[b];
    int slots = 0;
    for (const InterfaceSpec& f : c.interfaces)
      slots += (f.a == static_cast<int>(b)) + (f.b == static_cast<int>(b));
    Vec3a lo{}, hi{};
    geometry_bounds(body.geometry[0], dim, lo, hi);
    memory += static_cast<double>(particles[b]) * bytes_per_particle(dim, c.simulation.apic);
    memory += std::min(nodes, field_nodes(lo, hi, dim, c.grid.cell_size)) *
              bytes_per_field_node(dim, contact, remap, slots);
  }
  return memory;
}

bool float32_positions_suffice(const GridSettings& grid, int dim) {
  // The grid's far face is a whole number of cells from its origin (Grid: ceil(extent / h)).
  double largest = 0.0;
  for (int d = 0; d < dim; ++d) {
    const double far =
        grid.origin[d] + std::ceil(grid.extent[d] / grid.cell_size - 1e-9) * grid.cell_size;
    largest = std::max({largest, std::abs(grid.origin[d]), std::abs(far)});
  }
  if (largest == 0.0) return true;
  const double half_spacing = std::ldexp(1.0, std::ilogb(largest) - 24);
  return half_spacing <= grid.cell_size / 2000.0;
}

bool frame_float32_positions(const Case& c) {
  return c.output.float32_positions.value_or(
      float32_positions_suffice(c.grid, c.simulation.dimension));
}

double frame_position_quantum(const Case& c) {
  if (c.output.field_bits == 0 || !frame_float32_positions(c) ||
      !float32_positions_suffice(c.grid, c.simulation.dimension))
    return 0.0;
  // The largest power of two <= h / 1000: every position within h / 2000, as float32's own
  // rounding promises, and each rounded position exact in float32 (float32_positions_suffice
  // puts float32's spacing at the grid's far face at or below h / 1000, a power of two too).
  return std::ldexp(1.0, std::ilogb(c.grid.cell_size / 1000.0));
}

double frame_bytes_per_particle(const Case& c) {
  const double real = c.output.float64_fields ? 8.0 : 4.0;
  const double position = frame_float32_positions(c) ? 12.0 : 24.0;
  auto wants = [&](const std::string& f) {
    return c.output.fields.empty() ||
           std::find(c.output.fields.begin(), c.output.fields.end(), f) != c.output.fields.end();
  };
  double bytes = position + 4 + 4 + 1 + 4 + 4; // positions, connectivity and offsets (Int32),
                                               // types, body, id
  bytes += wants("velocity") * 3 * real + wants("displacement") * 3 * real;
  bytes += wants("stress") * 6 * real;
  bytes += (wants("mass") + wants("volume") + wants("plastic_strain")) * real;
  bytes += (wants("material") + wants("field")) * 4.0;
  bytes += wants("interface") * (4.0 + 3 * real);
  return bytes;
}

double machine_memory() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
  return pages > 0 && page > 0 ? static_cast<double>(pages) * static_cast<double>(page) : 8e9;
}

RunPlan plan_run(const Case& c, const std::vector<std::size_t>& particles,
                 const std::string& out_dir) {
  RunPlan plan;
  double max_wave = 0.0; // the fastest P-wave, sqrt(M / rho), of a deformable body
  for (std::size_t b = 0; b < c.bodies.size(); ++b) {
    plan.particles += particles[b];
    const Material& mat = c.materials[c.bodies[b].material];
    if (!c.bodies[b].rigid)
      max_wave = std::max(max_wave, std::sqrt(mat.p_wave_modulus() / mat.density()));
  }
  const SimulationSettings& s = c.simulation;
  plan.cfl_dt = std::min(s.dt_max, s.cfl * c.grid.cell_size / max_wave);
  plan.dt = s.dt ? *s.dt : plan.cfl_dt;
  // Settling runs first, at its own CFL number (a fixed dt applies to both).
  const double settle_dt = s.dt ? plan.dt
                                : std::min(s.dt_max, c.initial_state.settle_cfl.value_or(s.cfl) *
                                                         c.grid.cell_size / max_wave);
  // Output times: the step is shortened to land on each, so there are at least as many steps.
  const double every = c.output.every > 0 ? c.output.every : s.end_time;
  const double outputs = std::ceil(s.end_time / every - 1e-9);
  plan.frames = c.output.particles ? outputs + 1.0 : 0.0;
  plan.steps = std::max(std::ceil(s.end_time / plan.dt), outputs) +
               std::ceil(c.initial_state.settle_time / settle_dt);
  plan.memory_bytes = estimate_memory(c, particles);
  plan.frame_bytes = frame_bytes_per_particle(c);
  // Fixed bodies (rigid, at rest) beside others are written once (RunWriter::frame_parts).
  double fixed = 0.0;
  for (std::size_t b = 0; b < c.bodies.size(); ++b)
    if (c.bodies[b].fixed(c.simulation.dimension)) fixed += static_cast<double>(particles[b]);
  if (fixed == static_cast<double>(plan.particles)) fixed = 0.0;
  plan.output_bytes = (plan.frames * (static_cast<double>(plan.particles) - fixed) +
                       std::min(plan.frames, 1.0) * fixed) *
                      plan.frame_bytes;
  // The free space where the run folder goes: its nearest folder that exists.
  std::error_code ec;
  std::filesystem::path where = std::filesystem::absolute(out_dir.empty() ? "." : out_dir, ec);
  while (!where.empty() && !std::filesystem::exists(where, ec) && where != where.parent_path())
    where = where.parent_path();
  if (const auto space = std::filesystem::space(where, ec); !ec)
    plan.free_disk_bytes = static_cast<double>(space.available);

  if (plan.frames > 10000)
    plan.warnings.push_back(
        fmt::format("output.every = {:.3g} s writes about {:.0f} frames: more than 10,000", every,
                    plan.frames));
  if (plan.free_disk_bytes >= 0 && plan.output_bytes > plan.free_disk_bytes)
    plan.warnings.push_back(fmt::format(
        "the output (about {:.3g} GB before compression) may not fit in the {:.3g} GB free here: "
        "a larger output.every or fewer output.fields",
        plan.output_bytes / 1e9, plan.free_disk_bytes / 1e9));
  if (s.dt && *s.dt > plan.cfl_dt)
    plan.warnings.push_back(fmt::format(
        "simulation.dt = {:.3g} s is {:.3g} times the stable (CFL {}) step {:.3g} s of the "
        "stiffest body: expect the run to blow up",
        *s.dt, *s.dt / plan.cfl_dt, s.cfl, plan.cfl_dt));
  // Refused: a step count past any run; an output that cannot fit even compressed.
  if (!(plan.steps <= max_run_steps))
    plan.refusal = fmt::format(
        "the case would take about {:.3g} steps (a time step of {:.3g} s), more than the {:.0e} a "
        "run may take: check simulation.end_time, simulation.dt and the materials' densities and "
        "moduli",
        plan.steps, plan.dt, max_run_steps);
  if (plan.free_disk_bytes >= 0 && best_compression(c) * plan.output_bytes > plan.free_disk_bytes)
    plan.disk_full = fmt::format(
        "the output (about {:.3g} GB before compression, at least {:.3g} GB compressed) does not "
        "fit in the {:.3g} GB free here: a larger output.every or fewer output.fields (or "
        "--force to run anyway)",
        plan.output_bytes / 1e9, best_compression(c) * plan.output_bytes / 1e9,
        plan.free_disk_bytes / 1e9);
  return plan;
}

} // namespace talus
