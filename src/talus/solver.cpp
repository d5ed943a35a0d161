#include "talus/solver.hpp"

#include "talus/case/geometry.hpp"
#include "talus/shape.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <fmt/format.h>
#include <numeric>
#include <variant>

namespace talus {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

template <class T>
void permute(std::vector<T>& a, const std::vector<std::uint32_t>& order) {
  std::vector<T> tmp(a.size());
  for (std::size_t i = 0; i < order.size(); ++i)
    tmp[i] = a[order[i]];
  a.swap(tmp);
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
  nodes_.resize(static_cast<std::size_t>(grid_.num_nodes()));
  for (const BodySpec& b : c.bodies) {
    body_material_.push_back(c.materials[b.material]);
    body_lp_.push_back(0.5 * c.grid.cell_size / b.particles_per_cell);
  }
  conditions_ = build_grid_conditions<D>(c, grid_);
  for (int d = 0; d < D; ++d)
    gravity_[d] = c.simulation.gravity[d];
  // Slab width: GIMP writes nodes [cell-1, cell+2], so slabs of 4 cells keep two slabs of one
  // colour at least one slab apart.
  slab_width_ = 4;
  num_slabs_ = (grid_.cells[0] + slab_width_ - 1) / slab_width_;
  bin_offset_.assign(static_cast<std::size_t>(num_slabs_ * particles_.num_bodies() + 1), 0);
}

template <int D>
double Simulation<D>::compute_time_step() const {
  const auto& P = particles_;
  double max_speed = 0.0;
  for (int b = 0; b < P.num_bodies(); ++b) {
    const double modulus = body_material_[b].p_wave_modulus();
    const std::int64_t begin = P.body_begin[b], end = P.body_begin[b + 1];
#pragma omp parallel for reduction(max : max_speed) schedule(static)
    for (std::int64_t p = begin; p < end; ++p) {
      const double c = std::sqrt(modulus * P.vol[p] / P.m[p]);
      max_speed = std::max(max_speed, c + P.v[p].norm());
    }
  }
  double dt = case_data_.simulation.dt ? *case_data_.simulation.dt
                                       : case_data_.simulation.cfl * grid_.h / max_speed;
  return std::min(dt, case_data_.simulation.dt_max);
}

template <int D>
void Simulation<D>::check_particles() const {
  const auto& P = particles_;
  std::atomic<std::size_t> bad{P.size()};
  const Vec<D> lo = grid_.origin, hi = grid_.upper();
#pragma omp parallel for schedule(static)
  for (std::int64_t p = 0; p < static_cast<std::int64_t>(P.size()); ++p) {
    const bool ok = P.x[p].allFinite() && P.v[p].allFinite() && P.stress[p].allFinite() &&
                    (P.x[p].array() >= lo.array()).all() && (P.x[p].array() <= hi.array()).all();
    if (!ok) record_bad(bad, static_cast<std::size_t>(p));
  }
  const std::size_t p = bad.load();
  if (p == P.size()) return;
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
  std::vector<std::uint32_t> order(P.size());
  std::iota(order.begin(), order.end(), 0u);
  std::vector<std::int64_t> key(P.size());
  for (std::size_t p = 0; p < P.size(); ++p)
    key[p] = grid_.cell_index(grid_.cell_of(P.x[p]));
  for (int b = 0; b < P.num_bodies(); ++b)
    std::stable_sort(order.begin() + P.body_begin[b], order.begin() + P.body_begin[b + 1],
                     [&](std::uint32_t i, std::uint32_t j) { return key[i] < key[j]; });
  P.for_each_array([&](auto& a) { permute(a, order); });
}

template <int D>
void Simulation<D>::bin_particles_by_slab() {
  const auto& P = particles_;
  const int B = P.num_bodies();
  const std::size_t n = P.size();
  particle_bin_.resize(n);
  bin_index_.resize(n);
  std::fill(bin_offset_.begin(), bin_offset_.end(), 0);
  for (int b = 0; b < B; ++b) {
    for (std::size_t p = P.body_begin[b]; p < P.body_begin[b + 1]; ++p) {
      const double xi = (P.x[p][0] - grid_.origin[0]) / grid_.h;
      const std::int64_t s =
          std::clamp<std::int64_t>(static_cast<std::int64_t>(xi) / slab_width_, 0, num_slabs_ - 1);
      particle_bin_[p] = static_cast<std::uint32_t>(s * B + b);
      ++bin_offset_[particle_bin_[p] + 1];
    }
  }
  std::partial_sum(bin_offset_.begin(), bin_offset_.end(), bin_offset_.begin());
  std::vector<std::size_t> fill(bin_offset_.begin(), bin_offset_.end() - 1);
  for (std::size_t p = 0; p < n; ++p)
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

template <int D>
void Simulation<D>::clear_nodes() {
  auto& N = nodes_;
  const std::int64_t n = static_cast<std::int64_t>(N.size());
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < n; ++i) {
    N.m[i] = 0.0;
    N.p[i].setZero();
    N.f[i].setZero();
  }
}

// P2G, eq. 14-18: mass, momentum and (optionally) internal and external force.
template <int D>
void Simulation<D>::map_particles_to_nodes(bool with_forces) {
  auto& P = particles_;
  auto& N = nodes_;
  const ShapeKind kind = case_data_.grid.shape;
  scatter([&](std::uint32_t p, int b) {
    const ShapeWeights<D> sw = evaluate_shape(grid_, kind, body_lp_[b], P.x[p]);
    const double m_p = P.m[p];
    const Vec<D> mv_p = m_p * P.v[p];
    const Mat<D> Vsigma = P.vol[p] * in_plane<D>(to_tensor(P.stress[p]));
    const Vec<D> mg = m_p * gravity_;
    for_each_node(grid_, sw, [&](std::int64_t I, double N_I, const Vec<D>& dN_I) {
      N.m[I] += N_I * m_p;
      N.p[I] += N_I * mv_p;
      if (with_forces) N.f[I] += N_I * mg - Vsigma * dN_I;
    });
  });
}

template <int D>
void Simulation<D>::map_forces_to_nodes() {
  auto& P = particles_;
  auto& N = nodes_;
  const ShapeKind kind = case_data_.grid.shape;
  scatter([&](std::uint32_t p, int b) {
    const ShapeWeights<D> sw = evaluate_shape(grid_, kind, body_lp_[b], P.x[p]);
    const Mat<D> Vsigma = P.vol[p] * in_plane<D>(to_tensor(P.stress[p]));
    const Vec<D> mg = P.m[p] * gravity_;
    for_each_node(grid_, sw, [&](std::int64_t I, double N_I, const Vec<D>& dN_I) {
      N.f[I] += N_I * mg - Vsigma * dN_I;
    });
  });
}

// MUSL: momentum of the updated particle velocities, re-mapped for the strain rate.
template <int D>
void Simulation<D>::map_momentum_to_nodes() {
  auto& P = particles_;
  auto& N = nodes_;
  const ShapeKind kind = case_data_.grid.shape;
  const std::int64_t n = static_cast<std::int64_t>(N.size());
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < n; ++i)
    N.p[i].setZero();
  scatter([&](std::uint32_t p, int b) {
    const ShapeWeights<D> sw = evaluate_shape(grid_, kind, body_lp_[b], P.x[p]);
    const Vec<D> mv_p = P.m[p] * P.v[p];
    for_each_node(grid_, sw,
                  [&](std::int64_t I, double N_I, const Vec<D>&) { N.p[I] += N_I * mv_p; });
  });
#pragma omp parallel for schedule(static)
  for (std::int64_t i = 0; i < n; ++i)
    N.v_remap[i] = N.m[i] > 0.0 ? Vec<D>(N.p[i] / N.m[i]) : Vec<D>::Zero();
  apply_grid_conditions<D>(conditions_, N.v_remap);
}

// Grid update, eq. 19-20: v^n = p/m and v^{n+1} = v^n + f/m dt, with local damping and the
// velocity conditions applied to both.
template <int D>
void Simulation<D>::compute_node_velocities(double dt) {
  auto& N = nodes_;
  const double alpha = case_data_.simulation.damping;
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
  apply_grid_conditions<D>(conditions_, N.v);
  apply_grid_conditions<D>(conditions_, N.v_new);
}

// G2P. With `velocity`, the particle velocity takes the FLIP/PIC blend of the grid change (eq. 22);
// with `move`, the particle moves with the mean of v^n and v^{n+1} (eq. 23; exact for a constant
// acceleration); with a strain-rate field, its gradient L updates F, volume and stress (eq. 24-28).
template <int D>
void Simulation<D>::map_nodes_to_particles(double dt, const Gather& what) {
  for (int b = 0; b < particles_.num_bodies(); ++b) {
    if (what.strain_rate_field)
      std::visit([&](const auto& model) { map_nodes_to_body(b, dt, what, &model); },
                 body_material_[b].model);
    else
      map_nodes_to_body<LinearElastic>(b, dt, what, nullptr);
  }
}

template <int D>
template <class Model>
void Simulation<D>::map_nodes_to_body(int b, double dt, const Gather& what, const Model* model) {
  auto& P = particles_;
  const auto& N = nodes_;
  const ShapeKind kind = case_data_.grid.shape;
  const double flip = case_data_.simulation.flip;
  const double lp = body_lp_[b];
  const std::int64_t begin = P.body_begin[b], end = P.body_begin[b + 1];
  std::atomic<std::size_t> bad{P.size()};
#pragma omp parallel for schedule(static)
  for (std::int64_t p = begin; p < end; ++p) {
    const ShapeWeights<D> sw = evaluate_shape(grid_, kind, lp, P.x[p]);
    Vec<D> v_old = Vec<D>::Zero(), v_new = Vec<D>::Zero();
    Mat<D> L = Mat<D>::Zero();
    for_each_node(grid_, sw, [&](std::int64_t I, double N_I, const Vec<D>& dN_I) {
      if (what.velocity || what.move) {
        v_old += N_I * N.v[I];
        v_new += N_I * N.v_new[I];
      }
      if (what.strain_rate_field) L += (*what.strain_rate_field)[I] * dN_I.transpose();
    });
    if (what.velocity) P.v[p] = flip * (P.v[p] + v_new - v_old) + (1.0 - flip) * v_new;
    if (what.move) P.x[p] += 0.5 * dt * (v_old + v_new);
    if (model) {
      P.F[p] = (Mat<D>::Identity() + L * dt) * P.F[p];
      const double J = P.F[p].determinant();
      if (!(J > 0.0)) record_bad(bad, static_cast<std::size_t>(p));
      P.vol[p] = P.vol0[p] * J;
      const Mat3 L3 = embed<D>(L);
      update_stress(*model, P.stress[p], P.eps_p[p], 0.5 * (L3 + L3.transpose()),
                    0.5 * (L3 - L3.transpose()), dt);
    }
  }
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
  check_particles();
  dt_ = std::min(compute_time_step(), dt_limit);
  if (steps_ % sort_interval_ == 0) sort_particles_by_cell();
  bin_particles_by_slab();
  clear_nodes();
  phase_times_.other += seconds_since(t0);

  auto timed = [](double& acc, auto&& phase) {
    const auto t = Clock::now();
    phase();
    acc += seconds_since(t);
  };
  auto& T = phase_times_;
  switch (case_data_.simulation.scheme) {
  case Scheme::usf: // stress first, from the velocity of the mapped momentum
    timed(T.p2g, [&] { map_particles_to_nodes(false); });
    timed(T.grid, [&] { compute_node_velocities(0.0); });
    timed(T.stress, [&] { map_nodes_to_particles(dt_, {.strain_rate_field = &nodes_.v}); });
    timed(T.p2g, [&] { map_forces_to_nodes(); });
    timed(T.grid, [&] { compute_node_velocities(dt_); });
    timed(T.g2p, [&] { map_nodes_to_particles(dt_, {.velocity = true, .move = true}); });
    break;
  case Scheme::usl: // stress last, from the updated grid velocity
    timed(T.p2g, [&] { map_particles_to_nodes(true); });
    timed(T.grid, [&] { compute_node_velocities(dt_); });
    timed(T.g2p, [&] {
      map_nodes_to_particles(dt_,
                             {.velocity = true, .move = true, .strain_rate_field = &nodes_.v_new});
    });
    break;
  case Scheme::musl: // stress last, from the velocity re-mapped from the updated particles
    timed(T.p2g, [&] { map_particles_to_nodes(true); });
    timed(T.grid, [&] { compute_node_velocities(dt_); });
    timed(T.g2p, [&] { map_nodes_to_particles(dt_, {.velocity = true}); });
    timed(T.p2g, [&] { map_momentum_to_nodes(); });
    timed(T.stress, [&] {
      map_nodes_to_particles(dt_, {.move = true, .strain_rate_field = &nodes_.v_remap});
    });
    break;
  }
  time_ += dt_;
  ++steps_;
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
