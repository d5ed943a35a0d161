// The contact pass (eq. 29-37): at every node two or more bodies share,
// the node as the contact law sees it, each body's friction and bond there, the law, and with
// `record` the forces, work, contact nodes and interface slip rates it leaves behind.
#include "talus/case/geometry.hpp"
#include "talus/solver/detail.hpp"
#include "talus/solver/simulation.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace talus {

namespace {

using detail::heaviest_other;
using detail::is_slave;

// The global node range [lo, hi) where at least two bodies' frames overlap (the same on every
// process); false if none do. A node outside a body's stored box has none of its mass here.
// `pairs`: the pairs whose frames overlap, the only ones that can meet, as a * B + b for both
// orders, ascending.
template <int D>
bool shared_nodes(const std::vector<BodyField<D>>& fields, Index<D>& lo, Index<D>& hi,
                  std::vector<std::int64_t>& pairs) {
  const int B = static_cast<int>(fields.size());
  bool any = false;
  pairs.clear();
  for (int a = 0; a < B; ++a)
    for (int b = a + 1; b < B; ++b) {
      Index<D> l, h;
      bool overlap = true;
      for (int d = 0; d < D; ++d) {
        l[d] = std::max(fields[a].frame_offset[d], fields[b].frame_offset[d]);
        h[d] = std::min(fields[a].frame_offset[d] + fields[a].frame.nodes[d],
                        fields[b].frame_offset[d] + fields[b].frame.nodes[d]);
        overlap = overlap && l[d] < h[d];
      }
      if (!overlap) continue;
      pairs.push_back(std::int64_t{a} * B + b), pairs.push_back(std::int64_t{b} * B + a);
      for (int d = 0; d < D; ++d)
        lo[d] = any ? std::min(lo[d], l[d]) : l[d], hi[d] = any ? std::max(hi[d], h[d]) : h[d];
      any = true;
    }
  std::sort(pairs.begin(), pairs.end());
  return any;
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

// Each body's friction at the node is that of its pair with the heaviest other body there; on
// an interface pair the slave body's interface particles give the friction and the cohesive and
// tensile capacities (eq. 37), except in a pass on a strain's velocity (`bonds` false: see
// ContactPass). Settling with hold_interfaces holds a bond outright in every pass; with
// hold_contacts every pair sticks (unlimited friction).
template <int D>
void set_pair_properties(ContactNode<D>& node, const std::int64_t* local, const Setup<D>& setup,
                         const std::vector<BodyField<D>>& fields, bool settling, bool bonds) {
  for (int k = 0; k < node.n; ++k) {
    const int other = heaviest_other(node, k);
    node.mu[k] = setup.friction(node.body[k], node.body[other]);
    node.cohesion[k] = node.tension[k] = 0.0;
    if (const int f = setup.interface_of(node.body[k], node.body[other]); f >= 0) {
      const int s = is_slave(node, k, other) ? k : other;
      const BodyField<D>& S = fields[node.body[s]];
      const std::int64_t i = local[s] * S.slots + setup.slot(node.body[s], f);
      if (S.area[i] > 0.0) {
        node.mu[k] = S.friction_area[i] / S.area[i];
        if (bonds) node.cohesion[k] = S.cohesion[i], node.tension[k] = S.tension[i];
        if (settling && setup.hold_interfaces) node.cohesion[k] = node.tension[k] = inf;
      }
    }
    if (settling && setup.hold_contacts) node.mu[k] = inf;
  }
}

// Slip rate (eq. 38-39, as the interface's relative displacement), written to the node's slot of
// the body's interface with its partner (the heaviest other body there, whose friction and bond
// the node used; a third body sliding past is not the interface): where the node holds the
// bodies together, the tangential relative velocity after contact; where a bond has opened past
// its tensile capacity, the whole relative velocity (an opened bond breaks as sliding does, and
// does not heal). Weighted by how evenly the two bodies share the node's volume (m / rho),
// 4 s (1 - s), and not measured where either has less than min_slip_share of it: at such a
// fringe node one body's velocity is a force over a round-off mass (docs/formulation.md).
template <int D>
void measure_slip(const ContactNode<D>& node, const std::int64_t* local, const Setup<D>& setup,
                  std::vector<BodyField<D>>& fields, double dt) {
  for (int k = 0; k < node.n; ++k) {
    BodyField<D>& K = fields[node.body[k]];
    if (!K.needs.interfaces || !(node.closed[k] || node.opened[k])) continue;
    const int other = heaviest_other(node, k);
    const int f = setup.interface_of(node.body[k], node.body[other]);
    if (f < 0) continue; // no bond
    const std::int64_t j = local[k] * K.slots + setup.slot(node.body[k], f);
    // The normal force here per unit of body k's interface area: its particles' normal stress
    // (their bands' sigma_n). Only where the law corrected body k against its partner alone:
    // the pair meets alone (two bodies here, or one pair of a node resolved pair by pair), or the
    // partner is the node's rigid body. Under contact.node_law = "centre_of_mass" a node of three
    // deformable bodies gives body k's impulse against all the others, at a part's leading
    // corner the ram's, not the traction across this interface (docs/formulation.md, "Pore
    // pressure on an interface").
    if (K.needs.pressure && K.area[j] > 0.0 && (node.n == 2 || node.rigid[other]))
      K.normal_stress[j] = node.normal_impulse[k] / (dt * K.area[j]);
    const Vec<D> rel = node.v[k] - node.v[other];
    const Vec<D>& nrm = node.normal[k];
    const double rate = node.opened[k] ? rel.norm() : (rel - rel.dot(nrm) * nrm).norm();
    // The work of the tangential impulse over the slip here heats the bands of the slave body's
    // particles at the node (theirs set the friction), in proportion to N_I A^p (1 - r^p), their
    // share of the friction on the effective normal force: per unit of that weight. One band,
    // heated once; a node whose particles all carry no effective stress heats none.
    if (K.needs.heating && is_slave(node, k, other) && K.heat_weight[j] > 0.0)
      K.heat[j] = (node.friction_impulse[k] + node.cohesion_impulse[k]) * rate / K.heat_weight[j];
    const double v_k = node.m[k] / setup.bodies[node.body[k]].density;
    const double v_other = node.m[other] / setup.bodies[node.body[other]].density;
    const double s = v_other / (v_k + v_other);
    if (std::min(s, 1.0 - s) < detail::min_slip_share) continue; // a fringe: no velocity to trust
    const double share = 4.0 * s * (1.0 - s);
    K.slip_rate[j] = share * rate;
    K.slip_weight[j] = share;
  }
}

// The interface's pore pressure pushes the pair apart at the node (effective stress): the slave
// body k's pore force P_I (Simulation::share_interface_loads) as an impulse P_I dt along the
// contact normal, -P_I dt n on the slave and +P_I dt n on its partner (none on a rigid one), so
// that the contact that follows carries the effective normal force N - P and its friction is
// mu (N - p A). Returns the force applied to body k (N; 0 if none).
template <int D>
double push_pore(ContactNode<D>& node, const std::int64_t* local, const Setup<D>& setup,
                 const std::vector<BodyField<D>>& fields, int k, double dt) {
  const BodyField<D>& K = fields[node.body[k]];
  if (!K.needs.pressure || K.slots == 0) return 0.0;
  const int other = heaviest_other(node, k);
  const int f = setup.interface_of(node.body[k], node.body[other]);
  if (f < 0 || !setup.interface_pressure[f] || !is_slave(node, k, other)) return 0.0;
  const double P = K.pore_force[local[k] * K.slots + setup.slot(node.body[k], f)];
  if (P <= 0.0) return 0.0;
  const Vec<D> g = contact_direction(node, k);
  const double g_norm = g.norm();
  if (g_norm <= 0.0) return 0.0;
  const Vec<D> impulse = (P * dt / g_norm) * g;
  node.v[k] -= impulse / node.m[k];
  if (!node.rigid[other]) node.v[other] += impulse / node.m[other];
  return P;
}

// Body k of `from` as body j of `to` (its field's data at the node; the law's outputs are not
// copied).
template <int D>
void copy_body(const ContactNode<D>& from, int k, ContactNode<D>& to, int j) {
  to.body[j] = from.body[k], to.m[j] = from.m[k], to.v[j] = from.v[k];
  to.grad_m[j] = from.grad_m[k], to.x[j] = from.x[k], to.rigid[j] = from.rigid[k];
  to.rank[j] = from.rank[k], to.surface_normal[j] = from.surface_normal[k];
}

// Moves to `others` every rigid body of `node` but its heaviest (by nodal mass, the first of
// equals), and every rigid body apart[k] (its surface pair's partner is here), keeping the order.
template <int D>
void split_rigid_others(ContactNode<D>& node, std::int64_t* local, ContactNode<D>& others,
                        std::int64_t* others_local, const bool* apart) {
  int heaviest = -1, rigid = 0, away = 0;
  for (int k = 0; k < node.n; ++k)
    if (node.rigid[k] && apart[k]) {
      ++away;
    } else if (node.rigid[k]) {
      ++rigid;
      if (heaviest < 0 || node.m[k] > node.m[heaviest]) heaviest = k;
    }
  if (rigid < 2 && away == 0) return;
  int kept = 0;
  for (int k = 0; k < node.n; ++k) {
    if (node.rigid[k] && (apart[k] || (rigid >= 2 && k != heaviest))) {
      others_local[others.n] = local[k];
      copy_body(node, k, others, others.n++);
      continue;
    }
    if (kept != k) copy_body(node, k, node, kept), local[kept] = local[k];
    ++kept;
  }
  node.n = kept;
}

} // namespace

// The exact normal of body b's geometry at node g (moved with a rigid body's velocity); where g
// lies on an edge or corner of a box or a terrain body, its normal at `from`, where the other
// bodies' mass at the node lies (beside a wall standing on a floor, a node on the wall's foot
// has the side's normal for the water beside it; a floor's edge on the grid's face its top's).
// A body whose geometry stays put keeps each contact node's normal (an edge marked infinite and
// asked from `from` each time): per node row along x (allocated when first met; the row's
// thread alone touches it), per line of nodes along the last axis, the contiguous range of that
// line met so far. Its memory follows the contact surface, not the grid.
template <int D>
Vec<D> Simulation<D>::geometric_normal(int b, const Index<D>& g, const Vec<D>& from) {
  const BodySetup<D>& body = setup_.bodies[b];
  const bool moves = body.rigid && !body.rigid_velocity.isZero();
  bool edge = false;
  if (moves) {
    const Vec<D> shift = body.rigid_velocity * time_;
    const Vec<D> n =
        surface_normal<D>(*body.normal_geometry, Vec<D>(grid_.node_position(g) - shift), &edge);
    return edge ? surface_normal<D>(*body.normal_geometry, Vec<D>(from - shift)) : n;
  }
  std::vector<NormalLine<D>>& row = normal_cache_[b][g[0]];
  std::int64_t line = 0; // the line's index in the row: nodes[1] x ... x nodes[D - 2]
  for (int d = 1; d < D - 1; ++d)
    line = line * grid_.nodes[d] + g[d];
  if (row.empty()) row.resize(grid_.num_nodes() / (grid_.nodes[0] * grid_.nodes[D - 1]));
  NormalLine<D>& L = row[line];
  const std::int64_t z = g[D - 1];
  const Vec<D> unset = Vec<D>::Constant(std::numeric_limits<double>::quiet_NaN());
  if (L.normals.empty()) {
    L.first = z;
  } else if (z < L.first) {
    L.normals.insert(L.normals.begin(), L.first - z, unset);
    L.first = z;
  }
  const auto i = static_cast<std::size_t>(z - L.first);
  if (i >= L.normals.size()) L.normals.resize(i + 1, unset);
  Vec<D>& n = L.normals[i];
  if (std::isnan(n[0])) {
    n = surface_normal<D>(*body.normal_geometry, grid_.node_position(g), &edge);
    if (edge) n[0] = std::numeric_limits<double>::infinity();
  }
  return std::isinf(n[0]) ? surface_normal<D>(*body.normal_geometry, from) : n;
}

// Node by node, then the pairs of law = "surface" at their surface points (surface_contact.cpp).
template <int D>
void Simulation<D>::apply_contact(std::vector<Vec<D>> BodyField<D>::*velocity, double dt,
                                  ContactPass pass) {
  if (num_bodies() < 2) return;
  apply_node_contact(velocity, dt, pass);
  apply_surface_contact(velocity, dt, pass);
}

// Every pair but those of law = "surface". Reads m, grad m, mx, bond capacities and `velocity`;
// writes `velocity` and the momentum pass's record and slip rates, row by row along x.
template <int D>
void Simulation<D>::apply_node_contact(std::vector<Vec<D>> BodyField<D>::*velocity, double dt,
                                       ContactPass pass) {
  const bool record = pass == ContactPass::momentum;
  const int B = num_bodies();
  Index<D> lo, hi;
  std::vector<std::int64_t> pairs;
  const bool any = shared_nodes<D>(fields_, lo, hi, pairs);
  const std::int64_t rows = any ? hi[0] - lo[0] : 0;
  if (record) record_.begin(rows, setup_.record_contact_nodes, std::move(pairs));
  if (!any) return;
  // On several processes, only the rows this process's particles can complete: contact at a
  // node reads and writes that node (and its smoothing neighbours) alone.
  std::int64_t first = 0, last = rows;
  if (exchange_) {
    std::int64_t reach_lo, reach_hi;
    exchange_->plane_reach(reach_lo, reach_hi);
    first = std::clamp<std::int64_t>(reach_lo - lo[0], 0, rows);
    last = std::clamp<std::int64_t>(reach_hi - lo[0], first, rows);
  }
  // Static: each thread takes the same planes every step, about the stretch of x its scatter
  // wrote (scatter.hpp); the sums are per plane, then the planes in order.
#pragma omp parallel for schedule(static)
  for (std::int64_t r = first; r < last; ++r) {
    Index<D> g = lo;
    g[0] = lo[0] + r;
    // The rigid bodies beyond a node's heaviest, reset at each node (its entries are written by
    // split_rigid_others before they are read): one per row, not a zeroed one per node.
    ContactNode<D> rigid_others;
    std::int64_t rigid_local[max_bodies_at_node];
    while (true) {
      // Most nodes of the bodies' shared box hold one body or none: counted first, they are
      // passed over before the node is built (the law acts only where two bodies have mass).
      int with_mass = 0;
      for (int b = 0; b < B && with_mass < 2; ++b) {
        const std::int64_t i = fields_[b].local(g);
        with_mass += i >= 0 && fields_[b].m[i] > 0.0;
      }
      if (with_mass >= 2) {
        // The node as the law sees it: each body with mass here.
        ContactNode<D> node;
        std::int64_t local[max_bodies_at_node];
        for (int b = 0; b < B && node.n < max_bodies_at_node; ++b) {
          const std::int64_t i = fields_[b].local(g);
          if (i < 0 || fields_[b].m[i] <= 0.0) continue;
          const BodyField<D>& N = fields_[b];
          const BodySetup<D>& body = setup_.bodies[b];
          const int k = node.n++;
          node.body[k] = b, local[k] = i;
          node.m[k] = N.m[i];
          node.v[k] = (N.*velocity)[i];
          node.grad_m[k] = N.grad_m[i];
          node.x[k] = N.mx[i] / N.m[i];
          node.rigid[k] = body.rigid;
          node.rank[k] = detail::body_rank(body.mass, b);
          node.surface_normal[k].setZero();
        }
        // A node with two or more rigid bodies: the deformable bodies there meet the heaviest in
        // the node's own law and each other rigid body in a pair of its own, after it (below).
        rigid_others.n = 0;
        // A rigid body whose surface pair's deformable body is here leaves the node's own law.
        bool apart[max_bodies_at_node]{};
        for (int k = 0; k < node.n; ++k)
          for (int j = 0; j < node.n && node.rigid[k] && setup_.surface_rigid[node.body[k]]; ++j)
            apart[k] = apart[k] || (!node.rigid[j] && setup_.surface(node.body[j], node.body[k]));
        split_rigid_others(node, local, rigid_others, rigid_local, apart);
        const bool rigid_here =
            std::any_of(node.rigid, node.rigid + node.n, [](bool rigid) { return rigid; });
        if (node.n >= 3 && setup_.pairwise_nodes && !rigid_here) {
          resolve_pairwise(node, local, g, r, dt, velocity, pass);
        } else if (node.n >= 2) {
          for (int k = 0; k < node.n; ++k)
            if (setup_.bodies[node.body[k]].normal_geometry) { // from the others' mass here
              Vec<D> mx = Vec<D>::Zero();
              double m = 0.0;
              for (int j = 0; j < node.n; ++j)
                if (j != k) mx += node.m[j] * node.x[j], m += node.m[j];
              node.surface_normal[k] = geometric_normal(node.body[k], g, Vec<D>(mx / m));
            }
          // Normals from mass gradients smoothed over the neighbouring nodes: a lattice-sampled
          // surface's raw gradient tilts by a degree or more from node to node.
          if (const int radius = setup_.normal_smoothing; radius > 0)
            for (int k = 0; k < node.n; ++k)
              if (node.surface_normal[k].isZero())
                node.grad_m[k] = smoothed_gradient<D>(fields_[node.body[k]], g, radius);
          resolve_node(node, local, g, r, dt, velocity, pass);
        }
        // Each deformable body against each other rigid body, in body order, from the velocity
        // the node's law left: a body in a corner (a floor and a wall, a valley floor and a dam)
        // is held off both faces.
        for (int j = 0; j < rigid_others.n; ++j)
          for (int k = 0; k < node.n; ++k) {
            if (node.rigid[k]) continue;
            // A pair meeting at surface points (law = "surface") is apply_surface_contact's.
            if (setup_.surface_rigid[rigid_others.body[j]] &&
                setup_.surface(node.body[k], rigid_others.body[j]))
              continue;
            ContactNode<D> pair;
            std::int64_t pair_local[2] = {local[k], rigid_local[j]};
            pair.n = 2;
            copy_body(node, k, pair, 0);
            copy_body(rigid_others, j, pair, 1);
            if (setup_.bodies[pair.body[1]].normal_geometry)
              pair.surface_normal[1] = geometric_normal(pair.body[1], g, pair.x[0]);
            if (const int radius = setup_.normal_smoothing;
                radius > 0 && pair.surface_normal[1].isZero())
              pair.grad_m[1] = smoothed_gradient<D>(fields_[pair.body[1]], g, radius);
            resolve_node(pair, pair_local, g, r, dt, velocity, pass);
            node.v[k] = pair.v[0];
          }
      }
      int d = D - 1;
      while (d >= 1 && ++g[d] == hi[d])
        g[d] = lo[d], --d;
      if (d < 1) break;
    }
  }
  if (record && exchange_)
    record_.share_rows(
        lo[0], [&](std::int64_t i) { return exchange_->owns_plane(i); },
        [&](double* data, std::size_t n) { exchange_->sum_disjoint(data, n); });
  if (record) record_.end();
}

// A node three or more deformable bodies share (docs/formulation.md, "Three or more bodies at a
// node"): the two-body law on each pair in turn, lightest pair (by nodal mass) first, so that the
// heaviest, usually a part on the bedrock, is resolved last and holds exactly; each pair takes the
// normal grad m_a - grad m_b, which a corner of either does not tilt towards a third body. (With a
// rigid body at the node, the node's own law holds each body against its velocity.)
template <int D>
void Simulation<D>::resolve_pairwise(ContactNode<D>& node, const std::int64_t* local,
                                     const Index<D>& g, std::int64_t r, double dt,
                                     std::vector<Vec<D>> BodyField<D>::*velocity,
                                     ContactPass pass) {
  if (const int radius = setup_.normal_smoothing; radius > 0)
    for (int k = 0; k < node.n; ++k)
      if (!setup_.bodies[node.body[k]].normal_geometry)
        node.grad_m[k] = smoothed_gradient<D>(fields_[node.body[k]], g, radius);
  std::array<int, 2> order[max_bodies_at_node * (max_bodies_at_node - 1) / 2];
  int pairs = 0;
  for (int a = 0; a < node.n; ++a)
    for (int b = a + 1; b < node.n; ++b)
      order[pairs++] = {a, b};
  std::stable_sort(order, order + pairs, [&](const auto& p, const auto& q) {
    return node.m[p[0]] + node.m[p[1]] < node.m[q[0]] + node.m[q[1]];
  });
  // Each pair records the work of its own correction, m dv . (v^n + v) / 2 with v its
  // velocity after that pair; the node's work on a body is that of its whole change,
  // m (v_end - v_0) . (v^n + v_end) / 2, and the difference is added at the end.
  Vec<D> v0[max_bodies_at_node];
  double pair_work[max_bodies_at_node]{};
  for (int k = 0; k < node.n; ++k)
    v0[k] = node.v[k];
  for (int i = 0; i < pairs; ++i) {
    const auto [a, b] = order[i];
    ContactNode<D> pair;
    std::int64_t pair_local[2] = {local[a], local[b]};
    pair.n = 2;
    copy_body(node, a, pair, 0);
    copy_body(node, b, pair, 1);
    pair.symmetric = true;
    for (int k = 0; k < 2; ++k)
      if (setup_.bodies[pair.body[k]].normal_geometry)
        pair.surface_normal[k] = geometric_normal(pair.body[k], g, pair.x[1 - k]);
    resolve_node(pair, pair_local, g, r, dt, velocity, pass);
    for (const int k : {a, b}) {
      const Vec<D>& v_new = pair.v[k == a ? 0 : 1];
      const Vec<D>& v_start = fields_[node.body[k]].v[local[k]];
      pair_work[k] += node.m[k] * (v_new - node.v[k]).dot(0.5 * (v_start + v_new));
      node.v[k] = v_new;
    }
  }
  if (pass == ContactPass::momentum)
    for (int k = 0; k < node.n; ++k) {
      const Vec<D>& v_start = fields_[node.body[k]].v[local[k]];
      const double whole = node.m[k] * (node.v[k] - v0[k]).dot(0.5 * (v_start + node.v[k]));
      record_.add_work(r, node.body[k], whole - pair_work[k]);
    }
}

template <int D>
void Simulation<D>::resolve_node(ContactNode<D>& node, const std::int64_t* local, const Index<D>& g,
                                 std::int64_t r, double dt,
                                 std::vector<Vec<D>> BodyField<D>::*velocity, ContactPass pass) {
  const bool record = pass == ContactPass::momentum;
  set_pair_properties(node, local, setup_, fields_, settling_, pass != ContactPass::strain);
  Vec<D> before[max_bodies_at_node];
  for (int k = 0; k < node.n; ++k)
    before[k] = node.v[k];
  // The pore pressure's push, once a step (on v^{n+1}), before the contact law.
  double pore[max_bodies_at_node]{};
  bool pushed = false;
  if (record && setup_.pore_pressure)
    for (int k = 0; k < node.n; ++k)
      pushed = (pore[k] = push_pore(node, local, setup_, fields_, k, dt)) > 0.0 || pushed;
  if (resolve_contact(node, setup_.contact_law, dt) || pushed) {
    for (int k = 0; k < node.n; ++k) {
      (fields_[node.body[k]].*velocity)[local[k]] = node.v[k];
      if (!record) continue;
      const int other = heaviest_other(node, k);
      const Vec<D> dp = node.m[k] * (node.v[k] - before[k]);
      record_.add_force(r, node.body[k], node.body[other], dp / dt);
      // The contact's work on the body over the step: its impulse times the node's mean
      // velocity over the step, (v^n + v^{n+1}) / 2, the velocity the particles move with.
      const Vec<D>& v_start = fields_[node.body[k]].v[local[k]];
      record_.add_work(r, node.body[k],
                       node.m[k] * (node.v[k] - before[k]).dot(0.5 * (v_start + node.v[k])));
      if (setup_.record_contact_nodes && node.v[k] != before[k])
        record_.add_node(r, {grid_.node_position(g), node.body[k], node.body[other],
                             Vec<D>(dp / dt), node.normal[k], node.friction_impulse[k] / dt,
                             node.cohesion_impulse[k] / dt});
      const int f = setup_.interface_of(node.body[k], node.body[other]);
      if (f >= 0 && is_slave(node, k, other)) // the slave side, counted once
        record_.add_interface(r, f, node.cohesion_impulse[k] / dt, node.friction_impulse[k] / dt,
                              node.normal_impulse[k] / dt + pore[k]); // N = N' + P
    }
  }
  if (record) measure_slip(node, local, setup_, fields_, dt);
}

#define TALUS_INSTANTIATE(D)                                                                       \
  template void Simulation<D>::apply_contact(std::vector<Vec<D>> BodyField<D>::*, double,          \
                                             ContactPass);                                         \
  template void Simulation<D>::resolve_pairwise(ContactNode<D>&, const std::int64_t*,              \
                                                const Index<D>&, std::int64_t, double,             \
                                                std::vector<Vec<D>> BodyField<D>::*, ContactPass); \
  template void Simulation<D>::resolve_node(ContactNode<D>&, const std::int64_t*, const Index<D>&, \
                                            std::int64_t, double,                                  \
                                            std::vector<Vec<D>> BodyField<D>::*, ContactPass);
TALUS_INSTANTIATE(2)
TALUS_INSTANTIATE(3)

} // namespace talus
