#include "talus/solver/diagnostics.hpp"

#include "talus/core/math.hpp"
#include "talus/physics/water.hpp"

#include <algorithm>
#include <limits>
#include <variant>

namespace talus {

namespace {

// A particle's elastic energy, V (p^2 / 2K + J2 / 2G).
double elastic_energy(const Voigt& stress, double vol, double K, double G) {
  const double mean = mean_stress(stress);
  return vol * (0.5 * mean * mean / K + 0.5 * second_invariant(deviator(stress)) / G);
}

} // namespace

// Gravity's work since release, m g . (x - x0), and below a water level the buoyancy's,
// rho_w / rho m g (H(z0) - H(z)) (physics/water.hpp); the elastic energy V (p^2 / 2K + J2 / 2G).
template <int D>
void add_energy_terms(const Simulation<D>& sim, int b, bool own_only, ExactSum& gravity,
                      ExactSum& strain) {
  const auto& P = sim.particles();
  const WaterSetup<D>& W = sim.setup().water;
  const BodySetup<D>& body = sim.setup().bodies[b];
  const bool buoyant = W.on && body.buoyancy > 0.0;
  const double K = std::visit([](const auto& m) { return m.bulk_modulus(); }, body.material.model);
  const double G = std::visit([](const auto& m) { return m.shear_modulus(); }, body.material.model);
  // A fluid's: its equation of state's stored energy (its deviatoric stress is viscous).
  const Fluid* fluid = std::get_if<Fluid>(&body.material.model);
  for (std::size_t p = P.body_begin[b]; p < P.body_begin[b + 1]; ++p) {
    if (own_only && !sim.is_own(p)) continue;
    gravity += P.m[p] * sim.setup().gravity.dot(P.x[p] - P.x0[p]);
    if (buoyant)
      gravity += body.buoyancy * P.m[p] * W.g *
                 (submerged_integral(W.level, W.up.dot(P.x0[p]), body.particle_height) -
                  submerged_integral(W.level, W.up.dot(P.x[p]), body.particle_height));
    if (fluid)
      strain += P.vol0[p] * fluid->stored_energy(P.vol[p] / P.vol0[p]);
    else if (!body.rigid)
      strain += elastic_energy(P.stress[p], P.vol[p], K, G);
  }
}

template <int D>
double gravity_work(const Simulation<D>& sim, int b) {
  ExactSum gravity, strain;
  add_energy_terms(sim, b, false, gravity, strain);
  return gravity.value();
}

template <int D>
double strain_energy(const Simulation<D>& sim, int b) {
  ExactSum gravity, strain;
  add_energy_terms(sim, b, false, gravity, strain);
  return strain.value();
}

// Each process's nearest own particle, then the least distance over the processes and, among
// the processes at that distance, the least id.
template <int D>
std::vector<std::uint32_t> probe_ids(const Simulation<D>& sim) {
  const auto& P = sim.particles();
  const std::vector<ProbeSpec>& probes = sim.case_().probes;
  Exchange* exchange = sim.exchange();
  const int K = static_cast<int>(probes.size());
  std::vector<double> d2(K, inf), id(K, inf);
  for (int k = 0; k < K; ++k) {
    Vec<D> near;
    for (int d = 0; d < D; ++d)
      near[d] = probes[k].near[d];
    for (std::size_t p = P.body_begin[probes[k].body]; p < P.body_begin[probes[k].body + 1]; ++p) {
      const double q = (P.x[p] - near).squaredNorm();
      if (sim.is_own(p) && (q < d2[k] || (q == d2[k] && P.id[p] < id[k])))
        d2[k] = q, id[k] = P.id[p];
    }
  }
  if (exchange && K > 0) {
    std::vector<double> least(d2), unused(d2);
    exchange->min_max(least.data(), unused.data(), K);
    for (int k = 0; k < K; ++k)
      if (d2[k] != least[k]) id[k] = inf; // another process holds a nearer particle
    unused = id;
    exchange->min_max(id.data(), unused.data(), K);
  }
  std::vector<std::uint32_t> ids;
  for (int k = 0; k < K; ++k)
    ids.push_back(static_cast<std::uint32_t>(id[k]));
  return ids;
}

// The hydrostatic rho_w g (level - z) below the water level, plus the interface's excess.
template <int D>
double pore_pressure(const Simulation<D>& sim, std::size_t p) {
  const WaterSetup<D>& W = sim.setup().water;
  const double hydrostatic =
      W.on ? W.density * W.g * std::max(W.level - W.up.dot(sim.particles().x[p]), 0.0) : 0.0;
  return hydrostatic + sim.interface_pore_pressure(p);
}

template <int D>
double band_temperature(const Simulation<D>& sim, std::size_t p) {
  const auto& P = sim.particles();
  const Setup<D>& S = sim.setup();
  if (P.pore[p] < 0 || !S.bands[P.iface[p]]) return std::numeric_limits<double>::quiet_NaN();
  return S.interfaces[P.iface[p]].thermal_pressurization->temperature +
         sim.pore_pool().at(P.pore[p]).temperature_rise();
}

#define TALUS_INSTANTIATE(D)                                                                       \
  template void add_energy_terms(const Simulation<D>&, int, bool, ExactSum&, ExactSum&);           \
  template double gravity_work(const Simulation<D>&, int);                                         \
  template double strain_energy(const Simulation<D>&, int);                                        \
  template std::vector<std::uint32_t> probe_ids(const Simulation<D>&);                             \
  template double pore_pressure(const Simulation<D>&, std::size_t);                                \
  template double band_temperature(const Simulation<D>&, std::size_t);
TALUS_INSTANTIATE(2)
TALUS_INSTANTIATE(3)

} // namespace talus
