// Contact at surface points ([[contact]] law = "surface"; docs/formulation.md has the equations).
#include "talus/case/geometry.hpp"
#include "talus/solver/simulation.hpp"

#include <algorithm>
#include <cmath>

namespace talus {

// From the seeded positions: each particle within a spacing of its body's surface gets r_0 to the
// surface points that near (the lattice's outer row, so every face has points); each pair's anchor.
template <int D>
void Simulation<D>::build_surface_points() {
  surface_points_.clear();
  surface_anchors_.clear();
  const auto& P = particles_;
  std::vector<Vec<D>> near;
  for (const auto& pair : setup_.surface_pairs) {
    const std::size_t first = P.body_begin[pair.rigid];
    surface_anchors_.push_back({P.id[first], P.x[first]});
    if (std::any_of(surface_points_.begin(), surface_points_.end(),
                    [&](const SurfacePoint& s) { return s.body == pair.body; }))
      continue; // one set per body, whatever rigid bodies it meets
    const double within = setup_.bodies[pair.body].particle_height;
    for (std::size_t p = P.body_begin[pair.body]; p < P.body_begin[pair.body + 1]; ++p) {
      near.clear();
      surface_points_near<D>(pair.shape, P.x0[p], within, near);
      for (const Vec<D>& q : near)
        surface_points_.push_back({P.id[p], pair.body, Vec<D>(q - P.x0[p])});
    }
  }
  // In id order: the same points in the same order after a restart.
  std::stable_sort(surface_points_.begin(), surface_points_.end(),
                   [](const SurfacePoint& a, const SurfacePoint& b) { return a.id < b.id; });
}

// Reads positions, F, weights, masses and `velocity`; writes `velocity` (and the momentum pass's
// force and work). The step's first pass finds the constraints; its later passes reuse them.
template <int D>
void Simulation<D>::apply_surface_contact(std::vector<Vec<D>> BodyField<D>::*velocity, double dt,
                                          ContactPass pass) {
  if (setup_.surface_pairs.empty()) return;
  const auto& P = particles_;
  const bool record = pass == ContactPass::momentum;
  if (surface_step_ != steps_) { // the step's first pass finds the points near a rigid shape
    surface_step_ = steps_;
    shape_.require(steps_, P.size());
    surface_rows_.clear();
    surface_nodes_.clear();
    for (std::size_t k = 0; k < setup_.surface_pairs.size(); ++k) {
      const auto& pair = setup_.surface_pairs[k];
      const BodyField<D>& N = fields_[pair.body];
      // The rigid shape moved as its body did (settling included): x - x_seeded of its anchor.
      const SurfaceAnchor& anchor = surface_anchors_[k];
      const Vec<D> shift = P.x[index_of_id_[anchor.id]] - anchor.x;
      const double reach = 0.5 * grid_.h;
      for (const SurfacePoint& s : surface_points_) {
        if (s.body != pair.body) continue;
        const std::size_t p = index_of_id_[s.id];
        if (P.field[p] != pair.body) continue; // an orphan moves in another body's field
        const Vec<D> r = P.F[p] * s.offset;
        SurfaceRow row;
        row.gap = signed_distance<D>(pair.rigid_shape, Vec<D>(P.x[p] + r - shift), row.normal);
        if (row.gap >= reach) continue;
        row.pair = static_cast<int>(k);
        row.first = surface_nodes_.size();
        for_each_node(N.box, shape_.weights[p], [&](std::int64_t I, double N_I, const Vec<D>& dN) {
          if (N.m[I] <= 0.0) return;
          const double a = N_I + dN.dot(r);
          surface_nodes_.push_back({I, a});
          row.inverse_mass += a * a / N.m[I];
        });
        row.count = surface_nodes_.size() - row.first;
        if (row.inverse_mass > 0.0)
          surface_rows_.push_back(row);
        else
          surface_nodes_.resize(row.first);
      }
    }
  }
  if (surface_rows_.empty()) return;
  // The nodes the points move, with their velocities before (the work record).
  std::vector<std::pair<std::int64_t, Vec<D>>> before;
  auto key = [&](const SurfaceRow& row) { return setup_.surface_pairs[row.pair].body; };
  if (record)
    for (const SurfaceRow& row : surface_rows_)
      for (std::size_t j = row.first; j < row.first + row.count; ++j)
        before.push_back({surface_nodes_[j].node * num_bodies() + key(row), Vec<D>::Zero()});
  std::sort(before.begin(), before.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  before.erase(std::unique(before.begin(), before.end(),
                           [](const auto& a, const auto& b) { return a.first == b.first; }),
               before.end());
  for (auto& [k, v] : before)
    v = (fields_[k % num_bodies()].*velocity)[k / num_bodies()];

  // Projected Gauss-Seidel: lambda_n >= 0 with u_n >= -g / dt, |lambda_t| <= mu lambda_n; J to node
  // I as a_I J / m_I.
  std::vector<Vec<D>> impulse(surface_rows_.size(), Vec<D>::Zero());
  constexpr int max_sweeps = 50;
  constexpr double push_out = 0.2;
  for (int sweep = 0; sweep < max_sweeps; ++sweep) {
    double change = 0.0, largest = 0.0;
    for (std::size_t c = 0; c < surface_rows_.size(); ++c) {
      const SurfaceRow& row = surface_rows_[c];
      const auto& pair = setup_.surface_pairs[row.pair];
      BodyField<D>& N = fields_[pair.body];
      std::vector<Vec<D>>& v = N.*velocity;
      Vec<D> u = -setup_.bodies[pair.rigid].rigid_velocity;
      for (std::size_t j = row.first; j < row.first + row.count; ++j)
        u += surface_nodes_[j].a * v[surface_nodes_[j].node];
      const Vec<D>& n = row.normal;
      const double bias = row.gap > 0.0 ? row.gap / dt : push_out * row.gap / dt;
      const Vec<D> old = impulse[c];
      const double old_n = old.dot(n);
      const double new_n = std::max(0.0, old_n - (u.dot(n) + bias) / row.inverse_mass);
      Vec<D> old_t = old - old_n * n;
      Vec<D> new_t = old_t - (u - u.dot(n) * n) / row.inverse_mass;
      // Held while settling with hold_contacts: unlimited friction, only where pressed (inf x 0).
      const double mu =
          settling_ && setup_.hold_contacts ? inf : setup_.friction(pair.body, pair.rigid);
      const double limit = new_n > 0.0 ? mu * new_n : 0.0;
      if (const double t = new_t.norm(); t > limit) new_t *= limit / t;
      impulse[c] = new_n * n + new_t;
      const Vec<D> dJ = impulse[c] - old;
      for (std::size_t j = row.first; j < row.first + row.count; ++j)
        v[surface_nodes_[j].node] += (surface_nodes_[j].a / N.m[surface_nodes_[j].node]) * dJ;
      change = std::max(change, dJ.norm());
      largest = std::max(largest, impulse[c].norm());
    }
    if (change <= 1e-12 * largest) break;
  }
  if (!record) return;
  // The pair's force on the body and the contact's work on it, m dv . (v^n + v^{n+1}) / 2.
  for (const auto& [k, v_before] : before) {
    const int b = static_cast<int>(k % num_bodies());
    const std::int64_t I = k / num_bodies();
    const BodyField<D>& N = fields_[b];
    const Vec<D>& v = (N.*velocity)[I];
    record_.work[b] += N.m[I] * (v - v_before).dot(0.5 * (N.v[I] + v));
  }
  for (std::size_t c = 0; c < surface_rows_.size(); ++c) {
    const auto& pair = setup_.surface_pairs[surface_rows_[c].pair];
    record_.add_pair_force(pair.body, pair.rigid, impulse[c] / dt);
  }
}

#define TALUS_INSTANTIATE(D)                                                                       \
  template void Simulation<D>::build_surface_points();                                             \
  template void Simulation<D>::apply_surface_contact(std::vector<Vec<D>> BodyField<D>::*, double,  \
                                                     ContactPass);
TALUS_INSTANTIATE(2)
TALUS_INSTANTIATE(3)

} // namespace talus
