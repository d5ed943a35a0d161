#include "talus/setup/initial_state.hpp"

#include "talus/physics/water.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <vector>

namespace talus {

template <int D>
void apply_k0_stress(const Case& c, Particles<D>& P) {
  double g = 0.0;
  for (int d = 0; d < D; ++d)
    g += c.simulation.gravity[d] * c.simulation.gravity[d];
  g = std::sqrt(g);
  const double h = c.grid.cell_size;
  const double area = std::pow(h, D - 1);
  // Group particles by column, then walk each column from the top down.
  std::map<std::vector<std::int64_t>, std::vector<std::size_t>> columns;
  for (std::size_t p = 0; p < P.size(); ++p) {
    std::vector<std::int64_t> key(D - 1);
    for (int d = 0; d < D - 1; ++d)
      key[d] = static_cast<std::int64_t>(std::floor((P.x[p][d] - c.grid.origin[d]) / h));
    columns[key].push_back(p);
  }
  for (auto& [key, ps] : columns) {
    std::stable_sort(ps.begin(), ps.end(),
                     [&](std::size_t a, std::size_t b) { return P.x[a][D - 1] > P.x[b][D - 1]; });
    // Two overburdens: the buoyant one, whose weight the skeleton of a body below a water level
    // carries (its effective stress; water below the level weighs nothing in it), and the whole
    // one, which a water body's pressure holds. Without a level they are the same.
    double above = 0.0, above_whole = 0.0;
    for (const std::size_t p : ps) {
      const int b = P.body_of(p);
      const bool fluid = std::holds_alternative<Fluid>(c.materials[c.bodies[b].material].model);
      double m = P.m[p];
      const double m_whole = m;
      if (c.water.level && !c.bodies[b].rigid)
        m *= 1.0 - c.water.density /
                       (fluid ? c.water.density : c.materials[c.bodies[b].material].density()) *
                       submerged_fraction(*c.water.level, P.x[p][D - 1],
                                          h / c.bodies[b].particles_per_cell);
      const double sigma_v = -g * (fluid ? above_whole + 0.5 * m_whole : above + 0.5 * m) / area;
      above += m;
      above_whole += m_whole;
      double k0 = c.initial_state.k0;
      if (k0 < 0.0) {
        const double nu = std::visit([](const auto& m) { return m.poisson_ratio; },
                                     c.materials[c.bodies[b].material].model);
        k0 = nu / (1.0 - nu);
      }
      if (c.bodies[b].rigid) continue;
      if (const auto* f = std::get_if<Fluid>(&c.materials[c.bodies[b].material].model)) {
        // Hydrostatic, p = -sigma_v, held by the fluid's state: the volume ratio J(p), its
        // seeded volume the compressed one (V_0 = V / J).
        const double J = f->volume_ratio(-sigma_v);
        P.F[p] = Mat<D>::Identity() * std::pow(J, 1.0 / D);
        P.vol0[p] = P.vol[p] / J;
        P.stress[p] = Voigt::Zero();
        for (int i = 0; i < 3; ++i)
          P.stress[p][i] = sigma_v;
        continue;
      }
      Voigt s = Voigt::Zero();
      for (int i = 0; i < 3; ++i)
        s[i] = k0 * sigma_v;
      s[D - 1] = sigma_v;
      P.stress[p] = s;
    }
  }
}

template void apply_k0_stress<2>(const Case&, Particles<2>&);
template void apply_k0_stress<3>(const Case&, Particles<3>&);

} // namespace talus
