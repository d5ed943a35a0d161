// Orphans (contact.orphan_fraction; docs/formulation.md "Orphan particles").
#include "talus/solver/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace talus {

// Reads the fields' masses and the shape-weight cache; writes each particle's field. A deformable
// body's particle cut off from its body inside another one cannot be resolved as a surface of its
// own: alone in its field, its stress acts on nodes that carry only its mass while contact with
// the body around it keeps squeezing it. So a particle whose own-body neighbours put less than
// orphan_fraction of a filled cell's mass (rho_0 h^D) on its nodes, while another deformable body
// puts at least a quarter of it there and more than its own body, maps to that body's field from
// the next step on: it moves with the body around it (one velocity field, as in single-field
// MPM) and keeps its own material, stress and body. It returns to its own field when its own
// body's neighbours put twice the fraction there (hysteresis). Decided at the end of every
// orphan_interval-th step from that step's nodal masses and start-of-step weights, for the steps
// that follow; deterministic.
template <int D>
void Simulation<D>::update_orphans() {
  const double fraction = setup_.orphan_fraction;
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
    if (setup_.bodies[b].rigid) continue;
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
          if (c == b || setup_.bodies[c].rigid) continue;
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

#define TALUS_INSTANTIATE(D)                                                                       \
  template void Simulation<D>::update_orphans();                                                   \
  template std::int64_t Simulation<D>::orphans() const;
TALUS_INSTANTIATE(2)
TALUS_INSTANTIATE(3)

} // namespace talus
