// What the run folder's tables record of the state at a frame, summed over the particles: per
// body its mass, centroid, velocity, speeds and energies, per interface with pore pressure its
// water figures, and the probes' particles. Formed on every process from its own particles and
// combined exactly (core/exact_sum.hpp), so that they are the same bits on any number of processes
// and threads, and no process needs the whole state.
#pragma once

#include "talus/solver/simulation.hpp"

#include <cstdint>
#include <vector>

namespace talus {

template <int D>
struct BodyTotals {
  std::size_t particles = 0;
  double mass = 0.0;
  Vec<D> centroid = Vec<D>::Zero(), velocity = Vec<D>::Zero(); // mass-weighted means
  double mean_speed = 0.0, max_speed = 0.0;                    // mass-weighted mean |v|, max |v|
  double kinetic_energy = 0.0, gravity_work = 0.0, strain_energy = 0.0;
  std::size_t orphans = 0; // particles on another body's field
};

// Per interface with pore pressure: the area means and the largest of its particles' excess pore
// pressure (Pa) and band temperature (deg C; NaN without a band), orphans aside.
struct InterfaceWater {
  double pressure_mean = 0.0, pressure_max = 0.0;
  double temperature_mean = 0.0, temperature_max = 0.0;
};

template <int D>
struct ProbeState {
  Vec<D> x = Vec<D>::Zero(), v = Vec<D>::Zero(), x0 = Vec<D>::Zero();
};

template <int D>
struct FrameTotals {
  std::vector<BodyTotals<D>> bodies;
  double kinetic_energy = 0.0;       // of every particle
  Vec<D> momentum = Vec<D>::Zero();  // of every particle
  std::vector<InterfaceWater> water; // per interface (zeros without pore pressure)
  std::vector<ProbeState<D>> probes; // per probe id given
  std::vector<double> gauges;        // per [[gauge]]: the surface's elevation (NaN: dry)
};

// Collective on several processes (Simulation::exchange): every process calls it.
template <int D>
FrameTotals<D> frame_totals(const Simulation<D>& sim, const std::vector<std::uint32_t>& probe_ids);

} // namespace talus
