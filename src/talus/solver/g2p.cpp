// G2P: the particles' velocity and position from their field (eq. 22-23), and MUSL's re-map of
// the updated particles' momentum back onto the nodes.
#include "talus/setup/boundary.hpp"
#include "talus/setup/interface.hpp"
#include "talus/solver/detail.hpp"
#include "talus/solver/scatter.hpp"
#include "talus/solver/simulation.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <numeric>
#include <variant>

namespace talus {

namespace {

// G2P for one particle, eq. 22-23: a rigid body's particle takes the body's velocity; any other
// the FLIP/PIC blend of its field's velocity change, v_p <- flip (v_p + v^{n+1} - v^n) +
// (1 - flip) v^{n+1} (interpolated), and moves with (v^n + v^{n+1}) / 2. Under XPIC(m) the
// particle carries S v* for v_p, against the contact-corrected v_c for v^n:
// v_p <- v^{n+1} + flip S (v* - v_c). Under APIC it takes v^{n+1} and its gradient,
// v_p <- sum N_I v_I^{n+1}, C_p <- sum v_I^{n+1} (grad N_I)^T.
template <detail::Transfer T, int D>
[[gnu::always_inline]] inline void
move_particle(Particles<D>& P, std::size_t p, const BodySetup<D>& body, const BodyField<D>& N,
              const ShapeWeights<D>& sw, double flip, double dt) {
  if (body.rigid) {
    P.v[p] = body.rigid_velocity;
    P.x[p] += dt * body.rigid_velocity;
    return;
  }
  Vec<D> v_old = Vec<D>::Zero(), v_new = Vec<D>::Zero(), delta = Vec<D>::Zero();
  Mat<D> C = Mat<D>::Zero();
  for_each_node(N.box, sw, [&](std::int64_t I, double N_I, const Vec<D>& dN_I) {
    v_old += N_I * N.v[I];
    v_new += N_I * N.v_new[I];
    if constexpr (T == detail::Transfer::xpic) delta += N_I * N.xpic_delta[I];
    if constexpr (T == detail::Transfer::apic) C += N.v_new[I] * dN_I.transpose();
  });
  if constexpr (T == detail::Transfer::xpic)
    P.v[p] = v_new + flip * delta;
  else if constexpr (T == detail::Transfer::apic)
    P.v[p] = v_new, P.C[p] = C;
  else
    P.v[p] = flip * (P.v[p] + v_new - v_old) + (1.0 - flip) * v_new;
  P.x[p] += 0.5 * dt * (v_old + v_new);
}

// Whether particle p, found outside the grid [lo, hi] or not finite, is fine once put back on
// the walls it crossed. A wall is impenetrable: a particle carried past one (a FLIP velocity's
// normal part, which the wall's nodes do not see) goes back onto it and loses its outward
// velocity; past a free face it has left the grid. A rigid body's particles follow its
// prescribed motion: one driven through a wall has left the grid too.
// A fluid particle past an outflow face has left the run: it keeps its place on the face and
// its volume, but no mass, speed or stress (it scatters nothing from then on; the body's mass in
// bodies.csv falls by what left).
template <int D>
bool put_back_on_walls(Particles<D>& P, std::size_t p, const BodySetup<D>& body, const Vec<D>& lo,
                       const Vec<D>& hi, const GridConditions<D>& faces) {
  if (body.rigid) return false;
  bool out = false;
  for (int d = 0; d < D; ++d) {
    const bool below = P.x[p][d]<lo[d], above = P.x[p][d]> hi[d];
    out = out || (below && faces.outflow[2 * d]) || (above && faces.outflow[2 * d + 1]);
    if (below && (faces.closed[2 * d] || faces.outflow[2 * d]))
      P.x[p][d] = lo[d], P.v[p][d] = std::max(P.v[p][d], 0.0);
    if (above && (faces.closed[2 * d + 1] || faces.outflow[2 * d + 1]))
      P.x[p][d] = hi[d], P.v[p][d] = std::min(P.v[p][d], 0.0);
  }
  if (out) {
    if (!body.fluid) return false; // only water flows out; a solid past the face left the grid
    P.m[p] = 0.0;
    P.v[p].setZero();
    P.vol[p] = P.vol0[p];
    P.F[p].setIdentity();
    P.stress[p].setZero();
  }
  return detail::motion_ok(P, static_cast<std::int64_t>(p), lo, hi);
}

} // namespace

// G2P, eq. 22-23. Reads v^n and v^{n+1} of each particle's field and the shape-weight cache;
// writes the particles' velocity (the FLIP/PIC blend of the grid change, XPIC's or APIC's, with
// APIC's C) and position (moved
// with (v^n + v^{n+1}) / 2, exact for a constant acceleration); a rigid body's particles take
// its prescribed velocity. A held field's particles do not move.
template <int D>
void Simulation<D>::update_particles(double dt) {
  auto& P = particles_;
  const double flip = setup_.flip;
  std::atomic<std::size_t> gone{StepCheck::no_particle};
  const Vec<D> lo = grid_.origin, hi = grid_.upper();
  const GridConditions<D>& faces = setup_.conditions;
  for (int b = 0; b < num_bodies(); ++b) {
    if (field_held_[b]) continue;
    shape_.require(steps_, particles_.size());
    const BodySetup<D>& body = setup_.bodies[b];
    const std::int64_t begin = P.body_begin[b], end = P.body_begin[b + 1];
    auto move = [&](auto transfer) {
#pragma omp parallel for schedule(static)
      for (std::int64_t p = begin; p < end; ++p) {
        if (body.fluid && P.m[p] == 0.0) continue; // gone through an outflow face: stays there
        move_particle<transfer()>(P, p, body, fields_[P.field[p]], shape_[p], flip, dt);
        if (!detail::motion_ok(P, p, lo, hi) && !put_back_on_walls(P, p, body, lo, hi, faces))
          detail::record_bad(gone, static_cast<std::size_t>(p), exchange_);
      }
    };
    detail::with_transfer(setup_, move);
  }
  check_.bad_particle = std::min(check_.bad_particle, gone.load());
}

// MUSL's middle (eq. 22-23, then the re-map). Reads v and v_new of each particle's field;
// writes the particles' velocity and position as update_particles does, the fields' momentum p
// re-mapped from the new particle velocities (under APIC their affine fields about x_p^n), and
// v_remap = p / m. One coloured pass does the
// gather and the scatter; the stress pass that follows reads the start-of-step weights.
template <int D>
void Simulation<D>::update_particles_and_remap(double dt) {
  auto& P = particles_;
  const double flip = setup_.flip;
  shape_.require(steps_, particles_.size());
  for (int b = 0; b < num_bodies(); ++b) // a held field's velocities stand (grid_update.cpp)
    if (!field_held_[b]) std::fill(fields_[b].p.begin(), fields_[b].p.end(), Vec<D>::Zero());
  std::atomic<std::size_t> gone{StepCheck::no_particle};
  const Vec<D> lo = grid_.origin, hi = grid_.upper();
  const GridConditions<D>& faces = setup_.conditions;
  const bool bspline = setup_.shape == ShapeKind::bspline;
  auto move_and_remap = [&](auto transfer) {
    scatter([&](std::uint32_t p, int b) {
      BodyField<D>& N = fields_[P.field[p]];
      const ShapeWeights<D>& sw = shape_.weights[p];
      if (setup_.bodies[b].fluid && P.m[p] == 0.0) return; // gone through an outflow face
      [[maybe_unused]] const Vec<D> x_n = P.x[p];          // where the weights were taken
      move_particle<transfer()>(P, p, setup_.bodies[b], N, sw, flip, dt);
      if (!detail::motion_ok(P, p, lo, hi) &&
          !put_back_on_walls(P, p, setup_.bodies[b], lo, hi, faces))
        detail::record_bad(gone, p, exchange_);
      const Vec<D> mv_p = P.m[p] * P.v[p];
      if constexpr (transfer() ==
                    detail::Transfer::apic) { // p_I += N_I m_p (v_p + C_p (x_I - x_p))
        const Mat<D> mC = P.m[p] * P.C[p];
        for_each_node(N.box, sw, [&](std::int64_t I, double N_I, const Vec<D>&) {
          N.p[I] += N_I * (mv_p + mC * (detail::apic_node_position(N, I, bspline) - x_n));
        });
      } else {
        for_each_node(N.box, sw,
                      [&](std::int64_t I, double N_I, const Vec<D>&) { N.p[I] += N_I * mv_p; });
      }
    });
  };
  detail::with_transfer(setup_, move_and_remap);
  check_.bad_particle = std::min(check_.bad_particle, gone.load());
  for (int b = 0; b < num_bodies(); ++b) {
    if (field_held_[b]) continue;
    BodyField<D>& N = fields_[b];
    const std::int64_t n = static_cast<std::int64_t>(N.size());
#pragma omp parallel for schedule(static)
    for (std::int64_t i = 0; i < n; ++i)
      N.v_remap[i] = N.m[i] > 0.0 ? Vec<D>(N.p[i] / N.m[i]) : Vec<D>::Zero();
  }
}

// XPIC(m) (Hammerquist & Nairn 2017): the particles carry S v*, the part of their velocity the
// grid represents, instead of their own: v* = sum_{k=0}^{m-1} (I - S^+ S)^k v_c, the m-term series
// of (S^+ S)^{-1} S^+ v_p, so m = 1 is PIC and m -> infinity FLIP without the velocities the grid
// cannot represent. v_c is the start-of-step velocity with contact and the velocity conditions
// (Nairn et al. 2018 correct the extrapolated field too: without it the series sharpens the
// contact layer's approach, which the contact then takes away again). Each term is one gather
// and scatter, w <- w - (sum_p N m_p (S w)_p) / M; S^+ S keeps a field's momentum, so the terms
// carry none and v_p's momentum is v^{n+1}'s. A rigid body's field takes no terms (its v_c is
// its velocity).
template <int D>
void Simulation<D>::extrapolate_xpic_velocity(double dt) {
  using F = BodyField<D>;
  auto& P = particles_;
  const int B = num_bodies();
  shape_.require(steps_, particles_.size());
  auto deformable = [&](int b) { return !setup_.bodies[b].rigid && !field_held_[b]; };
  for (int b = 0; b < B; ++b)
    if (!field_held_[b]) fields_[b].xpic_w = fields_[b].v;
  if (B > 1) apply_contact(&F::xpic_w, dt, ContactPass::carried);
  apply_velocity_conditions(&F::xpic_w);
  for (int b = 0; b < B; ++b)
    if (deformable(b))
      std::fill(fields_[b].xpic_delta.begin(), fields_[b].xpic_delta.end(), Vec<D>::Zero());
  for (int k = 1; k < setup_.xpic; ++k) {
    for (int b = 0; b < B; ++b)
      if (deformable(b)) std::fill(fields_[b].p.begin(), fields_[b].p.end(), Vec<D>::Zero());
    scatter([&](std::uint32_t p, int b) {
      if (setup_.bodies[b].rigid || !deformable(P.field[p])) return; // an orphan's host too
      BodyField<D>& N = fields_[P.field[p]];
      const ShapeWeights<D>& sw = shape_.weights[p];
      Vec<D> w_p = Vec<D>::Zero();
      for_each_node(N.box, sw,
                    [&](std::int64_t I, double N_I, const Vec<D>&) { w_p += N_I * N.xpic_w[I]; });
      const Vec<D> mw_p = P.m[p] * w_p;
      for_each_node(N.box, sw,
                    [&](std::int64_t I, double N_I, const Vec<D>&) { N.p[I] += N_I * mw_p; });
    });
    for (int b = 0; b < B; ++b) {
      if (!deformable(b)) continue;
      BodyField<D>& N = fields_[b];
      const std::int64_t n = static_cast<std::int64_t>(N.size());
#pragma omp parallel for schedule(static)
      for (std::int64_t i = 0; i < n; ++i) {
        N.xpic_w[i] = N.m[i] > 0.0 ? Vec<D>(N.xpic_w[i] - N.p[i] / N.m[i]) : Vec<D>::Zero();
        N.xpic_delta[i] += N.xpic_w[i];
      }
    }
  }
}

#define TALUS_INSTANTIATE(D)                                                                       \
  template void Simulation<D>::update_particles(double);                                           \
  template void Simulation<D>::extrapolate_xpic_velocity(double);                                  \
  template void Simulation<D>::update_particles_and_remap(double);
TALUS_INSTANTIATE(2)
TALUS_INSTANTIATE(3)

} // namespace talus
