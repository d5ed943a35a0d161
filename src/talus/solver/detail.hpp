// Helpers shared by the files of the solver's phases (not part of the library's interface).
#pragma once

#include "talus/core/nodes.hpp"
#include "talus/core/particles.hpp"
#include "talus/physics/contact.hpp"
#include "talus/solver/exchange.hpp"

#include <atomic>
#include <chrono>
#include <cstddef>
#include <type_traits>

namespace talus::detail {

using Clock = std::chrono::steady_clock;
inline double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Adds the wall time from its making to its end to `seconds`: timed(T.p2g), phase(); times the
// phase (the temporary ends with the full expression).
class PhaseTimer {
public:
  explicit PhaseTimer(double& seconds) : seconds_(seconds), t0_(Clock::now()) {}
  PhaseTimer(const PhaseTimer&) = delete;
  PhaseTimer& operator=(const PhaseTimer&) = delete;
  ~PhaseTimer() { seconds_ += seconds_since(t0_); }

private:
  double& seconds_;
  Clock::time_point t0_;
};
inline PhaseTimer timed(double& seconds) {
  return PhaseTimer(seconds);
}

// How the particles carry velocity between steps: their own under a FLIP/PIC blend, XPIC(m)'s
// S v*, or APIC's affine field v_p + C_p (x - x_p).
enum class Transfer { flip, xpic, apic };
// Where APIC's affine field is sampled for node I of field N: the node, or with B-splines its
// basis function's Greville point, which the open knots put 3/4 of a cell in for the second
// node from a face (talus/core/shape.hpp): with it sum_I N_I x_I = x_p holds to the faces, so
// p_I = sum_p N_I m_p (v_p + C_p (x_I - x_p)) keeps an affine field there too.
template <int D>
Vec<D> apic_node_position(const BodyField<D>& N, std::int64_t I, bool bspline) {
  const Index<D> i = N.box.node_coords(I);
  Vec<D> x = N.box.node_position(i);
  if (bspline)
    for (int d = 0; d < D; ++d) {
      const std::int64_t f = N.offset[d] + i[d] - N.frame_offset[d]; // in the frame's numbering
      if (N.face_hi[d] - N.face_lo[d] < 3) continue; // two cells: the middle node is its own
      if (f == N.face_lo[d] + 1) x[d] -= 0.25 * N.box.h;
      if (f == N.face_hi[d] - 1) x[d] += 0.25 * N.box.h;
    }
  return x;
}

// fn(std::integral_constant<Transfer, T>{}) for the setup's transfer T.
template <class Setup, class Fn>
void with_transfer(const Setup& s, Fn&& fn) {
  if (s.xpic > 0)
    fn(std::integral_constant<Transfer, Transfer::xpic>{});
  else if (s.apic)
    fn(std::integral_constant<Transfer, Transfer::apic>{});
  else
    fn(std::integral_constant<Transfer, Transfer::flip>{});
}

// Records the smallest bad particle index seen by any thread. With an exchange only this
// process's own particles count: a ghost near the share's edge reads nodes that lack particles
// only other processes hold, and is dropped after the step; its owner checks the real one.
inline void record_bad(std::atomic<std::size_t>& first, std::size_t p,
                       const Exchange* exchange = nullptr) {
  if (exchange && !exchange->is_own(p)) return;
  std::size_t cur = first.load();
  while (p < cur && !first.compare_exchange_weak(cur, p)) {
  }
}

// Particle p's position and velocity finite and the particle inside [lo, hi]: what the passes
// that move a particle check.
template <int D>
bool motion_ok(const Particles<D>& P, std::int64_t p, const Vec<D>& lo, const Vec<D>& hi) {
  return P.x[p].allFinite() && P.v[p].allFinite() && (P.x[p].array() >= lo.array()).all() &&
         (P.x[p].array() <= hi.array()).all();
}

// The body at a contact node that body k's pair is with: the heaviest other body there (its
// friction and bond apply at the node, and the node's force on k is booked to it).
template <int D>
int heaviest_other(const ContactNode<D>& node, int k) {
  int other = k == 0 ? 1 : 0;
  for (int j = 0; j < node.n; ++j)
    if (j != k && node.m[j] > node.m[other]) other = j;
  return other;
}

// Whether body k is the slave of its pair with `other` at a node: the side whose interface
// particles carry the bond (capacities, friction, degradation) and whose impulses the interface
// totals count. Against a rigid body, the deformable one (a rigid body's particles are never
// corrected and record no slip); otherwise the lighter (the lower rank, as for the normal).
// A body's rank: its mass, ties broken by body order.
inline double body_rank(double mass, int b) {
  return mass + 1e-9 * b;
}
inline bool slave_rule(bool rigid, double rank, bool other_rigid, double other_rank) {
  if (rigid != other_rigid) return !rigid;
  return rank < other_rank;
}
template <int D>
bool is_slave(const ContactNode<D>& node, int k, int other) {
  return slave_rule(node.rigid[k], node.rank[k], node.rigid[other], node.rank[other]);
}

// Interface slip (docs/formulation.md): a node measures it only where each of the two bodies has
// at least this share of their volume there; a particle with less weight than min_slip_weight on
// the nodes that measure it takes a proportionally smaller rate.
constexpr double min_slip_share = 0.05;
constexpr double min_slip_weight = 0.05;

} // namespace talus::detail
