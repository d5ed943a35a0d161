#include "talus/case/size.hpp"

#include <cmath>
#include <numbers>
#include <unistd.h>

namespace talus {

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
  case Geometry::Kind::polygon: {
    double twice = 0.0; // shoelace; a self-crossing polygon gives at most its true area
    const auto& v = g.vertices;
    for (std::size_t i = 0; i < v.size(); ++i) {
      const auto& a = v[i];
      const auto& b = v[(i + 1) % v.size()];
      twice += a[0] * b[1] - b[0] * a[1];
    }
    return 0.5 * std::abs(twice);
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

double machine_memory() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
  return pages > 0 && page > 0 ? static_cast<double>(pages) * static_cast<double>(page) : 8e9;
}

} // namespace talus
