// The interface history (ARCHITECTURE.md step 9, paper eq. 38-39): each interface particle's
// slip grows by the slip rate the recorded contact pass measured at its nodes, and its cohesion
// and friction follow their degradation curves.
#include "talus/solver.hpp"
#include "talus/solver/detail.hpp"

#include <algorithm>

namespace talus {

// Reads the slip rates and weights of each interface particle's own field (its interface's
// slot) and the shape-weight cache; writes the particle's slip, cohesion and friction. The rate
// is the weighted mean sum N_I w_I r_I / max(sum N_I w_I, min_slip_weight), so a particle that
// barely touches the nodes that measured one gathers proportionally less. Nothing degrades
// while settling, nor on a rigid body or an orphan (off its interface).
template <int D>
void Simulation<D>::update_interface_history(double dt) {
  if (settling_ || setup_.num_interfaces == 0) return;
  auto& P = particles_;
  for (int b = 0; b < num_bodies(); ++b) {
    if (setup_.bodies[b].rigid || fields_[b].slots == 0) continue;
    assert_shape_current();
    const BodyField<D>& N = fields_[b];
    const int S = N.slots;
    const std::int64_t begin = P.body_begin[b], end = P.body_begin[b + 1];
#pragma omp parallel for schedule(static)
    for (std::int64_t p = begin; p < end; ++p) {
      if (P.iface[p] < 0 || P.field[p] != b) continue;
      const int slot = setup_.slot(b, P.iface[p]);
      double rate = 0.0, weight = 0.0;
      for_each_node(N.box, shape_[p], [&](std::int64_t I, double N_I, const Vec<D>&) {
        rate += N_I * N.slip_rate[I * S + slot];
        weight += N_I * N.slip_weight[I * S + slot];
      });
      const InterfaceSpec& spec = setup_.interfaces[P.iface[p]];
      P.slip[p] += rate / std::max(weight, detail::min_slip_weight) * dt;
      P.cohesion[p] = spec.cohesion.at(P.slip[p], spec.curve);
      P.friction[p] = spec.friction.at(P.slip[p], spec.curve);
    }
  }
}

#define TALUS_INSTANTIATE(D) template void Simulation<D>::update_interface_history(double);
TALUS_INSTANTIATE(2)
TALUS_INSTANTIATE(3)

} // namespace talus
