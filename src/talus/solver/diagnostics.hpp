// What the output reads from a Simulation besides its state: the energy budget's terms summed
// from the particles, a particle's pore pressure and band temperature, and the probes' particles.
// Pure functions of the state, not part of the step.
#pragma once

#include "talus/core/exact_sum.hpp"
#include "talus/solver/simulation.hpp"

#include <cstdint>
#include <vector>

namespace talus {

// Body b's energy budget since release (or the start, without settling), J (per unit thickness
// in 2D), is gravity's work, the contact and interface forces' work (Simulation::contact_work),
// the stresses' work (Simulation::internal_work: the elastic energy stored plus the plastic
// work) and the elastic energy held now; with the kinetic energy, what does not balance is the
// scheme's own dissipation and the work of the grid conditions.

// Adds body b's gravity work (m g . (x - x0), and below a water level the buoyancy's) and elastic
// energy (V (p^2 / 2K + J2 / 2G)) to `gravity` and `strain`: of every particle sim holds, or
// (own_only, on several processes) of this process's own, for a sum over the processes.
template <int D>
void add_energy_terms(const Simulation<D>& sim, int b, bool own_only, ExactSum& gravity,
                      ExactSum& strain);
// The same summed over every particle sim holds (one process: the whole body).
template <int D>
double gravity_work(const Simulation<D>& sim, int b);
template <int D>
double strain_energy(const Simulation<D>& sim, int b);

// The pore pressure of particle p (Pa): the hydrostatic rho_w g (level - z) below a water level,
// plus an interface particle's excess (Simulation::interface_pore_pressure).
template <int D>
double pore_pressure(const Simulation<D>& sim, std::size_t p);
// The band temperature of an interface particle with thermal pressurization (deg C), else NaN.
template <int D>
double band_temperature(const Simulation<D>& sim, std::size_t p);

// Stable ids of the case's probes: the particle of the probe's body nearest its point now (of
// equals, the least id). Collective on several processes.
template <int D>
std::vector<std::uint32_t> probe_ids(const Simulation<D>& sim);

} // namespace talus
