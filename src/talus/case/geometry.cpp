#include "talus/case/geometry.hpp"

#include "talus/case/parse.hpp"

#include <cmath>
#include <fmt/format.h>

namespace talus {

bool point_in_polygon(const std::vector<std::array<double, 2>>& poly, double x, double y) {
  // Crossing number: count edges crossed by the ray towards +x (half-open on y, so vertices on
  // the ray count once).
  bool in = false;
  const std::size_t n = poly.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const auto& a = poly[i];
    const auto& b = poly[j];
    if ((a[1] > y) != (b[1] > y)) {
      const double xc = a[0] + (y - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
      if (x < xc) in = !in;
    }
  }
  return in;
}

template <int D>
bool inside(const Geometry& g, const Vec<D>& x) {
  switch (g.kind) {
  case Geometry::Kind::box:
    for (int d = 0; d < D; ++d)
      if (x[d] < g.min[d] || x[d] > g.max[d]) return false;
    return true;
  case Geometry::Kind::disk: {
    double r2 = 0.0;
    for (int d = 0; d < D; ++d)
      r2 += (x[d] - g.center[d]) * (x[d] - g.center[d]);
    return r2 <= g.radius * g.radius;
  }
  case Geometry::Kind::polygon:
    if constexpr (D == 2) return point_in_polygon(g.vertices, x[0], x[1]);
    return false;
  }
  return false;
}

namespace {

// Calls f(position) for each sub-cell centre of the grid that lies inside the body.
template <int D, class F>
void for_each_seed(const Case& c, const BodySpec& b, F&& f) {
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
  if (g.kind == Geometry::Kind::box)
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
  for (int d = 0; d < D; ++d)
    if (lo[d] >= hi[d]) return;
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
Particles<D> fill_particles(const Case& c) {
  Particles<D> P;
  for (const BodySpec& b : c.bodies) {
    const double rho = c.materials[b.material].density();
    const double vol = std::pow(c.grid.cell_size / b.particles_per_cell, D);
    Vec<D> v0;
    for (int d = 0; d < D; ++d)
      v0[d] = b.velocity[d];
    const std::size_t before = P.size();
    for_each_seed<D>(c, b, [&](const Vec<D>& x) { P.push_back(x, v0, rho * vol, vol); });
    require_particles(c, P.body_begin.size() - 1, P.size() - before);
    P.body_begin.push_back(P.size());
  }
  return P;
}

template bool inside<2>(const Geometry&, const Vec<2>&);
template bool inside<3>(const Geometry&, const Vec<3>&);
template Particles<2> fill_particles<2>(const Case&);
template Particles<3> fill_particles<3>(const Case&);

} // namespace talus
