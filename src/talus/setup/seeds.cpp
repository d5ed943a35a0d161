#include "talus/setup/seeds.hpp"

#include "talus/case/geometry.hpp"
#include "talus/case/parse.hpp"

#include <cmath>
#include <fmt/format.h>

namespace talus {

namespace {

// Calls f(position) for each sub-cell centre of the grid that lies inside the body.
// A 2D lattice rotated by b.lattice_angle about the geometry's anchor (first polygon vertex, box
// corner or disk centre): seeds at anchor + R ((i + 1/2) s, (j + 1/2) s).
template <class F>
void for_each_rotated_seed(const Case& c, const BodySpec& b, F&& f) {
  const Geometry& g = b.geometry[0];
  const double s = c.grid.cell_size / b.particles_per_cell;
  const double ca = std::cos(b.lattice_angle), sa = std::sin(b.lattice_angle);
  Vec<2> anchor;
  std::vector<Vec<2>> corners;
  if (g.kind == Geometry::Kind::polygon) {
    anchor = Vec<2>(g.vertices[0][0], g.vertices[0][1]);
    for (const auto& v : g.vertices)
      corners.emplace_back(v[0], v[1]);
  } else if (g.kind == Geometry::Kind::box) {
    anchor = Vec<2>(g.min[0], g.min[1]);
    corners = {Vec<2>(g.min[0], g.min[1]), Vec<2>(g.max[0], g.min[1]), Vec<2>(g.max[0], g.max[1]),
               Vec<2>(g.min[0], g.max[1])};
  } else {
    anchor = Vec<2>(g.center[0], g.center[1]);
    for (int k = 0; k < 4; ++k)
      corners.push_back(anchor + g.radius * Vec<2>(k % 2 ? 1 : -1, k / 2 ? 1 : -1));
  }
  // The geometry's extent in lattice coordinates.
  double lo[2] = {inf, inf}, hi[2] = {-inf, -inf};
  for (const Vec<2>& x : corners) {
    const Vec<2> d = x - anchor;
    const double u = ca * d[0] + sa * d[1], w = -sa * d[0] + ca * d[1];
    lo[0] = std::min(lo[0], u), hi[0] = std::max(hi[0], u);
    lo[1] = std::min(lo[1], w), hi[1] = std::max(hi[1], w);
  }
  const Vec<2> gmin(c.grid.origin[0], c.grid.origin[1]);
  const Vec<2> gmax = gmin + Vec<2>(c.grid.extent[0], c.grid.extent[1]);
  for (auto i = static_cast<std::int64_t>(std::floor(lo[0] / s)) - 1; i * s < hi[0]; ++i)
    for (auto j = static_cast<std::int64_t>(std::floor(lo[1] / s)) - 1; j * s < hi[1]; ++j) {
      const double u = (static_cast<double>(i) + 0.5) * s, w = (static_cast<double>(j) + 0.5) * s;
      const Vec<2> x = anchor + Vec<2>(ca * u - sa * w, sa * u + ca * w);
      if ((x.array() >= gmin.array()).all() && (x.array() <= gmax.array()).all() && inside<2>(g, x))
        f(x);
    }
}

template <int D, class F>
void for_each_lattice_seed(const Case& c, const BodySpec& b, F&& f);

// Calls f(position) for each seed of body b: its lattice inside its geometry, and for a body that
// fills around the others (fill_around: a reservoir) only where no other body's geometry is.
template <int D, class F>
void for_each_seed(const Case& c, const BodySpec& b, F&& f) {
  if (!b.fill_around) return for_each_lattice_seed<D>(c, b, f);
  for_each_lattice_seed<D>(c, b, [&](const Vec<D>& x) {
    for (const BodySpec& o : c.bodies)
      if (&o != &b)
        for (const Geometry& g : o.geometry)
          if (inside<D>(g, x)) return;
    f(x);
  });
}

template <int D, class F>
void for_each_lattice_seed(const Case& c, const BodySpec& b, F&& f) {
  if constexpr (D == 2) {
    if (b.lattice_angle != 0.0) {
      for_each_rotated_seed(c, b, f);
      return;
    }
  }
  const double h = c.grid.cell_size;
  const int n = b.particles_per_cell;
  const double s = h / n;
  Index<D> cells{};
  std::int64_t total = 1;
  for (int d = 0; d < D; ++d) {
    cells[d] = static_cast<std::int64_t>(std::ceil(c.grid.extent[d] / h - 1e-9)) * n;
    total *= cells[d];
  }
  // Only the sub-cells in the bounding box of the geometry are visited.
  Index<D> lo{}, hi{};
  for (int d = 0; d < D; ++d)
    lo[d] = 0, hi[d] = cells[d];
  const Geometry& g = b.geometry[0];
  Vec3a blo{}, bhi{};
  if (g.kind == Geometry::Kind::box || g.kind == Geometry::Kind::prism ||
      g.kind == Geometry::Kind::terrain)
    blo = g.min, bhi = g.max;
  else if (g.kind == Geometry::Kind::disk)
    for (int d = 0; d < D; ++d)
      blo[d] = g.center[d] - g.radius, bhi[d] = g.center[d] + g.radius;
  else {
    blo = {inf, inf, 0}, bhi = {-inf, -inf, 0};
    for (const auto& v : g.vertices)
      for (int d = 0; d < 2; ++d)
        blo[d] = std::min(blo[d], v[d]), bhi[d] = std::max(bhi[d], v[d]);
  }
  for (int d = 0; d < D; ++d) {
    lo[d] = std::max<std::int64_t>(
        0, static_cast<std::int64_t>(std::floor((blo[d] - c.grid.origin[d]) / s)));
    hi[d] = std::min<std::int64_t>(
        cells[d], static_cast<std::int64_t>(std::ceil((bhi[d] - c.grid.origin[d]) / s)));
  }
  Index<D> i = lo;
  if (D == 0 || total == 0) return;
  // A terrain's columns are visited even where its z range is empty, so that a bottom above its
  // top everywhere is refused at a point, not taken for a body without particles.
  const int spanned = D == 3 && g.kind == Geometry::Kind::terrain ? 2 : D;
  for (int d = 0; d < spanned; ++d)
    if (lo[d] >= hi[d]) return;
  if constexpr (D == 3) {
    if (g.kind == Geometry::Kind::terrain) {
      // Column by column: the surfaces are read once per (x, y), and a bottom above its top is
      // refused where it is seen.
      for (i[0] = lo[0]; i[0] < hi[0]; ++i[0])
        for (i[1] = lo[1]; i[1] < hi[1]; ++i[1]) {
          const double x = c.grid.origin[0] + (static_cast<double>(i[0]) + 0.5) * s;
          const double y = c.grid.origin[1] + (static_cast<double>(i[1]) + 0.5) * s;
          if (g.footprint && !point_in_polygon(g.vertices, x, y)) continue;
          const auto [top, bottom] = terrain_column(g, x, y);
          if (!std::isfinite(top) || !std::isfinite(bottom)) continue; // a hole
          if (bottom > top) {
            const TerrainSurface& ras = g.top.raster ? g.top : g.bottom;
            std::string cell;
            if (ras.raster) {
              const auto rc = ras.raster->file_cell(x, y);
              cell =
                  fmt::format(", cell (row {}, column {}) of {}", rc[0], rc[1], ras.raster->file);
            }
            throw CaseError(fmt::format(
                "{}: body '{}': its bottom ({:.6g} m) is above its top ({:.6g} m) at x = {:.6g}, "
                "y = {:.6g} (local m){}",
                c.file, b.name, bottom, top, x, y, cell));
          }
          for (i[2] = lo[2]; i[2] < hi[2]; ++i[2]) {
            const double z = c.grid.origin[2] + (static_cast<double>(i[2]) + 0.5) * s;
            if (z >= bottom && z <= top) f(Vec<D>(x, y, z));
          }
        }
      return;
    }
  }
  while (true) {
    Vec<D> x;
    for (int d = 0; d < D; ++d)
      x[d] = c.grid.origin[d] + (static_cast<double>(i[d]) + 0.5) * s;
    if (inside<D>(g, x)) f(x);
    int d = D - 1;
    while (d >= 0 && ++i[d] == hi[d])
      i[d] = lo[d], --d;
    if (d < 0) break;
  }
}

} // namespace

void require_particles(const Case& c, std::size_t body, std::size_t count) {
  if (count > 0) return;
  const BodySpec& b = c.bodies[body];
  throw CaseError(
      fmt::format("{}: body '{}': its geometry holds no particle at cell size {} m with "
                  "{} particles per cell",
                  c.file, b.name, c.grid.cell_size, b.particles_per_cell));
}

std::size_t count_particles(const Case& c, std::size_t body) {
  std::size_t n = 0;
  if (c.simulation.dimension == 2)
    for_each_seed<2>(c, c.bodies[body], [&](const Vec<2>&) { ++n; });
  else
    for_each_seed<3>(c, c.bodies[body], [&](const Vec<3>&) { ++n; });
  return n;
}

template <int D>
SeedParticle<D> seed_particle(const Case& c, std::size_t body) {
  const BodySpec& b = c.bodies[body];
  SeedParticle<D> s;
  s.vol = std::pow(c.grid.cell_size / b.particles_per_cell, D);
  s.m = c.materials[b.material].density() * s.vol;
  for (int d = 0; d < D; ++d)
    s.v[d] = b.velocity[d];
  return s;
}

template <int D>
void for_each_seed_of(const Case& c, std::size_t body,
                      const std::function<void(const Vec<D>&)>& f) {
  for_each_seed<D>(c, c.bodies[body], f);
}

template <int D>
Particles<D> fill_particles(const Case& c) {
  Particles<D> P;
  // Exact capacity: growing by doubling would leave up to half of every array unused (and the
  // copies make the peak of the set-up higher still).
  std::size_t total = 0;
  for (std::size_t b = 0; b < c.bodies.size(); ++b)
    total += count_particles(c, b);
  P.reserve(total);
  for (std::size_t b = 0; b < c.bodies.size(); ++b) {
    const SeedParticle<D> s = seed_particle<D>(c, b);
    const std::size_t before = P.size();
    for_each_seed<D>(c, c.bodies[b], [&](const Vec<D>& x) { P.push_back(x, s.v, s.m, s.vol); });
    require_particles(c, b, P.size() - before);
    P.body_begin.push_back(P.size());
  }
  return P;
}

template Particles<2> fill_particles<2>(const Case&);
template SeedParticle<2> seed_particle<2>(const Case&, std::size_t);
template SeedParticle<3> seed_particle<3>(const Case&, std::size_t);
template void for_each_seed_of<2>(const Case&, std::size_t,
                                  const std::function<void(const Vec<2>&)>&);
template void for_each_seed_of<3>(const Case&, std::size_t,
                                  const std::function<void(const Vec<3>&)>&);
template Particles<3> fill_particles<3>(const Case&);

} // namespace talus
