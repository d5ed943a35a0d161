// The stress update (eq. 24-28): each deformable particle's deformation gradient, volume and
// stress from its field's velocity gradient, through its material's pure update, and the
// bodies' stress work summed in a thread-count independent order.
#include "talus/setup/interface.hpp"
#include "talus/solver/detail.hpp"
#include "talus/solver/simulation.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <numeric>
#include <type_traits>
#include <variant>

namespace talus {

namespace {

// A particle's stress work over a step, midpoint rule: (V sigma) : D dt.
double stress_work(double vol_old, const Voigt& sigma_old, double vol, const Voigt& sigma,
                   const Mat3& D3, double dt) {
  const Voigt s = 0.5 * (vol_old * sigma_old + vol * sigma);
  return dt * (s[0] * D3(0, 0) + s[1] * D3(1, 1) + s[2] * D3(2, 2) +
               2.0 * (s[3] * D3(0, 1) + s[4] * D3(1, 2) + s[5] * D3(0, 2)));
}

} // namespace

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
  shape_.require(steps_, particles_.size());
  const double max_J = setup_.bodies[b].material.max_volume_ratio;
  const std::int64_t begin = P.body_begin[b], end = P.body_begin[b + 1];
  constexpr bool fluid = std::is_same_v<Model, Fluid>;
  std::atomic<std::size_t> bad{P.size()}, gone{StepCheck::no_particle};
  // Particles go in fixed chunks so that the stress work sums in an order that does not depend
  // on the thread count (chunk sums, then the chunks in order).
  const std::int64_t chunks = (end - begin + work_sums_.chunk - 1) / work_sums_.chunk;
  if (static_cast<std::int64_t>(work_sums_.chunk_work.size()) < chunks)
    work_sums_.chunk_work.resize(chunks);
  // On several processes the chunks are of global indices: each particle's work goes to the
  // exchange, which forms the chunk sums one process would.
  double* particle_work = nullptr;
  if (exchange_) {
    work_sums_.particle_work.resize(P.size());
    particle_work = work_sums_.particle_work.data();
  }
  // The chunks go out statically: each thread takes the same stretch of the particle order
  // every step, the one G2P and the scatter give it, so the particles' state stays in that
  // core's cache (handed out dynamically, each step's stretch came from the other core's).
#pragma omp parallel for schedule(static)
  for (std::int64_t c = 0; c < chunks; ++c) {
    double work = 0.0;
    for (std::int64_t p = begin + c * work_sums_.chunk;
         p < std::min(end, begin + (c + 1) * work_sums_.chunk); ++p) {
      if constexpr (fluid)
        if (P.m[p] == 0.0) continue; // gone through an outflow face: no stress, no work
      const ShapeWeights<D>& sw = shape_.weights[p];
      const BodyField<D>& N = fields_[P.field[p]];
      const Vec<D>* rate = (N.*velocity).data();
      // L = sum_I v_I (grad N_I)^T, summed in scalars: an Eigen matrix accumulated across the
      // node loop's variants stays in memory (a store-to-load chain per node).
      double l[D][D] = {};
      for_each_node(N.box, sw, [&](std::int64_t I, double, const Vec<D>& dN_I) {
        const Vec<D>& v = rate[I];
        for (int i = 0; i < D; ++i)
          for (int j = 0; j < D; ++j)
            l[i][j] += v[i] * dN_I[j];
      });
      Mat<D> L;
      for (int i = 0; i < D; ++i)
        for (int j = 0; j < D; ++j)
          L(i, j) = l[i][j];
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
      if constexpr (fluid) { // a state function of J; the fluid keeps no shape
        P.F[p] = Mat<D>::Identity() * std::pow(J, 1.0 / D);
        P.stress[p] = fluid_stress(model, model.pressure(J), D3);
      } else {
        talus::update_stress(model, P.stress[p], P.eps_p[p], D3, 0.5 * (L3 - L3.transpose()), dt);
      }
      const double w = stress_work(vol_old, sigma_old, P.vol[p], P.stress[p], D3, dt);
      work += w;
      if (particle_work) particle_work[p] = w;
      if (!P.stress[p].allFinite())
        detail::record_bad(gone, static_cast<std::size_t>(p), exchange_);
    }
    work_sums_.chunk_work[c] = work;
  }
  if (exchange_) {
    exchange_->chunk_sums(b, begin, end, particle_work, work_sums_.chunk,
                          work_sums_.chunk_work_global);
    for (const double w : work_sums_.chunk_work_global)
      internal_work_[b] += w;
  } else {
    for (std::int64_t c = 0; c < chunks; ++c)
      internal_work_[b] += work_sums_.chunk_work[c];
  }
  check_.bad_particle = std::min(check_.bad_particle, gone.load());
  // Reported at the step's end, so that every process reaches the step's collective points.
  if (const std::size_t p = bad.load(); p != P.size() && check_.pending_failure.empty())
    check_.pending_failure = fmt::format(
        "step {}, time {:.6g} s: body '{}', particle {} (id {}) at ({}): det F = {:.3g} <= 0 "
        "(the particle turned inside out; reduce the time step or check the case)",
        steps_, time_, setup_.bodies[b].name, one_process_index(p), P.id[p],
        fmt::join(P.x[p].data(), P.x[p].data() + D, ", "), P.F[p].determinant());
}

#define TALUS_INSTANTIATE(D)                                                                       \
  template void Simulation<D>::update_stress(std::vector<Vec<D>> BodyField<D>::*, double);
TALUS_INSTANTIATE(2)
TALUS_INSTANTIATE(3)

} // namespace talus
