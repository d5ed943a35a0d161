// The particle-grid transfers: the particle order and slab bins that make the scatter
// deterministic, the fields' boxes, P2G (eq. 14-18, 30, 37), G2P (eq. 22-23), MUSL's re-map and
// the stress update (eq. 24-28).
#include "talus/interface.hpp"
#include "talus/solver.hpp"
#include "talus/solver/detail.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <numeric>
#include <variant>

namespace talus {

namespace {

// a[i] <- a[order[i]] in place, one cycle of the permutation at a time: no copy of the array
// (a copy of the largest, the stress, was the peak of the memory), one byte per element of marks.
template <class T>
void permute(std::vector<T>& a, const std::vector<std::uint32_t>& order, std::vector<char>& done) {
  done.assign(a.size(), 0);
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (done[i]) continue;
    T first = a[i];
    std::size_t j = i;
    while (true) {
      done[j] = 1;
      const std::size_t k = order[j];
      if (k == i) {
        a[j] = first;
        break;
      }
      a[j] = a[k];
      j = k;
    }
  }
}

// G2P for one particle, eq. 22-23: a rigid body's particle takes the body's velocity; any other
// the FLIP/PIC blend of its field's velocity change, v_p <- flip (v_p + v^{n+1} - v^n) +
// (1 - flip) v^{n+1} (interpolated), and moves with (v^n + v^{n+1}) / 2.
template <int D>
[[gnu::always_inline]] inline void
move_particle(Particles<D>& P, std::size_t p, const BodySetup<D>& body, const BodyField<D>& N,
              const ShapeWeights<D>& sw, double flip, double dt) {
  if (body.rigid) {
    P.v[p] = body.rigid_velocity;
    P.x[p] += dt * body.rigid_velocity;
    return;
  }
  Vec<D> v_old = Vec<D>::Zero(), v_new = Vec<D>::Zero();
  for_each_node(N.box, sw, [&](std::int64_t I, double N_I, const Vec<D>&) {
    v_old += N_I * N.v[I];
    v_new += N_I * N.v_new[I];
  });
  P.v[p] = flip * (P.v[p] + v_new - v_old) + (1.0 - flip) * v_new;
  P.x[p] += 0.5 * dt * (v_old + v_new);
}

} // namespace

// Reads the positions; writes the particle order (every array permuted, by cell within each
// body) and index_of_id_. Invalidates the shape-weight cache.
template <int D>
void Simulation<D>::sort_particles_by_cell() {
  auto& P = particles_;
  invalidate_shape(); // shape_ is indexed by particle
  std::vector<std::uint32_t> order(P.size());
  std::iota(order.begin(), order.end(), 0u);
  std::vector<std::int64_t> key(P.size());
  for (std::size_t p = 0; p < P.size(); ++p)
    key[p] = grid_.cell_index(grid_.cell_of(P.x[p]));
  for (int b = 0; b < P.num_bodies(); ++b)
    std::stable_sort(order.begin() + P.body_begin[b], order.begin() + P.body_begin[b + 1],
                     [&](std::uint32_t i, std::uint32_t j) { return key[i] < key[j]; });
  std::vector<char> done;
  P.for_each_array([&](auto& a) { permute(a, order, done); });
  index_of_id_.resize(std::max(index_of_id_.size(), P.size())); // a process's share: ids of all
  for (std::size_t p = 0; p < P.size(); ++p)
    index_of_id_[P.id[p]] = static_cast<std::uint32_t>(p);
}

// Reads the positions; writes each particle's slab bin (slabs of slab_width_ cells along x, by
// body) and the bins' index, in particle order; a held field's particles get no bin.
template <int D>
void Simulation<D>::bin_particles_by_slab() {
  const auto& P = particles_;
  const int B = P.num_bodies();
  const std::size_t n = P.size();
  particle_bin_.resize(n);
  bin_index_.resize(n);
  std::fill(bin_offset_.begin(), bin_offset_.end(), 0);
  const double inv_h = 1.0 / grid_.h;
  constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();
  for (int b = 0; b < B; ++b) {
    const std::int64_t begin = P.body_begin[b], end = P.body_begin[b + 1];
    if (field_held_[b]) { // its field stands: no scatter visits its particles
      std::fill(particle_bin_.begin() + begin, particle_bin_.begin() + end, none);
      continue;
    }
#pragma omp parallel for schedule(static)
    for (std::int64_t p = begin; p < end; ++p) {
      const double xi = (P.x[p][0] - grid_.origin[0]) * inv_h;
      const std::int64_t s =
          std::clamp<std::int64_t>(static_cast<std::int64_t>(xi) / slab_width_, 0, num_slabs_ - 1);
      particle_bin_[p] = static_cast<std::uint32_t>(s * B + b);
    }
  }
  for (std::size_t p = 0; p < n; ++p)
    if (particle_bin_[p] != none) ++bin_offset_[particle_bin_[p] + 1];
  std::partial_sum(bin_offset_.begin(), bin_offset_.end(), bin_offset_.begin());
  std::vector<std::size_t> fill(bin_offset_.begin(), bin_offset_.end() - 1);
  for (std::size_t p = 0; p < n; ++p)
    if (particle_bin_[p] != none)
      bin_index_[fill[particle_bin_[p]]++] = static_cast<std::uint32_t>(p);
}

template <int D>
template <class F>
void Simulation<D>::scatter(F&& f) {
  const int B = particles_.num_bodies();
  for (int colour = 0; colour < 2; ++colour) {
#pragma omp parallel for schedule(dynamic, 1)
    for (std::int64_t s = colour; s < num_slabs_; s += 2)
      for (int b = 0; b < B; ++b)
        for (std::size_t k = bin_offset_[s * B + b]; k < bin_offset_[s * B + b + 1]; ++k)
          f(bin_index_[k], b);
  }
}

// Reads the positions and the particles' fields; writes each body's field box and clears it.
// Each body's field covers the nodes its particles and the orphans it hosts reach (GIMP: one
// cell beyond the particle's cell on each side), refitted and cleared every step.
template <int D>
void Simulation<D>::fit_body_fields() {
  const auto& P = particles_;
  const int B = P.num_bodies();
  std::vector<double>& bounds = box_bounds_; // B x D minima, then B x D maxima
  bounds.resize(2 * B * D);
  double* lo_ = bounds.data();
  double* hi_ = bounds.data() + B * D;
  for (int b = 0; b < B; ++b) {
    if (field_held_[b]) continue;
    double l[D], h[D];
    std::fill_n(l, D, inf), std::fill_n(h, D, -inf);
    const std::int64_t begin = P.body_begin[b], end = P.body_begin[b + 1];
#pragma omp parallel for schedule(static) reduction(min : l[:D]) reduction(max : h[:D])
    for (std::int64_t p = begin; p < end; ++p)
      for (int d = 0; d < D; ++d)
        l[d] = std::min(l[d], P.x[p][d]), h[d] = std::max(h[d], P.x[p][d]);
    std::copy_n(l, D, lo_ + b * D), std::copy_n(h, D, hi_ + b * D);
  }
  // The orphans (a handful, if any) stretch their hosts' boxes.
  for (int b = 0; b < B; ++b) {
    const std::int64_t begin = P.body_begin[b], end = P.body_begin[b + 1];
#pragma omp parallel for schedule(static) reduction(min : lo_[:B * D]) reduction(max : hi_[:B * D])
    for (std::int64_t p = begin; p < end; ++p)
      if (const int f = P.field[p]; f != b)
        for (int d = 0; d < D; ++d) {
          lo_[f * D + d] = std::min(lo_[f * D + d], P.x[p][d]);
          hi_[f * D + d] = std::max(hi_[f * D + d], P.x[p][d]);
        }
  }
  // The nodes [cell(lo) - 1, cell(hi) + 3) hold the support of every point in [lo, hi].
  auto node_range = [&](const double* lo, const double* hi, Index<D>& first, Index<D>& last) {
    first = grid_.cell_of(Eigen::Map<const Vec<D>>(lo));
    last = grid_.cell_of(Eigen::Map<const Vec<D>>(hi));
    for (int d = 0; d < D; ++d) {
      first[d] = std::clamp<std::int64_t>(first[d] - 1, 0, grid_.nodes[d]);
      last[d] = std::clamp<std::int64_t>(last[d] + 3, 0, grid_.nodes[d]);
    }
  };
  // On several processes each frame spans every process's particles: the frames, and with them
  // the shape weights (relative to the frame) and the contact rows, are one process's. Each
  // process stores the part of the frame its own and ghost particles reach.
  std::vector<double>& mine = box_bounds_local_;
  mine.assign(bounds.begin(), bounds.end());
  if (exchange_) exchange_->min_max(lo_, hi_, B * D);
  for (int b = 0; b < B; ++b) {
    if (field_held_[b]) continue; // its box and sums stand
    Index<D> frame_first, frame_last, first, last;
    node_range(lo_ + b * D, hi_ + b * D, frame_first, frame_last);
    const double *l = mine.data() + b * D, *h = mine.data() + (B + b) * D;
    if (!exchange_)
      first = frame_first, last = frame_last;
    else if (l[0] <= h[0]) // the process holds particles of the body
      node_range(l, h, first, last);
    else
      first = last = frame_first; // none: one empty node
    fields_[b].fit(grid_, frame_first, frame_last, first, last);
  }
}

// P2G, eq. 14-18, 30 and 37. Reads the particles; writes the shape-weight cache and each field's
// mass, momentum, mass gradient and mass-weighted position (near other bodies), bond capacities,
// and with `with_forces` the internal and external force. The mass gradient and position serve
// contact only; a single body skips them.
template <int D>
void Simulation<D>::map_particles_to_nodes(bool with_forces) {
  const bool contact = fields_.empty() || fields_[0].needs.contact;
  if (with_forces)
    contact ? scatter_particles<true, true>() : scatter_particles<true, false>();
  else
    contact ? scatter_particles<false, true>() : scatter_particles<false, false>();
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
template <bool with_forces, bool with_contact>
void Simulation<D>::scatter_particles() {
  auto& P = particles_;
  const ShapeKind kind = setup_.shape;
  shape_.resize(P.size());
  shape_step_ = steps_;
  scatter([&](std::uint32_t p, int b) {
    const int f = P.field[p]; // b, or the host of an orphan
    BodyField<D>& N = fields_[f];
    ShapeWeights<D>& sw = shape_[p];
    N.weights(sw, kind, setup_.bodies[b].gimp, P.x[p]);
    const double m_p = P.m[p];
    const Vec<D> mv_p = m_p * P.v[p], mx_p = m_p * P.x[p];
    const Mat<D> Vsigma = P.vol[p] * in_plane<D>(to_tensor(P.stress[p]));
    const Vec<D> mg = setup_.weight(m_p, b, P.x[p]);
    auto map = [&]<bool contact>() {
      for_each_node(N.box, sw, [&](std::int64_t I, double N_I, const Vec<D>& dN_I) {
        N.m[I] += N_I * m_p;
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
    if (with_contact &&
        (setup_.bodies[b].fixed || reaches_other_body(f, sw, setup_.normal_smoothing)))
      map.template operator()<true>();
    else
      map.template operator()<false>();
    if (P.iface[p] >= 0 && f == b) { // eq. 37 (an orphan is not on its interface any more): the
                                     // interface particle's share of the node's capacity
      const InterfaceSpec& spec = setup_.interfaces[P.iface[p]];
      const double A = P.iface_area[p];
      const double cA = P.cohesion[p] * A, tA = tensile_strength(spec, P.cohesion[p]) * A;
      const double muA = P.friction[p] * A;
      const int S = N.slots, slot = setup_.slot(b, P.iface[p]);
      for_each_node(N.box, sw, [&](std::int64_t I, double N_I, const Vec<D>&) {
        const std::int64_t j = I * S + slot;
        N.cohesion[j] += N_I * cA;
        N.tension[j] += N_I * tA;
        N.friction_area[j] += N_I * muA;
        N.area[j] += N_I * A;
      });
      if (P.pore[p] >= 0) { // sum N A^p min(p / sigma_n, 1): its mean at the node
        const double ratio = pore_ratio(p);
        for_each_node(N.box, sw, [&](std::int64_t I, double N_I, const Vec<D>&) {
          N.pore_ratio[I * S + slot] += N_I * A * ratio;
        });
      }
    }
  });
}

// USF's force scatter, eq. 17-18. Reads the particles' stress, volume and mass and the
// shape-weight cache; writes each field's force.
template <int D>
void Simulation<D>::map_forces_to_nodes() {
  auto& P = particles_;
  assert_shape_current();
  scatter([&](std::uint32_t p, int b) {
    BodyField<D>& N = fields_[P.field[p]];
    const ShapeWeights<D>& sw = shape_[p];
    const Mat<D> Vsigma = P.vol[p] * in_plane<D>(to_tensor(P.stress[p]));
    const Vec<D> mg = setup_.weight(P.m[p], b, P.x[p]);
    for_each_node(N.box, sw, [&](std::int64_t I, double N_I, const Vec<D>& dN_I) {
      N.f[I] += N_I * mg - Vsigma * dN_I;
    });
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

// G2P, eq. 22-23. Reads v^n and v^{n+1} of each particle's field and the shape-weight cache;
// writes the particles' velocity (the FLIP/PIC blend of the grid change) and position (moved
// with (v^n + v^{n+1}) / 2, exact for a constant acceleration); a rigid body's particles take
// its prescribed velocity. A held field's particles do not move.
template <int D>
void Simulation<D>::update_particles(double dt) {
  auto& P = particles_;
  const double flip = setup_.flip;
  std::atomic<std::size_t> gone{no_particle};
  const Vec<D> lo = grid_.origin, hi = grid_.upper();
  for (int b = 0; b < num_bodies(); ++b) {
    if (field_held_[b]) continue;
    assert_shape_current();
    const BodySetup<D>& body = setup_.bodies[b];
    const std::int64_t begin = P.body_begin[b], end = P.body_begin[b + 1];
#pragma omp parallel for schedule(static)
    for (std::int64_t p = begin; p < end; ++p) {
      move_particle(P, p, body, fields_[P.field[p]], shape_[p], flip, dt);
      if (!motion_ok(p, lo, hi)) detail::record_bad(gone, static_cast<std::size_t>(p), exchange_);
    }
  }
  bad_particle_ = std::min(bad_particle_, gone.load());
}

// MUSL's middle (eq. 22-23, then the re-map). Reads v and v_new of each particle's field;
// writes the particles' velocity and position as update_particles does, the fields' momentum p
// re-mapped from the new particle velocities, and v_remap = p / m. One coloured pass does the
// gather and the scatter; the stress pass that follows reads the start-of-step weights.
template <int D>
void Simulation<D>::update_particles_and_remap(double dt) {
  auto& P = particles_;
  const double flip = setup_.flip;
  assert_shape_current();
  for (auto& N : fields_)
    std::fill(N.p.begin(), N.p.end(), Vec<D>::Zero());
  std::atomic<std::size_t> gone{no_particle};
  const Vec<D> lo = grid_.origin, hi = grid_.upper();
  scatter([&](std::uint32_t p, int b) {
    BodyField<D>& N = fields_[P.field[p]];
    const ShapeWeights<D>& sw = shape_[p];
    move_particle(P, p, setup_.bodies[b], N, sw, flip, dt);
    if (!motion_ok(p, lo, hi)) detail::record_bad(gone, p, exchange_);
    const Vec<D> mv_p = P.m[p] * P.v[p];
    for_each_node(N.box, sw,
                  [&](std::int64_t I, double N_I, const Vec<D>&) { N.p[I] += N_I * mv_p; });
  });
  bad_particle_ = std::min(bad_particle_, gone.load());
  for (int b = 0; b < num_bodies(); ++b) {
    BodyField<D>& N = fields_[b];
    const std::int64_t n = static_cast<std::int64_t>(N.size());
#pragma omp parallel for schedule(static)
    for (std::int64_t i = 0; i < n; ++i)
      N.v_remap[i] = N.m[i] > 0.0 ? Vec<D>(N.p[i] / N.m[i]) : Vec<D>::Zero();
  }
}

// Eq. 24-28. Reads the field array `velocity` and the shape-weight cache; writes every
// deformable particle's F, volume, stress and plastic strain, and the bodies' stress work.
template <int D>
void Simulation<D>::update_stress(std::vector<Vec<D>> BodyField<D>::*velocity, double dt) {
  for (int b = 0; b < num_bodies(); ++b) {
    if (setup_.bodies[b].rigid) continue; // prescribed motion: no stress
    std::visit([&](const auto& model) { update_body_stress(b, velocity, dt, model); },
               setup_.bodies[b].material.model);
  }
}

template <int D>
template <class Model>
void Simulation<D>::update_body_stress(int b, std::vector<Vec<D>> BodyField<D>::*velocity,
                                       double dt, const Model& model) {
  auto& P = particles_;
  assert_shape_current();
  const double max_J = setup_.bodies[b].material.max_volume_ratio;
  const std::int64_t begin = P.body_begin[b], end = P.body_begin[b + 1];
  std::atomic<std::size_t> bad{P.size()}, gone{no_particle};
  // Particles go in fixed chunks so that the stress work sums in an order that does not depend
  // on the thread count (chunk sums, then the chunks in order).
  const std::int64_t chunks = (end - begin + work_chunk - 1) / work_chunk;
  if (static_cast<std::int64_t>(chunk_work_.size()) < chunks) chunk_work_.resize(chunks);
  // On several processes the chunks are of global indices: each particle's work goes to the
  // exchange, which forms the chunk sums one process would.
  double* particle_work = nullptr;
  if (exchange_) particle_work_.resize(P.size()), particle_work = particle_work_.data();
#pragma omp parallel for schedule(dynamic, 1)
  for (std::int64_t c = 0; c < chunks; ++c) {
    double work = 0.0;
    for (std::int64_t p = begin + c * work_chunk; p < std::min(end, begin + (c + 1) * work_chunk);
         ++p) {
      const ShapeWeights<D>& sw = shape_[p];
      const BodyField<D>& N = fields_[P.field[p]];
      const Vec<D>* rate = (N.*velocity).data();
      // L = sum_I v_I (grad N_I)^T
      Mat<D> L = Mat<D>::Zero();
      for_each_node(N.box, sw, [&](std::int64_t I, double, const Vec<D>& dN_I) {
        L += rate[I] * dN_I.transpose();
      });
      // F^{n+1} = (I + L dt) F^n, V = V_0 det F (eq. 24-25).
      P.F[p] = (Mat<D>::Identity() + L * dt) * P.F[p];
      double J = P.F[p].determinant();
      if (!(J > 0.0)) detail::record_bad(bad, static_cast<std::size_t>(p), exchange_);
      if (J > max_J) { // past the volume limit the opening is separation, not the particle's
        P.F[p] *= std::pow(max_J / J, 1.0 / D);
        J = max_J;
      }
      const double vol_old = P.vol[p];
      P.vol[p] = P.vol0[p] * J;
      // The Jaumann rate with D = sym L and W = skew L, then the return (eq. 26-28).
      const Mat3 L3 = embed<D>(L);
      const Mat3 D3 = 0.5 * (L3 + L3.transpose());
      const Voigt sigma_old = P.stress[p];
      talus::update_stress(model, P.stress[p], P.eps_p[p], D3, 0.5 * (L3 - L3.transpose()), dt);
      // Stress work over the step, midpoint rule: (V sigma) : D dt.
      const Voigt s = 0.5 * (vol_old * sigma_old + P.vol[p] * P.stress[p]);
      const double w = dt * (s[0] * D3(0, 0) + s[1] * D3(1, 1) + s[2] * D3(2, 2) +
                             2.0 * (s[3] * D3(0, 1) + s[4] * D3(1, 2) + s[5] * D3(0, 2)));
      work += w;
      if (particle_work) particle_work[p] = w;
      if (!P.stress[p].allFinite())
        detail::record_bad(gone, static_cast<std::size_t>(p), exchange_);
    }
    chunk_work_[c] = work;
  }
  if (exchange_) {
    exchange_->chunk_sums(b, begin, end, particle_work, work_chunk, chunk_work_global_);
    for (const double w : chunk_work_global_)
      internal_work_[b] += w;
  } else {
    for (std::int64_t c = 0; c < chunks; ++c)
      internal_work_[b] += chunk_work_[c];
  }
  bad_particle_ = std::min(bad_particle_, gone.load());
  // Reported at the step's end, so that every process reaches the step's collective points.
  if (const std::size_t p = bad.load(); p != P.size() && pending_failure_.empty())
    pending_failure_ = fmt::format(
        "step {}, time {:.6g} s: body '{}', particle {} (id {}) at ({}): det F = {:.3g} <= 0 "
        "(the particle turned inside out; reduce the time step or check the case)",
        steps_, time_, setup_.bodies[b].name, one_process_index(p), P.id[p],
        fmt::join(P.x[p].data(), P.x[p].data() + D, ", "), P.F[p].determinant());
}

#define TALUS_INSTANTIATE(D)                                                                       \
  template void Simulation<D>::sort_particles_by_cell();                                           \
  template void Simulation<D>::bin_particles_by_slab();                                            \
  template void Simulation<D>::fit_body_fields();                                                  \
  template void Simulation<D>::map_particles_to_nodes(bool);                                       \
  template bool Simulation<D>::reaches_other_body(int, const ShapeWeights<D>&, int) const;         \
  template void Simulation<D>::map_forces_to_nodes();                                              \
  template void Simulation<D>::update_particles(double);                                           \
  template void Simulation<D>::update_particles_and_remap(double);                                 \
  template void Simulation<D>::update_stress(std::vector<Vec<D>> BodyField<D>::*, double);
TALUS_INSTANTIATE(2)
TALUS_INSTANTIATE(3)

} // namespace talus
