// The interface history (paper eq. 38-39): each interface particle's
// slip grows by the slip rate the recorded contact pass measured at its nodes, and its cohesion
// and friction follow their degradation curves.
#include "talus/solver/detail.hpp"
#include "talus/solver/simulation.hpp"

#include <algorithm>

namespace talus {

// Reads the slip rates and weights of each interface particle's own field (its interface's
// slot) and the shape-weight cache; writes the particle's slip, cohesion and friction. The rate
// is the weighted mean sum N_I w_I r_I / max(sum N_I w_I, min_slip_weight), so a particle that
// barely touches the nodes that measured one gathers proportionally less. Nothing degrades
// while settling, nor on a rigid body or an orphan (off its interface). Where the interface has
// pore pressure, the particle's normal stress is its share of the contact's normal force,
// sum N_I sigma_I (settling too), and a band takes its share of the frictional work.
template <int D>
void Simulation<D>::update_interface_history(double dt) {
  if ((settling_ && !setup_.pore_pressure) || setup_.num_interfaces == 0) return;
  auto& P = particles_;
  shape_.require(steps_, particles_.size());
  // One parallel region for every body with an interface (each particle's update is its own).
#pragma omp parallel
  for (int b = 0; b < num_bodies(); ++b) {
    if (setup_.bodies[b].rigid || fields_[b].slots == 0) continue;
    const BodyField<D>& N = fields_[b];
    const int S = N.slots;
    const std::int64_t begin = P.body_begin[b], end = P.body_begin[b + 1];
#pragma omp for schedule(static) nowait
    for (std::int64_t p = begin; p < end; ++p) {
      if (P.iface[p] < 0 || P.field[p] != b) continue;
      const int slot = setup_.slot(b, P.iface[p]);
      auto gather = [&](const std::vector<double>& a) {
        double sum = 0.0;
        for_each_node(N.box, shape_[p], [&](std::int64_t I, double N_I, const Vec<D>&) {
          sum += N_I * a[I * S + slot];
        });
        return sum;
      };
      const bool pore = P.pore[p] >= 0;
      const PoreRecord state = pore_.at(pore ? P.pore[p] : 0);
      const double share =
          pore ? effective_share(static_cast<std::size_t>(p)) : 0.0; // the scatter's
      // The total normal stress: the contact's (effective: the pore pressure has pushed the
      // bodies apart) plus that push, each the particle's share of its nodes' (zero where they
      // do not touch), as a recent mean. The push shared out is the mean pressure of the
      // particles at the nodes, so a particle whose p is above its neighbours' sees the normal
      // stress its nodes carry, not its own p: its effective stress is then below zero, and its
      // band takes no heat and drains (BandGrid::step's ceiling).
      if (pore) {
        double pushed = 0.0;
        for_each_node(N.box, shape_[p], [&](std::int64_t I, double N_I, const Vec<D>&) {
          const std::size_t i = static_cast<std::size_t>(I * S + slot);
          if (N.area[i] > 0.0) pushed += N_I * N.pore_force[i] / N.area[i];
        });
        const double contact = gather(N.normal_stress);
        const double now = contact > 0.0 ? contact + pushed : 0.0;
        state.normal_stress() += normal_stress_weight * (now - state.normal_stress());
      }
      if (settling_) continue;
      double rate = 0.0, weight = 0.0;
      for_each_node(N.box, shape_[p], [&](std::int64_t I, double N_I, const Vec<D>&) {
        rate += N_I * N.slip_rate[I * S + slot];
        weight += N_I * N.slip_weight[I * S + slot];
      });
      const InterfaceSpec& spec = setup_.interfaces[P.iface[p]];
      P.slip[p] += rate / std::max(weight, detail::min_slip_weight) * dt;
      P.cohesion[p] = spec.cohesion.at(P.slip[p], spec.curve);
      P.friction[p] = spec.friction.at(P.slip[p], spec.curve);
      if (pore && setup_.bands[P.iface[p]]) {
        // Thermal pressurization: the band takes its share of the frictional work at its nodes,
        // (1 - r^p) sum N_I W_I (J/m^2; the particles at a node share its work by
        // N_I A^p (1 - r^p), so the heat is the interface's dissipation and a band whose pore
        // pressure has reached its normal stress, carrying no friction, takes none); above its
        // normal stress the band is open and drains (the ceiling: sigma_n less the interface's
        // own pore pressure); its mean rises go to the pool's header for the next scatter and
        // the output.
        const BandGrid& band = *setup_.bands[P.iface[p]];
        const double ambient = setup_.interfaces[P.iface[p]].pore_pressure;
        band.step(state.band(), share * gather(N.heat), dt, state.normal_stress() - ambient);
        state.temperature_rise() = band.mean_temperature(state.band());
        state.pressure_rise() = band.mean_pressure(state.band());
      }
    }
  }
}

#define TALUS_INSTANTIATE(D) template void Simulation<D>::update_interface_history(double);
TALUS_INSTANTIATE(2)
TALUS_INSTANTIATE(3)

} // namespace talus
