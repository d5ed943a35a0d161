// P2G: the particles' mass, momentum, forces and contact data onto their body's field
// (eq. 14-18, 30, 37), in the coloured slab order that makes the sums thread-count independent.
#include "talus/setup/interface.hpp"
#include "talus/solver/detail.hpp"
#include "talus/solver/scatter.hpp"
#include "talus/solver/simulation.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <numeric>
#include <variant>

namespace talus {

// P2G, eq. 14-18, 30 and 37. Reads the particles; writes the shape-weight cache and each field's
// mass, momentum, mass gradient and mass-weighted position (near other bodies), the interfaces'
// friction and area (their capacities: share_interface_loads), and with `with_forces` the
// internal and external force. The mass gradient and position serve
// contact only; a single body skips them.
template <int D>
void Simulation<D>::map_particles_to_nodes(bool with_forces) {
  const bool contact = fields_.empty() || fields_[0].needs.contact;
  auto with_apic = [&]<bool forces, bool near>() {
    setup_.apic ? scatter_particles<forces, near, true>()
                : scatter_particles<forces, near, false>();
  };
  if (with_forces)
    contact ? with_apic.template operator()<true, true>()
            : with_apic.template operator()<true, false>();
  else
    contact ? with_apic.template operator()<false, true>()
            : with_apic.template operator()<false, false>();
}

// Whether any node in the support of sw (body b's weights) lies in another body's field box.
template <int D>
bool Simulation<D>::reaches_other_body(int b, const ShapeWeights<D>& sw, int margin) const {
  const BodyField<D>& N = fields_[b];
  for (int c = 0; c < static_cast<int>(fields_.size()); ++c) {
    if (c == b) continue;
    const BodyField<D>& O = fields_[c];
    bool overlap = true;
    for (int d = 0; d < D && overlap; ++d) {
      const std::int64_t first = N.offset[d] + sw.base[d], last = first + sw.k[d] - 1;
      overlap = last >= O.frame_offset[d] - margin &&
                first < O.frame_offset[d] + O.frame.nodes[d] + margin;
    }
    if (overlap) return true;
  }
  return false;
}

template <int D>
template <bool with_forces, bool with_contact, bool apic>
void Simulation<D>::scatter_particles() {
  auto& P = particles_;
  const ShapeKind kind = setup_.shape;
  shape_.weights.resize(P.size());
  shape_.step = steps_;
  const bool bspline = kind == ShapeKind::bspline;
  scatter([&](std::uint32_t p, int b) {
    const int f = P.field[p]; // b, or the host of an orphan
    BodyField<D>& N = fields_[f];
    ShapeWeights<D>& sw = shape_.weights[p];
    N.weights(sw, kind, setup_.bodies[b].gimp, P.x[p]);
    const double m_p = P.m[p];
    const Vec<D> mv_p = m_p * P.v[p], mx_p = m_p * P.x[p];
    const Mat<D> Vsigma = P.vol[p] * in_plane<D>(to_tensor(P.stress[p]));
    const Vec<D> mg = setup_.weight(m_p, b, P.x[p]);
    auto map = [&]<bool contact>() {
      for_each_node(N.box, sw, [&](std::int64_t I, double N_I, const Vec<D>& dN_I) {
        N.m[I] += N_I * m_p;
        if constexpr (apic) // APIC: p_I += N_I m_p (v_p + C_p (x_I - x_p)); a rigid body's C is 0
          N.p[I] +=
              N_I * (mv_p + m_p * (P.C[p] * (detail::apic_node_position(N, I, bspline) - P.x[p])));
        else
          N.p[I] += N_I * mv_p;
        if constexpr (contact) {
          N.mx[I] += N_I * mx_p;
          N.grad_m[I] += m_p * dN_I;
        }
        if constexpr (with_forces) N.f[I] += N_I * mg - Vsigma * dN_I;
      });
    };
    // Contact reads the mass gradient and position only at nodes another body also reaches, all
    // inside that body's box, and the gradient also within normal_smoothing cells of them: a
    // particle whose nodes miss every other box so widened (most of the Vaiont bedrock) skips
    // them. The sums at every node contact reads are unchanged.
    // A fixed body's field is scattered once for every step to come: all of it.
    const bool near = with_contact && (setup_.bodies[b].fixed ||
                                       reaches_other_body(f, sw, setup_.normal_smoothing));
    near ? map.template operator()<true>() : map.template operator()<false>();
    if (with_forces && N.needs.hydro) scatter_hydrostatic_load(N, sw, p);
    if (P.iface[p] >= 0 && f == b) { // eq. 37 (an orphan is not on its interface any more): the
                                     // interface particle's friction and area at its nodes (its
                                     // capacities: share_interface_loads)
      const double A = P.iface_area[p];
      const double muA = P.friction[p] * A;
      const int S = N.slots, slot = setup_.slot(b, P.iface[p]);
      for_each_node(N.box, sw, [&](std::int64_t I, double N_I, const Vec<D>&) {
        const std::int64_t j = I * S + slot;
        N.friction_area[j] += N_I * muA;
        N.area[j] += N_I * A;
      });
      if (P.pore[p] >= 0 && N.needs.heating) { // sum N A^p (1 - r^p): shares the heat out
        const double weight = A * effective_share(p);
        for_each_node(N.box, sw, [&](std::int64_t I, double N_I, const Vec<D>&) {
          N.heat_weight[I * S + slot] += N_I * weight;
        });
      }
    }
  });
}

template <int D>
int Simulation<D>::interface_slave(int f) const {
  const int a = setup_.interfaces[f].a, b = setup_.interfaces[f].b;
  const BodySetup<D>&A = setup_.bodies[a], &B = setup_.bodies[b];
  return detail::slave_rule(A.rigid, detail::body_rank(A.mass, a), B.rigid,
                            detail::body_rank(B.mass, b))
             ? a
             : b;
}

// What each of an interface's slave particles carries across it, shared out over the nodes of
// its support where the pair meets, in proportion to its weights there: its cohesive and tensile
// capacities c^p A^p and t^p A^p (eq. 37) and its excess pore pressure's force p^p A^p
// (docs/formulation.md, "Pore pressure on an interface"),
//   X_I = sum_p X^p N_I / max(sum_J N_J, min_share)   (J: the nodes where the pair meets).
// Contact acts only at nodes both bodies reach: a share scattered onto a node the partner does
// not reach (the row of nodes inside the slave along a grid-aligned interface) would be lost, and
// a cohesive block would hold with a fraction of c A. The pore force pushes the pair apart at
// those nodes (push_pore); the capacities bound the contact's tangential and opening impulses.
// Reads the particles, the shape-weight cache and the fields' mass; writes the slave fields'
// cohesion, tension and pore force. One pass in particle order: the same sums on any number of
// threads, and on any number of processes (own and ghost particles in one process's order).
template <int D>
void Simulation<D>::share_interface_loads() {
  constexpr double min_share = 0.5;
  const auto& P = particles_;
  for (BodyField<D>& F : fields_) { // once, before any interface adds to its slot
    std::fill(F.cohesion.begin(), F.cohesion.end(), 0.0);
    std::fill(F.tension.begin(), F.tension.end(), 0.0);
    std::fill(F.pore_force.begin(), F.pore_force.end(), 0.0);
  }
  for (std::size_t f = 0; f < setup_.interfaces.size(); ++f) {
    const InterfaceSpec& spec = setup_.interfaces[f];
    const int s = interface_slave(static_cast<int>(f));
    const int o = spec.a == s ? spec.b : spec.a;
    BodyField<D>& S = fields_[s];
    const BodyField<D>& O = fields_[o];
    if (S.slots == 0) continue;
    const bool pressure = setup_.pore_pressure && setup_.interface_pressure[f] && S.needs.pressure;
    const int slot = setup_.slot(s, static_cast<int>(f));
    const bool rigid_partner = setup_.bodies[o].rigid;
    const double rho_s = setup_.bodies[s].density, rho_o = setup_.bodies[o].density;
    // The partner's local index of each slave node the particle reaches (-1: no partner mass).
    constexpr int max_nodes = 27;
    std::int64_t node[max_nodes], partner[max_nodes];
    double weight[max_nodes];
    for (std::size_t p = P.body_begin[s]; p < P.body_begin[s + 1]; ++p) {
      if (P.iface[p] != static_cast<std::int32_t>(f) || P.field[p] != s) continue;
      const double A = P.iface_area[p];
      const double cA = P.cohesion[p] * A, tA = tensile_strength(spec, P.cohesion[p]) * A;
      const double pA = pressure && P.pore[p] >= 0 ? interface_pore_pressure(p) * A : 0.0;
      if (cA <= 0.0 && tA <= 0.0 && pA <= 0.0) continue;
      int n = 0;
      double shared = 0.0;
      for_each_node(S.box, shape_.weights[p], [&](std::int64_t I, double N_I, const Vec<D>&) {
        Index<D> g = S.box.node_coords(I);
        for (int d = 0; d < D; ++d)
          g[d] += S.offset[d];
        const std::int64_t j = O.local(g);
        // Where the pair meets: both hold at least min_slip_share of the node's volume (m / rho;
        // a rigid partner any), for at a fringe node a body's velocity is a force over a
        // round-off mass and the push would fling it (detail::min_slip_share).
        bool meets = N_I > 0.0 && j >= 0 && O.m[j] > 0.0;
        if (meets && !rigid_partner) {
          const double v_s = S.m[I] / rho_s, v_o = O.m[j] / rho_o;
          meets = std::min(v_s, v_o) >= detail::min_slip_share * (v_s + v_o);
        }
        node[n] = I, partner[n] = meets ? j : -1, weight[n] = N_I, ++n;
        if (meets) shared += N_I;
      });
      if (shared <= 0.0) continue; // the particle is not against its partner
      // Renormalised over the nodes that meet, but never by more than 1 / min_share: a particle
      // that barely reaches its partner's nodes would otherwise put its whole pore force on a
      // node where it has almost no mass (an acceleration p A / (shared m^p)).
      const double denominator = std::max(shared, min_share);
      const double c_share = cA / denominator, t_share = tA / denominator;
      const double force = pA / denominator;
      for (int k = 0; k < n; ++k) {
        if (partner[k] < 0) continue;
        const std::int64_t j = node[k] * S.slots + slot;
        if (cA > 0.0) S.cohesion[j] += weight[k] * c_share;
        if (tA > 0.0) S.tension[j] += weight[k] * t_share;
        if (pA > 0.0) S.pore_force[j] += weight[k] * force;
      }
    }
  }
}

// USF's force scatter, eq. 17-18. Reads the particles' stress, volume and mass and the
// shape-weight cache; writes each field's force.
template <int D>
void Simulation<D>::map_forces_to_nodes() {
  auto& P = particles_;
  shape_.require(steps_, particles_.size());
  scatter([&](std::uint32_t p, int b) {
    BodyField<D>& N = fields_[P.field[p]];
    const ShapeWeights<D>& sw = shape_.weights[p];
    const Mat<D> Vsigma = P.vol[p] * in_plane<D>(to_tensor(P.stress[p]));
    const Vec<D> mg = setup_.weight(P.m[p], b, P.x[p]);
    for_each_node(N.box, sw, [&](std::int64_t I, double N_I, const Vec<D>& dN_I) {
      N.f[I] += N_I * mg - Vsigma * dN_I;
    });
    if (N.needs.hydro) scatter_hydrostatic_load(N, sw, p);
  });
}

// A water particle below the level: its weight and the hydrostatic pressure's force on its
// nodes, N_I m g + V u grad N_I with u = rho_w |g| (level - z) (the force of the stress -u I).
template <int D>
void Simulation<D>::scatter_hydrostatic_load(BodyField<D>& N, const ShapeWeights<D>& sw,
                                             std::uint32_t p) {
  const auto& P = particles_;
  const WaterSetup<D>& w = setup_.water;
  const double depth = w.level - w.up.dot(P.x[p]);
  if (depth <= 0.0 || P.m[p] == 0.0) return; // above the level, or gone through an outflow
  const Vec<D> mg = P.m[p] * setup_.gravity;
  const double Vu = P.vol[p] * w.density * w.g * depth;
  for_each_node(N.box, sw, [&](std::int64_t I, double N_I, const Vec<D>& dN_I) {
    N.hydro[I] += N_I * mg + Vu * dN_I;
  });
}

// An interface particle's slip grows by the slip rate of the contact nodes around it that
// measure one (eq. 38-39: held nodes give the tangential relative velocity, a bond opened past
// its tensile capacity the whole relative velocity; apply_contact): their weighted mean, weights
// N_I times 4 s (1 - s), s the interface partner's share of the two bodies' volume, read from
// the nodes' slot of the particle's own interface. A particle with little weight on such nodes
// (less than min_slip_weight) takes a proportionally smaller rate, so one barely touching the
// other body gathers nothing. Its cohesion and friction follow their curves. Nothing degrades
// while settling.

#define TALUS_INSTANTIATE(D)                                                                       \
  template void Simulation<D>::map_particles_to_nodes(bool);                                       \
  template bool Simulation<D>::reaches_other_body(int, const ShapeWeights<D>&, int) const;         \
  template void Simulation<D>::map_forces_to_nodes();                                              \
  template void Simulation<D>::scatter_hydrostatic_load(BodyField<D>&, const ShapeWeights<D>&,     \
                                                        std::uint32_t);                            \
  template void Simulation<D>::share_interface_loads();                                            \
  template int Simulation<D>::interface_slave(int) const;
TALUS_INSTANTIATE(2)
TALUS_INSTANTIATE(3)

} // namespace talus
