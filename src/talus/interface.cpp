#include "talus/interface.hpp"

#include <cmath>
#include <unordered_map>
#include <vector>

namespace talus {

template <int D>
void mark_interface_particles(const Case& c, Particles<D>& P) {
  const double h = c.grid.cell_size;
  auto cell_key = [&](const Vec<D>& x) {
    std::int64_t key = 0;
    for (int d = 0; d < D; ++d)
      key = key * 2000003 + static_cast<std::int64_t>(std::floor((x[d] - c.grid.origin[d]) / h));
    return key;
  };
  for (std::size_t f = 0; f < c.interfaces.size(); ++f) {
    const InterfaceSpec& spec = c.interfaces[f];
    for (int side = 0; side < 2; ++side) {
      const int self = side == 0 ? spec.a : spec.b, other = side == 0 ? spec.b : spec.a;
      // The other body's particles, binned by cell.
      std::unordered_map<std::int64_t, std::vector<std::size_t>> bins;
      for (std::size_t q = P.body_begin[other]; q < P.body_begin[other + 1]; ++q)
        bins[cell_key(P.x[q])].push_back(q);
      const double s = h / c.bodies[self].particles_per_cell;
      const double reach = 1.5 * std::max(s, h / c.bodies[other].particles_per_cell);
      for (std::size_t p = P.body_begin[self]; p < P.body_begin[self + 1]; ++p) {
        bool near = false;
        Index<D> o{};
        for (int d = 0; d < D; ++d)
          o[d] = -1;
        while (!near) {
          Vec<D> probe = P.x[p];
          for (int d = 0; d < D; ++d)
            probe[d] += static_cast<double>(o[d]) * h;
          if (auto it = bins.find(cell_key(probe)); it != bins.end())
            for (const std::size_t q : it->second)
              if ((P.x[q] - P.x[p]).norm() <= reach) near = true;
          int d = D - 1;
          while (d >= 0 && ++o[d] == 2)
            o[d] = -1, --d;
          if (d < 0) break;
        }
        if (!near) continue;
        P.iface[p] = static_cast<std::int32_t>(f);
        P.iface_area[p] = std::pow(s, D - 1);
        P.cohesion[p] = spec.cohesion.initial;
        P.friction[p] = spec.friction.initial;
        P.slip[p] = 0.0;
      }
    }
  }
}

template void mark_interface_particles<2>(const Case&, Particles<2>&);
template void mark_interface_particles<3>(const Case&, Particles<3>&);

} // namespace talus
