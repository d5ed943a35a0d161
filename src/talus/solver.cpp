#include "talus/solver.hpp"

#include "talus/case/geometry.hpp"
#include "talus/initial_state.hpp"
#include "talus/interface.hpp"
#include "talus/shape.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <numeric>
#include <variant>

namespace talus {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

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

// Interface slip (docs/formulation.md): a node measures it only where each of the two bodies has
// at least this share of their volume there; a particle with less weight than min_slip_weight on
// the nodes that measure it takes a proportionally smaller rate.
constexpr double min_slip_share = 0.05;
constexpr double min_slip_weight = 0.05;

// Whether body k is the slave of its pair with `other` at a node: the side whose interface
// particles carry the bond (capacities, friction, degradation) and whose impulses the interface
// totals count. Against a rigid body, the deformable one (a rigid body's particles are never
// corrected and record no slip, so a bond carried by a lighter rigid body never degraded and
// its totals read zero); otherwise the lighter (the lower rank, as for the normal).
template <int D>
bool is_slave(const ContactNode<D>& node, int k, int other) {
  if (node.rigid[k] != node.rigid[other]) return !node.rigid[k];
  return node.rank[k] < node.rank[other];
}

// A body's mass gradient at node g smoothed over the nodes within `radius` cells of it, with
// weights prod_d (radius + 1 - |o_d|) (contact.normal_smoothing, docs/formulation.md). The body's
// box holds the gradient sums at every node within `radius` of another body's box (the scatter
// maps them there), so every node read here is complete.
template <int D>
Vec<D> smoothed_gradient(const BodyField<D>& N, const Index<D>& g, int radius) {
  Vec<D> sum = Vec<D>::Zero();
  Index<D> o;
  o.fill(-radius);
  while (true) {
    Index<D> j;
    double w = 1.0;
    for (int d = 0; d < D; ++d)
      j[d] = g[d] + o[d], w *= radius + 1 - std::abs(o[d]);
    if (const std::int64_t i = N.local(j); i >= 0) sum += w * N.grad_m[i];
    int d = D - 1;
    while (d >= 0 && ++o[d] > radius)
      o[d] = -radius, --d;
    if (d < 0) break;
  }
  return sum;
}

// Records the smallest bad particle index seen by any thread.
void record_bad(std::atomic<std::size_t>& first, std::size_t p) {
  std::size_t cur = first.load();
  while (p < cur && !first.compare_exchange_weak(cur, p)) {
  }
}

} // namespace

template <int D>
Simulation<D>::Simulation(const Case& c) : case_data_(c) {
  Vec<D> origin, extent;
  for (int d = 0; d < D; ++d)
    origin[d] = c.grid.origin[d], extent[d] = c.grid.extent[d];
  grid_ = Grid<D>(origin, extent, c.grid.cell_size);
  particles_ = fill_particles<D>(c);
  check_body_overlaps<D>(c, particles_);
  if (c.initial_state.method == InitialState::Method::k0) apply_k0_stress<D>(c, particles_);
  index_of_id_.resize(particles_.size());
  for (std::size_t p = 0; p < particles_.size(); ++p)
    index_of_id_[particles_.id[p]] = static_cast<std::uint32_t>(p);
  warnings_ = mark_interface_particles<D>(c, particles_);
  const int B = particles_.num_bodies();
  fields_.resize(B);
  body_mass_.assign(B, 0.0);
  for (int b = 0; b < B; ++b)
    for (std::size_t p = particles_.body_begin[b]; p < particles_.body_begin[b + 1]; ++p)
      body_mass_[b] += particles_.m[p];
  for (const BodySpec& b : c.bodies) {
    body_density_.push_back(c.materials[b.material].density());
    body_material_.push_back(c.materials[b.material]);
    body_material_.back().prepare();
    body_gimp_.emplace_back(c.grid.cell_size, 0.5 * c.grid.cell_size / b.particles_per_cell);
    Vec<D> v;
    for (int d = 0; d < D; ++d)
      v[d] = b.velocity[d];
    rigid_velocity_.push_back(v);
  }
  fixed_field_ready_.assign(B, 0);
  pair_friction_.assign(B * B, c.contact.friction);
  pair_interface_.assign(B * B, -1);
  // An interface pair slides with its interface's friction where no interface particle is
  // (bodies that meet only later), unless a [[contact]] entry names the pair (applied below).
  for (std::size_t f = 0; f < c.interfaces.size(); ++f) {
    const int a = c.interfaces[f].a, b = c.interfaces[f].b;
    pair_interface_[a * B + b] = pair_interface_[b * B + a] = static_cast<int>(f);
    pair_friction_[a * B + b] = pair_friction_[b * B + a] = c.interfaces[f].friction.initial;
  }
  interface_force_.assign(c.interfaces.size(), InterfaceForce{});
  interface_impulse_.assign(c.interfaces.size(), InterfaceForce{});
  for (const ContactPair& pair : c.contact.pairs)
    pair_friction_[pair.a * B + pair.b] = pair_friction_[pair.b * B + pair.a] = pair.friction;
  const int F = static_cast<int>(c.interfaces.size());
  interface_slot_.assign(B * F, -1);
  for (int f = 0; f < F; ++f)
    for (const int b : {c.interfaces[f].a, c.interfaces[f].b})
      interface_slot_[b * F + f] = fields_[b].slots++;
  for (BodyField<D>& N : fields_) {
    N.needs.contact = B > 1;
    N.needs.interfaces = N.slots > 0;
    N.needs.remap = c.simulation.scheme == Scheme::musl;
  }
  normal_cache_.resize(B);
  for (int b = 0; b < B; ++b)
    if (c.bodies[b].geometric_normal)
      normal_cache_[b].assign(static_cast<std::size_t>(grid_.num_nodes()),
                              Vec<D>::Constant(std::numeric_limits<double>::quiet_NaN()));
  contact_law_.gap_cutoff = c.contact.gap_cutoff;
  contact_law_.cell_size = c.grid.cell_size;
  contact_force_.assign(B * B, Vec<D>::Zero());
  contact_work_.assign(B, 0.0);
  internal_work_.assign(B, 0.0);
  contact_impulse_.assign(B * B, Vec<D>::Zero());
  conditions_ = build_grid_conditions<D>(c, grid_);
  for (int d = 0; d < D; ++d)
    gravity_[d] = c.simulation.gravity[d];
  // Slab width: GIMP writes nodes [cell-1, cell+2], so slabs of 4 cells keep two slabs of one
  // colour at least one slab apart.
  slab_width_ = 4;
  num_slabs_ = (grid_.cells[0] + slab_width_ - 1) / slab_width_;
  // The energy budget counts from the start (the initial stresses' elastic energy is its
  // baseline) until release() restarts it.
  for (int b = 0; b < B; ++b)
    strain_energy0_.push_back(strain_energy(b));
  bin_offset_.assign(static_cast<std::size_t>(num_slabs_ * B + 1), 0);
}

// The P-wave speed of particle p at its current density, sqrt(M V / m). It grows as sqrt(J): a
// particle's internal force scales with its current volume, so its stiffness over its mass does
// too (capping J here was tried and blows up: docs/performance.md).
template <int D>
double Simulation<D>::wave_speed(std::int64_t p, double modulus) const {
  const auto& P = particles_;
  return std::sqrt(modulus * P.vol[p] / P.m[p]);
}

// The stable time step: CFL on the P-wave speed plus the particle speed, one pass over the
// particles, unless the case fixes dt.
template <int D>
double Simulation<D>::compute_time_step() const {
  const auto& P = particles_;
  if (case_data_.simulation.dt)
    return std::min(*case_data_.simulation.dt, case_data_.simulation.dt_max);
  double max_speed = 0.0;
  for (int b = 0; b < P.num_bodies(); ++b) {
    // A rigid body carries no stress wave: only its speed counts.
    const double modulus = case_data_.bodies[b].rigid ? 0.0 : body_material_[b].p_wave_modulus();
    const std::int64_t begin = P.body_begin[b], end = P.body_begin[b + 1];
#pragma omp parallel for reduction(max : max_speed) schedule(static)
    for (std::int64_t p = begin; p < end; ++p)
      max_speed = std::max(max_speed, wave_speed(p, modulus) + P.v[p].norm());
  }
  const double cfl = settling_ && case_data_.initial_state.settle_cfl
                         ? *case_data_.initial_state.settle_cfl
                         : case_data_.simulation.cfl;
  return std::min(cfl * grid_.h / max_speed, case_data_.simulation.dt_max);
}

// The CFL step fell below its floor: name the particle that sets it (fastest wave plus speed).
template <int D>
void Simulation<D>::report_time_step_collapse(double stable, double floor) const {
  const auto& P = particles_;
  std::size_t worst = 0;
  double worst_speed = -1.0;
  for (int b = 0; b < P.num_bodies(); ++b) {
    const double modulus = case_data_.bodies[b].rigid ? 0.0 : body_material_[b].p_wave_modulus();
    for (std::size_t p = P.body_begin[b]; p < P.body_begin[b + 1]; ++p) {
      const double speed = wave_speed(p, modulus) + P.v[p].norm();
      if (speed > worst_speed) worst_speed = speed, worst = p;
    }
  }
  throw SimulationError(fmt::format(
      "step {}, time {:.6g} s: body '{}', particle {} (id {}) at ({}): time step collapsed to "
      "{:.3g} s, below the floor {:.3g} s (simulation.dt_min): speed {:.4g} m/s, volume ratio "
      "{:.3g}",
      steps_, time_, case_data_.bodies[P.body_of(worst)].name, worst, P.id[worst],
      fmt::join(P.x[worst].data(), P.x[worst].data() + D, ", "), stable, floor, P.v[worst].norm(),
      P.vol[worst] / P.vol0[worst]));
}

template <int D>
bool Simulation<D>::particle_ok(std::int64_t p, const Vec<D>& lo, const Vec<D>& hi) const {
  return motion_ok(p, lo, hi) && particles_.stress[p].allFinite();
}

template <int D>
void Simulation<D>::check_particles() const {
  const auto& P = particles_;
  std::atomic<std::size_t> bad{P.size()};
  const Vec<D> lo = grid_.origin, hi = grid_.upper();
#pragma omp parallel for schedule(static)
  for (std::int64_t p = 0; p < static_cast<std::int64_t>(P.size()); ++p)
    if (!particle_ok(p, lo, hi)) record_bad(bad, static_cast<std::size_t>(p));
  if (bad.load() != P.size()) report_bad_particle(bad.load());
}

template <int D>
void Simulation<D>::report_bad_particle(std::size_t p) const {
  const auto& P = particles_;
  const char* what = !P.x[p].allFinite()        ? "position is not finite"
                     : !P.v[p].allFinite()      ? "velocity is not finite"
                     : !P.stress[p].allFinite() ? "stress is not finite"
                                                : "particle left the grid";
  throw SimulationError(
      fmt::format("step {}, time {:.6g} s: body '{}', particle {} (id {}) at ({}): {}", steps_,
                  time_, case_data_.bodies[P.body_of(p)].name, p, P.id[p],
                  fmt::join(P.x[p].data(), P.x[p].data() + D, ", "), what));
}

template <int D>
void Simulation<D>::sort_particles_by_cell() {
  auto& P = particles_;
  shape_step_ = -1; // shape_ is indexed by particle: the permutation invalidates it
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
  index_of_id_.resize(P.size());
  for (std::size_t p = 0; p < P.size(); ++p)
    index_of_id_[P.id[p]] = static_cast<std::uint32_t>(p);
}

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
    if (fixed_field_ready_[b]) { // its field stands: no scatter visits its particles
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
    if (fixed_field_ready_[b]) continue;
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
  for (int b = 0; b < B; ++b) {
    if (fixed_field_ready_[b]) continue; // its box and sums stand
    const Vec<D> lo = Eigen::Map<const Vec<D>>(lo_ + b * D),
                 hi = Eigen::Map<const Vec<D>>(hi_ + b * D);
    Index<D> first = grid_.cell_of(lo), last = grid_.cell_of(hi);
    for (int d = 0; d < D; ++d) {
      first[d] = std::clamp<std::int64_t>(first[d] - 1, 0, grid_.nodes[d]);
      last[d] = std::clamp<std::int64_t>(last[d] + 3, 0, grid_.nodes[d]);
    }
    fields_[b].fit(grid_, first, last);
  }
}

// P2G, eq. 14-18 and 30: mass, momentum, mass gradient and mass-weighted position, and
// (optionally) internal and external force, each body into its own field. The mass gradient and
// position serve contact only; a single body skips them.
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
      overlap = last >= O.offset[d] - margin && first < O.offset[d] + O.box.nodes[d] + margin;
    }
    if (overlap) return true;
  }
  return false;
}

// Orphans (contact.orphan_fraction; docs/formulation.md "Orphan particles"). A deformable
// body's particle cut off from its body inside another one cannot be resolved as a surface of
// its own: alone in its field, its stress acts on nodes that carry only its mass while contact
// with the body around it keeps squeezing it. So a particle whose own-body neighbours put less
// than orphan_fraction of a filled cell's mass (rho_0 h^D) on its nodes, while another
// deformable body puts at least a quarter of it there and more than its own body, maps to that
// body's field from the next step on: it moves with the body around it (one velocity field,
// as in single-field MPM) and keeps its own material, stress and body. It returns to its own
// field when its own body's neighbours put twice the fraction there (hysteresis). Decided at
// the end of every orphan_interval-th step from that step's nodal masses and start-of-step
// weights, for the steps that follow; deterministic.
template <int D>
void Simulation<D>::update_orphans() {
  const double fraction = case_data_.contact.orphan_fraction;
  const int B = num_bodies();
  auto& P = particles_;
  if (fraction <= 0.0 || B < 2) { // off (a checkpoint's orphans, if any, go home)
    for (int b = 0; b < B; ++b)
      std::fill(P.field.begin() + P.body_begin[b], P.field.begin() + P.body_begin[b + 1], b);
    return;
  }
  if (shape_.size() != P.size())
    throw std::logic_error("update_orphans needs the step's shape weights");
  const double cell = std::pow(grid_.h, D);
  for (int b = 0; b < B; ++b) {
    if (case_data_.bodies[b].rigid) continue;
    const std::int64_t begin = P.body_begin[b], end = P.body_begin[b + 1];
#pragma omp parallel for schedule(static)
    for (std::int64_t p = begin; p < end; ++p) {
      const int f = P.field[p];
      const ShapeWeights<D>& sw = shape_[p];
      if (f == b && !reaches_other_body(b, sw, 0)) continue;
      const BodyField<D>& H = fields_[f];
      // Body c's nodal mass at p's nodes, weighted by p's shape functions, without p's own.
      auto mass_around = [&](int c) {
        double m = 0.0;
        if (c == f) {
          for_each_node(H.box, sw, [&](std::int64_t I, double N_I, const Vec<D>&) {
            m += N_I * (H.m[I] - N_I * P.m[p]);
          });
          return m;
        }
        const BodyField<D>& C = fields_[c];
        for_each_node(H.box, sw, [&](std::int64_t I, double N_I, const Vec<D>&) {
          Index<D> g;
          for (int d = D - 1; d >= 0; --d)
            g[d] = H.offset[d] + I % H.box.nodes[d], I /= H.box.nodes[d];
          if (const std::int64_t J = C.local(g); J >= 0) m += N_I * C.m[J];
        });
        return m;
      };
      const double filled = P.m[p] / P.vol0[p] * cell;
      const double own = mass_around(b);
      int host = b;
      if (own < (f == b ? 1.0 : 2.0) * fraction * filled) {
        double best = std::max(own, 0.25 * filled);
        for (int c = 0; c < B; ++c) {
          if (c == b || case_data_.bodies[c].rigid) continue;
          if (const double m = mass_around(c); m > best) best = m, host = c;
        }
      }
      P.field[p] = host;
    }
  }
}

template <int D>
std::int64_t Simulation<D>::orphans() const {
  const auto& P = particles_;
  std::int64_t n = 0;
  for (int b = 0; b < P.num_bodies(); ++b)
    n += std::count_if(P.field.begin() + P.body_begin[b], P.field.begin() + P.body_begin[b + 1],
                       [b](std::int32_t f) { return f != b; });
  return n;
}

template <int D>
template <bool with_forces, bool with_contact>
void Simulation<D>::scatter_particles() {
  auto& P = particles_;
  const ShapeKind kind = case_data_.grid.shape;
  shape_.resize(P.size());
  shape_step_ = steps_;
  scatter([&](std::uint32_t p, int b) {
    const int f = P.field[p]; // b, or the host of an orphan
    BodyField<D>& N = fields_[f];
    ShapeWeights<D>& sw = shape_[p];
    evaluate_shape(sw, N.box, kind, body_gimp_[b], P.x[p]);
    const double m_p = P.m[p];
    const Vec<D> mv_p = m_p * P.v[p], mx_p = m_p * P.x[p];
    const Mat<D> Vsigma = P.vol[p] * in_plane<D>(to_tensor(P.stress[p]));
    const Vec<D> mg = m_p * gravity_;
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
        (fixed(b) || reaches_other_body(f, sw, case_data_.contact.normal_smoothing)))
      map.template operator()<true>();
    else
      map.template operator()<false>();
    if (P.iface[p] >= 0 && f == b) { // eq. 37 (an orphan is not on its interface any more): the
                                     // interface particle's share of the node's capacity
      const InterfaceSpec& spec = case_data_.interfaces[P.iface[p]];
      const double A = P.iface_area[p];
      const double cA = P.cohesion[p] * A, tA = tensile_strength(spec, P.cohesion[p]) * A;
      const double muA = P.friction[p] * A;
      const int S = N.slots, slot = interface_slot(b, P.iface[p]);
      for_each_node(N.box, sw, [&](std::int64_t I, double N_I, const Vec<D>&) {
        const std::int64_t j = I * S + slot;
        N.cohesion[j] += N_I * cA;
        N.tension[j] += N_I * tA;
        N.friction_area[j] += N_I * muA;
        N.area[j] += N_I * A;
      });
    }
  });
}

template <int D>
void Simulation<D>::map_forces_to_nodes() {
  auto& P = particles_;
  assert_shape_current();
  scatter([&](std::uint32_t p, int) {
    BodyField<D>& N = fields_[P.field[p]];
    const ShapeWeights<D>& sw = shape_[p];
    const Mat<D> Vsigma = P.vol[p] * in_plane<D>(to_tensor(P.stress[p]));
    const Vec<D> mg = P.m[p] * gravity_;
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
template <int D>
void Simulation<D>::gather_slip(std::size_t p, const BodyField<D>& N, const ShapeWeights<D>& sw,
                                double dt) {
  auto& P = particles_;
  if (P.iface[p] < 0 || settling_) return;
  double rate = 0.0, weight = 0.0;
  const int S = N.slots, slot = interface_slot(P.body_of(p), P.iface[p]);
  for_each_node(N.box, sw, [&](std::int64_t I, double N_I, const Vec<D>&) {
    rate += N_I * N.slip_rate[I * S + slot];
    weight += N_I * N.slip_weight[I * S + slot];
  });
  const InterfaceSpec& spec = case_data_.interfaces[P.iface[p]];
  P.slip[p] += rate / std::max(weight, min_slip_weight) * dt;
  P.cohesion[p] = spec.cohesion.at(P.slip[p], spec.curve);
  P.friction[p] = spec.friction.at(P.slip[p], spec.curve);
}

// MUSL's middle: each particle takes the FLIP/PIC velocity of the contact-corrected grid (and
// its slip) and moves, then its new momentum is scattered for the re-mapped velocity. One
// coloured pass does all three: the gather reads v and v_new, the scatter writes p. The stress
// pass that follows reads the weights of the step's start (shape_), so moving here is safe.
template <int D>
void Simulation<D>::update_velocities_and_remap(double dt) {
  auto& P = particles_;
  const double flip = case_data_.simulation.flip;
  assert_shape_current();
  for (auto& N : fields_)
    std::fill(N.p.begin(), N.p.end(), Vec<D>::Zero());
  std::atomic<std::size_t> gone{no_particle};
  const Vec<D> lo = grid_.origin, hi = grid_.upper();
  scatter([&](std::uint32_t p, int b) {
    BodyField<D>& N = fields_[P.field[p]];
    const ShapeWeights<D>& sw = shape_[p];
    if (case_data_.bodies[b].rigid) {
      P.v[p] = rigid_velocity_[b];
      P.x[p] += dt * rigid_velocity_[b];
    } else {
      Vec<D> v_old = Vec<D>::Zero(), v_new = Vec<D>::Zero();
      for_each_node(N.box, sw, [&](std::int64_t I, double N_I, const Vec<D>&) {
        v_old += N_I * N.v[I];
        v_new += N_I * N.v_new[I];
      });
      P.v[p] = flip * (P.v[p] + v_new - v_old) + (1.0 - flip) * v_new;
      P.x[p] += 0.5 * dt * (v_old + v_new);
      if (P.field[p] == b) gather_slip(p, N, sw, dt);
    }
    if (!motion_ok(p, lo, hi)) record_bad(gone, p);
    const Vec<D> mv_p = P.m[p] * P.v[p];
    for_each_node(N.box, sw,
                  [&](std::int64_t I, double N_I, const Vec<D>&) { N.p[I] += N_I * mv_p; });
  });
  bad_particle_ = std::min(bad_particle_, gone.load());
  // The re-mapped velocity p/m of every body, with the velocity conditions and rigid motions.
  for (int b = 0; b < num_bodies(); ++b) {
    BodyField<D>& N = fields_[b];
    const std::int64_t n = static_cast<std::int64_t>(N.size());
#pragma omp parallel for schedule(static)
    for (std::int64_t i = 0; i < n; ++i)
      N.v_remap[i] = N.m[i] > 0.0 ? Vec<D>(N.p[i] / N.m[i]) : Vec<D>::Zero();
    apply_grid_conditions<D>(conditions_, b, N, N.v_remap);
  }
  impose_rigid_velocity(&BodyField<D>::v_remap);
}

// Grid update, eq. 19-20 and 31: v^n = p/m and the free v^{n+1} = v^n + f/m dt per body, with
// local damping and the velocity conditions applied to both.
template <int D>
void Simulation<D>::compute_node_velocities(double dt) {
  const double alpha =
      settling_ ? case_data_.initial_state.settle_damping : case_data_.simulation.damping;
  for (int b = 0; b < num_bodies(); ++b) {
    BodyField<D>& N = fields_[b];
    const std::int64_t n = static_cast<std::int64_t>(N.size());
#pragma omp parallel for schedule(static)
    for (std::int64_t i = 0; i < n; ++i) {
      if (N.m[i] <= 0.0) {
        N.v[i].setZero();
        N.v_new[i].setZero();
        continue;
      }
      N.v[i] = N.p[i] / N.m[i];
      Vec<D> f = N.f[i];
      if (alpha > 0.0)
        for (int d = 0; d < D; ++d)
          f[d] -= alpha * std::abs(f[d]) * (N.v[i][d] > 0.0 ? 1.0 : (N.v[i][d] < 0.0 ? -1.0 : 0.0));
      N.v_new[i] = N.v[i] + f / N.m[i] * dt;
    }
    apply_grid_conditions<D>(conditions_, b, N, N.v);
    apply_grid_conditions<D>(conditions_, b, N, N.v_new);
  }
  impose_rigid_velocity(&BodyField<D>::v);
  impose_rigid_velocity(&BodyField<D>::v_new);
}

template <int D>
void Simulation<D>::impose_rigid_velocity(std::vector<Vec<D>> BodyField<D>::*velocity) {
  for (int b = 0; b < num_bodies(); ++b)
    if (case_data_.bodies[b].rigid)
      std::fill((fields_[b].*velocity).begin(), (fields_[b].*velocity).end(), rigid_velocity_[b]);
}

// Contact at every node that two or more bodies share (ARCHITECTURE.md step 5). The nodes are
// visited row by row along x; contact forces are summed per row and then in row order, so the
// recorded forces do not depend on the thread count either.
template <int D>
void Simulation<D>::apply_contact(std::vector<Vec<D>> BodyField<D>::*velocity, double dt,
                                  bool record) {
  const int B = num_bodies();
  if (B < 2) return;
  // The nodes where at least two boxes overlap.
  Index<D> lo, hi;
  bool any = false;
  for (int a = 0; a < B; ++a)
    for (int b = a + 1; b < B; ++b) {
      Index<D> l, h;
      bool overlap = true;
      for (int d = 0; d < D; ++d) {
        l[d] = std::max(fields_[a].offset[d], fields_[b].offset[d]);
        h[d] = std::min(fields_[a].offset[d] + fields_[a].box.nodes[d],
                        fields_[b].offset[d] + fields_[b].box.nodes[d]);
        overlap = overlap && l[d] < h[d];
      }
      if (!overlap) continue;
      for (int d = 0; d < D; ++d)
        lo[d] = any ? std::min(lo[d], l[d]) : l[d], hi[d] = any ? std::max(hi[d], h[d]) : h[d];
      any = true;
    }
  if (record) {
    std::fill(contact_force_.begin(), contact_force_.end(), Vec<D>::Zero());
    std::fill(interface_force_.begin(), interface_force_.end(), InterfaceForce{});
    for (auto& row : contact_node_rows_)
      row.clear(); // keeps the capacity: no allocation once warmed up
  }
  if (!any) return;
  const std::int64_t rows = hi[0] - lo[0];
  if (record) {
    contact_rows_.assign(rows * B * B, Vec<D>::Zero());
    contact_work_rows_.assign(rows * B, 0.0);
    if (case_data_.output.contact_nodes &&
        static_cast<std::int64_t>(contact_node_rows_.size()) < rows)
      contact_node_rows_.resize(rows);
    interface_rows_.assign(rows * interface_force_.size(), InterfaceForce{});
  }
#pragma omp parallel for schedule(dynamic, 4)
  for (std::int64_t r = 0; r < rows; ++r) {
    Index<D> g = lo;
    g[0] = lo[0] + r;
    while (true) {
      ContactNode<D> node;
      std::int64_t local[max_bodies_at_node];
      for (int b = 0; b < B && node.n < max_bodies_at_node; ++b) {
        const std::int64_t i = fields_[b].local(g);
        if (i < 0 || fields_[b].m[i] <= 0.0) continue;
        const BodyField<D>& N = fields_[b];
        const int k = node.n++;
        node.body[k] = b, local[k] = i;
        node.m[k] = N.m[i];
        node.v[k] = (N.*velocity)[i];
        node.grad_m[k] = N.grad_m[i];
        node.x[k] = N.mx[i] / N.m[i];
        node.rigid[k] = case_data_.bodies[b].rigid;
        node.rank[k] = body_mass_[b] + 1e-9 * b; // ties broken by body order
        node.surface_normal[k].setZero();
        if (case_data_.bodies[b].geometric_normal) {
          // The exact normal of the body's geometry (moved with a rigid body's velocity). A body
          // whose geometry stays put keeps each node's normal in a cache.
          const bool moves = node.rigid[k] && !rigid_velocity_[b].isZero();
          Vec<D>* cached = moves ? nullptr : &normal_cache_[b][grid_.node_index(g)];
          if (cached && !std::isnan((*cached)[0])) {
            node.surface_normal[k] = *cached;
          } else {
            const Vec<D> x_I = grid_.node_position(g) -
                               (moves ? Vec<D>(rigid_velocity_[b] * time_) : Vec<D>::Zero());
            node.surface_normal[k] = surface_normal<D>(case_data_.bodies[b].geometry[0], x_I);
            if (cached) *cached = node.surface_normal[k]; // this row's thread alone writes it
          }
        }
      }
      if (node.n >= 2) {
        // Normals from mass gradients smoothed over the neighbouring nodes: a lattice-sampled
        // surface's raw gradient tilts by a degree or more from node to node.
        if (const int radius = case_data_.contact.normal_smoothing; radius > 0)
          for (int k = 0; k < node.n; ++k)
            if (node.surface_normal[k].isZero())
              node.grad_m[k] = smoothed_gradient<D>(fields_[node.body[k]], g, radius);
        // Each body's friction is that of its pair with the heaviest other body at the node.
        for (int k = 0; k < node.n; ++k) {
          int other = k == 0 ? 1 : 0;
          for (int j = 0; j < node.n; ++j)
            if (j != k && node.m[j] > node.m[other]) other = j;
          node.mu[k] = pair_friction_[node.body[k] * B + node.body[other]];
          // An interface pair: the slave body's interface particles give the capacities and the
          // friction at this node.
          node.cohesion[k] = node.tension[k] = 0.0;
          if (const int f = pair_interface_[node.body[k] * B + node.body[other]]; f >= 0) {
            const int s = is_slave(node, k, other) ? k : other;
            const BodyField<D>& S = fields_[node.body[s]];
            const std::int64_t i = local[s] * S.slots + interface_slot(node.body[s], f);
            if (S.area[i] > 0.0) {
              node.mu[k] = S.friction_area[i] / S.area[i];
              node.cohesion[k] = S.cohesion[i];
              node.tension[k] = S.tension[i];
              // Settling holds a bonded interface outright: no slip, no opening.
              if (settling_ && case_data_.initial_state.hold_interfaces)
                node.cohesion[k] = node.tension[k] = inf;
            }
          }
        }
        Vec<D> before[max_bodies_at_node];
        for (int k = 0; k < node.n; ++k)
          before[k] = node.v[k];
        if (resolve_contact(node, contact_law_, dt)) {
          for (int k = 0; k < node.n; ++k) {
            (fields_[node.body[k]].*velocity)[local[k]] = node.v[k];
            if (!record) continue;
            int other = k == 0 ? 1 : 0;
            for (int j = 0; j < node.n; ++j)
              if (j != k && node.m[j] > node.m[other]) other = j;
            contact_rows_[(r * B + node.body[k]) * B + node.body[other]] +=
                node.m[k] * (node.v[k] - before[k]) / dt;
            // The contact's work on the body over the step: its impulse times the node's mean
            // velocity over the step, (v^n + v^{n+1}) / 2, the velocity the particles move with.
            const Vec<D>& v_start = fields_[node.body[k]].v[local[k]];
            contact_work_rows_[r * B + node.body[k]] +=
                node.m[k] * (node.v[k] - before[k]).dot(0.5 * (v_start + node.v[k]));
            if (case_data_.output.contact_nodes && node.v[k] != before[k])
              contact_node_rows_[r].push_back(
                  {grid_.node_position(g), node.body[k], node.body[other],
                   Vec<D>(node.m[k] * (node.v[k] - before[k]) / dt), node.normal[k],
                   node.friction_impulse[k] / dt, node.cohesion_impulse[k] / dt});
            const int f = pair_interface_[node.body[k] * B + node.body[other]];
            if (f >= 0 && is_slave(node, k, other)) { // the slave side, counted once
              InterfaceForce& row = interface_rows_[r * interface_force_.size() + f];
              row.cohesive += node.cohesion_impulse[k] / dt;
              row.frictional += node.friction_impulse[k] / dt;
              row.normal += node.normal_impulse[k] / dt;
            }
          }
        }
        // Slip rate (eq. 38-39, as the interface's relative displacement): where the node holds
        // the bodies together, the tangential relative velocity after contact; where a bond has
        // opened past its tensile capacity, the whole relative velocity (the opening breaks the
        // bond as sliding does, and a bond that opened does not heal when it closes again).
        // Only against the body's interface partner (the heaviest other body at the node, whose
        // friction and bond the node used); a third body sliding past is not the interface.
        // Weighted by how evenly the two bodies share the node's volume (mass over material
        // density), 4 s (1 - s), and not measured where either has less than min_slip_share of
        // it (by mass, a rigid plane's density changed the slip a block recorded on it: a plane
        // 25 times denser put the block under the cut at nodes it half fills). At a node one body
        // barely reaches (a GIMP fringe) its velocity is a force over a round-off mass (1,640 m/s
        // in the two-block column at 3 ms, and 392 m/s times a weight of 1e-4 still added 0.6 m/s
        // to a lifted particle's slip rate there).
        if (record)
          for (int k = 0; k < node.n; ++k) {
            BodyField<D>& K = fields_[node.body[k]];
            if (!K.needs.interfaces || !(node.closed[k] || node.opened[k])) continue;
            int other = k == 0 ? 1 : 0;
            for (int j = 0; j < node.n; ++j)
              if (j != k && node.m[j] > node.m[other]) other = j;
            const int f = pair_interface_[node.body[k] * B + node.body[other]];
            if (f < 0) continue; // no bond
            const Vec<D> rel = node.v[k] - node.v[other];
            const Vec<D>& nrm = node.normal[k];
            const double v_k = node.m[k] / body_density_[node.body[k]];
            const double v_other = node.m[other] / body_density_[node.body[other]];
            const double s = v_other / (v_k + v_other);
            if (std::min(s, 1.0 - s) < min_slip_share) continue; // a fringe: no velocity to trust
            const double share = 4.0 * s * (1.0 - s);
            const double rate = node.opened[k] ? rel.norm() : (rel - rel.dot(nrm) * nrm).norm();
            const std::int64_t j = local[k] * K.slots + interface_slot(node.body[k], f);
            K.slip_rate[j] = share * rate;
            K.slip_weight[j] = share;
          }
      }
      int d = D - 1;
      while (d >= 1 && ++g[d] == hi[d])
        g[d] = lo[d], --d;
      if (d < 1) break;
    }
  }
  if (record) {
    for (std::int64_t r = 0; r < rows; ++r)
      for (int k = 0; k < B * B; ++k)
        contact_force_[k] += contact_rows_[r * B * B + k];
    for (std::int64_t r = 0; r < rows; ++r)
      for (int b = 0; b < B; ++b)
        contact_work_[b] += contact_work_rows_[r * B + b];
    const std::size_t F = interface_force_.size();
    for (std::size_t f = 0; f < F; ++f) {
      interface_force_[f] = InterfaceForce{};
      for (std::int64_t r = 0; r < rows; ++r) {
        interface_force_[f].cohesive += interface_rows_[r * F + f].cohesive;
        interface_force_[f].frictional += interface_rows_[r * F + f].frictional;
        interface_force_[f].normal += interface_rows_[r * F + f].normal;
      }
    }
  }
  // Velocity conditions have the last word over contact.
  for (int b = 0; b < B; ++b)
    apply_grid_conditions<D>(conditions_, b, fields_[b], fields_[b].*velocity);
}

// G2P. With `velocity`, the particle velocity takes the FLIP/PIC blend of the grid change (eq. 22);
// with `move`, the particle moves with the mean of v^n and v^{n+1} (eq. 23; exact for a constant
// acceleration); with a strain-rate field, its gradient L updates F, volume and stress (eq. 24-28).
template <int D>
void Simulation<D>::map_nodes_to_particles(double dt, const Gather& what) {
  auto body = [&]<bool velocity, bool move>(int b) {
    if (what.strain_rate)
      std::visit(
          [&](const auto& model) {
            map_nodes_to_body<std::decay_t<decltype(model)>, velocity, move>(b, dt, what, &model);
          },
          body_material_[b].model);
    else
      map_nodes_to_body<LinearElastic, velocity, move>(b, dt, what, nullptr);
  };
  for (int b = 0; b < particles_.num_bodies(); ++b) {
    if (what.velocity && what.move)
      body.template operator()<true, true>(b);
    else if (what.velocity)
      body.template operator()<true, false>(b);
    else if (what.move)
      body.template operator()<false, true>(b);
    else
      body.template operator()<false, false>(b);
  }
  if (what.move) shape_step_ = -1; // the weights are of the old positions
}

template <int D>
template <class Model, bool velocity, bool move>
void Simulation<D>::map_nodes_to_body(int b, double dt, const Gather& what, const Model* model) {
  auto& P = particles_;
  const double flip = case_data_.simulation.flip;
  const bool rigid = case_data_.bodies[b].rigid;
  if (fixed_field_ready_[b]) return; // a fixed body: nothing moves, no stress
  assert_shape_current();
  const double max_J = body_material_[b].max_volume_ratio;
  const std::int64_t begin = P.body_begin[b], end = P.body_begin[b + 1];
  std::atomic<std::size_t> bad{P.size()}, gone{no_particle};
  const Vec<D> lo = grid_.origin, hi = grid_.upper();
  // Particles go in fixed chunks so that the stress work sums in an order that does not depend
  // on the thread count (chunk sums, then the chunks in order).
  const std::int64_t chunks = (end - begin + work_chunk - 1) / work_chunk;
  if (static_cast<std::int64_t>(chunk_work_.size()) < chunks) chunk_work_.resize(chunks);
#pragma omp parallel for schedule(dynamic, 1)
  for (std::int64_t c = 0; c < chunks; ++c) {
    double work = 0.0;
    for (std::int64_t p = begin + c * work_chunk; p < std::min(end, begin + (c + 1) * work_chunk);
         ++p) {
      if (rigid) { // prescribed motion; no stress
        if constexpr (velocity) P.v[p] = rigid_velocity_[b];
        if constexpr (move) P.x[p] += dt * rigid_velocity_[b];
        if constexpr (velocity || move)
          if (!motion_ok(p, lo, hi)) record_bad(gone, static_cast<std::size_t>(p));
        continue;
      }
      const ShapeWeights<D>& sw = shape_[p];
      const BodyField<D>& N = fields_[P.field[p]];
      const Vec<D>* rate = what.strain_rate ? (N.*what.strain_rate).data() : nullptr;
      Vec<D> v_old = Vec<D>::Zero(), v_new = Vec<D>::Zero();
      Mat<D> L = Mat<D>::Zero();
      for_each_node(N.box, sw, [&](std::int64_t I, double N_I, const Vec<D>& dN_I) {
        if constexpr (velocity || move) {
          v_old += N_I * N.v[I];
          v_new += N_I * N.v_new[I];
        }
        if (rate) L += rate[I] * dN_I.transpose();
      });
      if constexpr (velocity) {
        P.v[p] = flip * (P.v[p] + v_new - v_old) + (1.0 - flip) * v_new;
        if (P.field[p] == b) gather_slip(static_cast<std::size_t>(p), N, sw, dt);
      }
      if constexpr (move) P.x[p] += 0.5 * dt * (v_old + v_new);
      if constexpr (velocity || move)
        if (!motion_ok(p, lo, hi)) record_bad(gone, static_cast<std::size_t>(p));
      if (model) {
        P.F[p] = (Mat<D>::Identity() + L * dt) * P.F[p];
        double J = P.F[p].determinant();
        if (!(J > 0.0)) record_bad(bad, static_cast<std::size_t>(p));
        if (J > max_J) { // past the volume limit the opening is separation, not the particle's
          P.F[p] *= std::pow(max_J / J, 1.0 / D);
          J = max_J;
        }
        const double vol_old = P.vol[p];
        P.vol[p] = P.vol0[p] * J;
        const Mat3 L3 = embed<D>(L);
        const Mat3 D3 = 0.5 * (L3 + L3.transpose());
        const Voigt sigma_old = P.stress[p];
        update_stress(*model, P.stress[p], P.eps_p[p], D3, 0.5 * (L3 - L3.transpose()), dt);
        // Stress work over the step, midpoint rule: (V sigma) : D dt.
        const Voigt s = 0.5 * (vol_old * sigma_old + P.vol[p] * P.stress[p]);
        work += dt * (s[0] * D3(0, 0) + s[1] * D3(1, 1) + s[2] * D3(2, 2) +
                      2.0 * (s[3] * D3(0, 1) + s[4] * D3(1, 2) + s[5] * D3(0, 2)));
        if (!P.stress[p].allFinite()) record_bad(gone, static_cast<std::size_t>(p));
      }
    }
    chunk_work_[c] = work;
  }
  if (model && !rigid)
    for (std::int64_t c = 0; c < chunks; ++c)
      internal_work_[b] += chunk_work_[c];
  bad_particle_ = std::min(bad_particle_, gone.load());
  if (const std::size_t p = bad.load(); p != P.size())
    throw SimulationError(fmt::format(
        "step {}, time {:.6g} s: body '{}', particle {} (id {}) at ({}): det F = {:.3g} <= 0 "
        "(the particle turned inside out; reduce the time step or check the case)",
        steps_, time_, case_data_.bodies[b].name, p, P.id[p],
        fmt::join(P.x[p].data(), P.x[p].data() + D, ", "), P.F[p].determinant()));
}

template <int D>
void Simulation<D>::step(double dt_limit) {
  const auto t0 = Clock::now();
  bad_particle_ = no_particle; // a phase run on its own before (tests) leaves nothing behind
  if (!particles_checked_) check_particles(), particles_checked_ = true;
  const double stable = compute_time_step();
  if (dt_reference_ == 0.0 && std::isfinite(stable)) {
    // The reference is a step of the motion: a settling step at settle_cfl is scaled to cfl.
    const auto& settle_cfl = case_data_.initial_state.settle_cfl;
    dt_reference_ = settling_ && settle_cfl && !case_data_.simulation.dt
                        ? stable * case_data_.simulation.cfl / *settle_cfl
                        : stable;
  }
  const double floor = case_data_.simulation.dt_min.value_or(1e-4 * dt_reference_);
  if (!case_data_.simulation.dt && stable < floor) report_time_step_collapse(stable, floor);
  dt_ = std::min(stable, dt_limit);
  if (steps_ % sort_interval_ == 0) sort_particles_by_cell();
  bin_particles_by_slab();
  fit_body_fields();
  phase_times_.other += seconds_since(t0);

  auto timed = [](double& acc, auto&& phase) {
    const auto t = Clock::now();
    phase();
    acc += seconds_since(t);
  };
  using F = BodyField<D>;
  auto& T = phase_times_;
  switch (case_data_.simulation.scheme) {
  case Scheme::usf: // stress first, from the velocity of the mapped momentum
    timed(T.p2g, [&] { map_particles_to_nodes(false); });
    timed(T.grid, [&] { compute_node_velocities(0.0); });
    timed(T.contact, [&] { apply_contact(&F::v, dt_, false); });
    timed(T.stress, [&] { map_nodes_to_particles(dt_, {.strain_rate = &F::v}); });
    timed(T.p2g, [&] { map_forces_to_nodes(); });
    timed(T.grid, [&] { compute_node_velocities(dt_); });
    timed(T.contact, [&] { apply_contact(&F::v_new, dt_, true); });
    timed(T.g2p, [&] { map_nodes_to_particles(dt_, {.velocity = true, .move = true}); });
    break;
  case Scheme::usl: // stress last, from the updated grid velocity
    timed(T.p2g, [&] { map_particles_to_nodes(true); });
    timed(T.grid, [&] { compute_node_velocities(dt_); });
    timed(T.contact, [&] { apply_contact(&F::v_new, dt_, true); });
    timed(T.g2p, [&] {
      map_nodes_to_particles(dt_, {.velocity = true, .move = true, .strain_rate = &F::v_new});
    });
    break;
  case Scheme::musl: // stress last, from the velocity re-mapped from the updated particles
    timed(T.p2g, [&] { map_particles_to_nodes(true); });
    timed(T.grid, [&] { compute_node_velocities(dt_); });
    timed(T.contact, [&] { apply_contact(&F::v_new, dt_, true); });
    timed(T.g2p, [&] { update_velocities_and_remap(dt_); });
    timed(T.contact, [&] { apply_contact(&F::v_remap, dt_, false); });
    timed(T.stress, [&] { map_nodes_to_particles(dt_, {.strain_rate = &F::v_remap}); });
    break;
  }
  // Orphans change over thousands of steps: every tenth step's masses and weights decide them.
  if (steps_ % orphan_interval == 0) timed(T.other, [&] { update_orphans(); });
  shape_step_ = -1; // the particles have moved
  for (std::size_t k = 0; k < contact_force_.size(); ++k)
    contact_impulse_[k] += dt_ * contact_force_[k];
  for (std::size_t f = 0; f < interface_force_.size(); ++f) {
    interface_impulse_[f].cohesive += dt_ * interface_force_[f].cohesive;
    interface_impulse_[f].frictional += dt_ * interface_force_[f].frictional;
    interface_impulse_[f].normal += dt_ * interface_force_[f].normal;
  }
  impulse_time_ += dt_;
  time_ += dt_;
  ++steps_;
  for (int b = 0; b < num_bodies(); ++b)
    fixed_field_ready_[b] = fixed(b);
  // Before anything reads the new state (output, checkpoint, the next step).
  if (bad_particle_ != no_particle) report_bad_particle(bad_particle_);
}

template <int D>
std::vector<ContactNodeForce<D>> Simulation<D>::contact_nodes() const {
  std::vector<ContactNodeForce<D>> all;
  for (const auto& row : contact_node_rows_)
    all.insert(all.end(), row.begin(), row.end());
  return all;
}

template <int D>
void Simulation<D>::reset_force_means() {
  std::fill(contact_impulse_.begin(), contact_impulse_.end(), Vec<D>::Zero());
  std::fill(interface_impulse_.begin(), interface_impulse_.end(), InterfaceForce{});
  impulse_time_ = 0.0;
}

template <int D>
void Simulation<D>::release() {
  settling_ = false;
  time_ = 0.0;
  reset_force_means();
  particles_.x0 = particles_.x;
  std::fill(contact_work_.begin(), contact_work_.end(), 0.0);
  std::fill(internal_work_.begin(), internal_work_.end(), 0.0);
  strain_energy0_.clear();
  for (int b = 0; b < num_bodies(); ++b)
    strain_energy0_.push_back(strain_energy(b));
}

template <int D>
double Simulation<D>::gravity_work(int b) const {
  const auto& P = particles_;
  double w = 0.0;
  for (std::size_t p = P.body_begin[b]; p < P.body_begin[b + 1]; ++p)
    w += P.m[p] * gravity_.dot(P.x[p] - P.x0[p]);
  return w;
}

template <int D>
double Simulation<D>::strain_energy(int b) const {
  const auto& P = particles_;
  if (case_data_.bodies[b].rigid) return 0.0;
  const double K =
      std::visit([](const auto& m) { return m.bulk_modulus(); }, body_material_[b].model);
  const double G =
      std::visit([](const auto& m) { return m.shear_modulus(); }, body_material_[b].model);
  double u = 0.0;
  for (std::size_t p = P.body_begin[b]; p < P.body_begin[b + 1]; ++p) {
    const double mean = mean_stress(P.stress[p]);
    u += P.vol[p] * (0.5 * mean * mean / K + 0.5 * second_invariant(deviator(P.stress[p])) / G);
  }
  return u;
}

template <int D>
std::vector<std::uint32_t> Simulation<D>::probe_ids() const {
  std::vector<std::uint32_t> ids;
  for (const ProbeSpec& pr : case_data_.probes) {
    Vec<D> near;
    for (int d = 0; d < D; ++d)
      near[d] = pr.near[d];
    ids.push_back(particles_.id[nearest_particle(pr.body, near)]);
  }
  return ids;
}

template <int D>
std::size_t Simulation<D>::nearest_particle(int body, const Vec<D>& point) const {
  const auto& P = particles_;
  std::size_t best = P.body_begin[body];
  double best_d = inf;
  for (std::size_t p = P.body_begin[body]; p < P.body_begin[body + 1]; ++p) {
    const double d = (P.x[p] - point).squaredNorm();
    if (d < best_d) best_d = d, best = p;
  }
  return best;
}

template class Simulation<2>;
template class Simulation<3>;

} // namespace talus
