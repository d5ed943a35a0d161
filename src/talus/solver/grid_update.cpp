// The grid update (eq. 19-20): nodal velocities from momentum and force, with local damping, and
// the velocity conditions (the faces' and boxes', and the rigid bodies' prescribed velocities).
#include "talus/setup/boundary.hpp"
#include "talus/solver/simulation.hpp"

#include <cmath>

namespace talus {

// Eq. 19. Reads each field's m and p; writes v^n = p / m (zero where m = 0).
// The grid loops here share one parallel region across the bodies (each body's nodes split
// statically, no barrier between bodies): waking a team of sleeping threads costs tens of
// microseconds, as much as a body's loop over tens of thousands of nodes.
// A held field (a fixed rigid body's, from its second step) is skipped here and in every
// velocity loop: its velocities are its prescribed zero, written by apply_velocity_conditions
// in its first step and left as they are by contact, which writes back a rigid body's velocity
// unchanged.
template <int D>
void Simulation<D>::compute_node_velocities() {
#pragma omp parallel
  for (int b = 0; b < num_bodies(); ++b) {
    if (field_held_[b]) continue;
    BodyField<D>& N = fields_[b];
    const std::int64_t n = static_cast<std::int64_t>(N.size());
#pragma omp for schedule(static) nowait
    for (std::int64_t i = 0; i < n; ++i)
      N.v[i] = N.m[i] > 0.0 ? Vec<D>(N.p[i] / N.m[i]) : Vec<D>::Zero();
  }
}

// Eq. 20 with local (Cundall) damping: f_d = f - alpha |f| sign(v). Reads each field's m, p and
// f; writes v^{n+1} = p / m + f_d / m dt (zero where m = 0), from the unconstrained p / m.
template <int D>
void Simulation<D>::integrate_node_forces(double dt) {
  const double alpha = settling_ ? setup_.settle_damping : setup_.damping;
#pragma omp parallel
  for (int b = 0; b < num_bodies(); ++b) {
    if (field_held_[b]) continue;
    BodyField<D>& N = fields_[b];
    const std::int64_t n = static_cast<std::int64_t>(N.size());
#pragma omp for schedule(static) nowait
    for (std::int64_t i = 0; i < n; ++i) {
      if (N.m[i] <= 0.0) {
        N.v_new[i].setZero();
        continue;
      }
      const Vec<D> v = N.p[i] / N.m[i];
      Vec<D> f = N.f[i];
      if (alpha > 0.0)
        for (int d = 0; d < D; ++d)
          f[d] -= alpha * std::abs(f[d]) * (v[d] > 0.0 ? 1.0 : (v[d] < 0.0 ? -1.0 : 0.0));
      N.v_new[i] = v + f / N.m[i] * dt;
    }
  }
}

// A water body below a [water] level beside bodies that level buoys (their weight buoyant, their
// stress effective): at the nodes where such a body meets the water (has mass), the water's
// hydrostatic load there (BodyField::hydro) is held, taken off the
// water's nodal force, for the buoyed body's buoyancy already stands for it (the load of the
// hydrostatic water on a body below the level is its buoyancy plus the pore pressure's share of
// its total stress, neither of which its effective stress carries). The contact then passes on
// only what is not hydrostatic: the drag, the added mass, a wave's pressure. Reads the fields'
// masses and the water's hydrostatic load; writes the water's nodal force.
template <int D>
void Simulation<D>::hold_hydrostatic_load() {
  for (int w = 0; w < num_bodies(); ++w) {
    BodyField<D>& W = fields_[w];
    if (!W.needs.hydro) continue;
    const std::int64_t n = static_cast<std::int64_t>(W.size());
#pragma omp parallel for schedule(static)
    for (std::int64_t i = 0; i < n; ++i) {
      if (W.m[i] <= 0.0 || W.hydro[i].isZero()) continue;
      Index<D> g = W.box.node_coords(i);
      for (int d = 0; d < D; ++d)
        g[d] += W.offset[d];
      for (int b = 0; b < num_bodies(); ++b) {
        if (!(setup_.bodies[b].buoyancy > 0.0)) continue;
        const BodyField<D>& K = fields_[b];
        const std::int64_t j = K.local(g);
        if (j >= 0 && K.m[j] > 0.0) {
          W.f[i] -= W.hydro[i];
          break;
        }
      }
    }
  }
}

// Reads the setup's conditions; writes the field array `velocity` of every body at the nodes
// the conditions cover, then a rigid body's whole field to its prescribed velocity.
template <int D>
void Simulation<D>::apply_velocity_conditions(std::vector<Vec<D>> BodyField<D>::*velocity) {
  for (int b = 0; b < num_bodies(); ++b)
    if (!field_held_[b])
      apply_grid_conditions<D>(setup_.conditions, b, fields_[b], fields_[b].*velocity);
  for (int b = 0; b < num_bodies(); ++b)
    if (setup_.bodies[b].rigid && !field_held_[b])
      std::fill((fields_[b].*velocity).begin(), (fields_[b].*velocity).end(),
                setup_.bodies[b].rigid_velocity);
}

#define TALUS_INSTANTIATE(D)                                                                       \
  template void Simulation<D>::compute_node_velocities();                                          \
  template void Simulation<D>::integrate_node_forces(double);                                      \
  template void Simulation<D>::hold_hydrostatic_load();                                            \
  template void Simulation<D>::apply_velocity_conditions(std::vector<Vec<D>> BodyField<D>::*);
TALUS_INSTANTIATE(2)
TALUS_INSTANTIATE(3)

} // namespace talus
