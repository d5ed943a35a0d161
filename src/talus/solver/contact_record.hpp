// ContactRecord<D>: what the recorded contact pass of a step leaves behind (per-pair forces,
// interface totals, each body's contact work, the contact-node rows) and its time means. The
// contact pass visits node rows in parallel; each row sums into its own slot and the rows are
// then added in row order, so the totals do not depend on the thread count.
#pragma once

#include "talus/core/math.hpp"

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace talus {

// Total forces of an interface pair in one step (N, per unit thickness in 2D): the cohesive and
// frictional parts of the tangential resistance and the normal force (paper Figure 5a).
struct InterfaceForce {
  double cohesive = 0, frictional = 0, normal = 0;
};

// The contact force on one body at one node in the last step (output.contact_nodes).
template <int D>
struct ContactNodeForce {
  Vec<D> position = Vec<D>::Zero();    // the node
  int body = 0, other = 0;             // the corrected body, and the heaviest other body there
  Vec<D> force = Vec<D>::Zero();       // m (v_after - v_before) / dt on `body`
  Vec<D> normal = Vec<D>::Zero();      // outward from `body`
  double frictional = 0, cohesive = 0; // tangential resistance used (N)
};

// Contact nodes as 3 D + 4 doubles each (for checkpoints: no padding bytes), and back (whole
// nodes: v.size() a multiple of 3 D + 4).
template <int D>
std::vector<double> flatten(const std::vector<ContactNodeForce<D>>& nodes) {
  std::vector<double> v;
  for (const ContactNodeForce<D>& n : nodes) {
    v.insert(v.end(), n.position.data(), n.position.data() + D);
    v.push_back(n.body), v.push_back(n.other);
    v.insert(v.end(), n.force.data(), n.force.data() + D);
    v.insert(v.end(), n.normal.data(), n.normal.data() + D);
    v.push_back(n.frictional), v.push_back(n.cohesive);
  }
  return v;
}
template <int D>
std::vector<ContactNodeForce<D>> unflatten(const std::vector<double>& v) {
  constexpr std::size_t size = 3 * D + 4;
  std::vector<ContactNodeForce<D>> nodes(v.size() / size);
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const double* a = v.data() + i * size;
    ContactNodeForce<D>& n = nodes[i];
    for (int d = 0; d < D; ++d)
      n.position[d] = a[d], n.force[d] = a[D + 2 + d], n.normal[d] = a[2 * D + 2 + d];
    n.body = static_cast<int>(a[D]), n.other = static_cast<int>(a[D + 1]);
    n.frictional = a[3 * D + 2], n.cohesive = a[3 * D + 3];
  }
  return nodes;
}

template <int D>
struct ContactRecord {
  int B = 0;                                     // bodies
  std::vector<Vec<D>> force_;                    // B x B, last step: on a from b at [a * B + b]
  std::vector<Vec<D>> impulse_;                  // B x B, since reset_means()
  std::vector<InterfaceForce> interface_force;   // per interface, last step
  std::vector<InterfaceForce> interface_impulse; // per interface, since reset_means()
  double impulse_time = 0.0;
  std::vector<double> work; // per body since release: the contact's work on it

  void resize(int bodies, std::size_t interfaces) {
    B = bodies;
    force_.assign(B * B, Vec<D>::Zero());
    impulse_.assign(B * B, Vec<D>::Zero());
    interface_force.assign(interfaces, InterfaceForce{});
    interface_impulse.assign(interfaces, InterfaceForce{});
    work.assign(B, 0.0);
  }

  const Vec<D>& force(int a, int b) const { return force_[a * B + b]; }
  // The time mean since reset_means() (the last step's if no time has passed).
  Vec<D> mean_force(int a, int b) const {
    return impulse_time > 0 ? Vec<D>(impulse_[a * B + b] / impulse_time) : force(a, b);
  }
  InterfaceForce mean_interface_force(std::size_t f) const {
    if (impulse_time <= 0) return interface_force[f];
    const InterfaceForce& I = interface_impulse[f];
    return {I.cohesive / impulse_time, I.frictional / impulse_time, I.normal / impulse_time};
  }
  void reset_means() {
    std::fill(impulse_.begin(), impulse_.end(), Vec<D>::Zero());
    std::fill(interface_impulse.begin(), interface_impulse.end(), InterfaceForce{});
    impulse_time = 0.0;
  }

  // The step's recorded pass starts: last step's forces and nodes go; `rows` node rows follow,
  // in which only `pairs` (a * B + b, ascending: the pairs whose boxes overlap) can meet. Each
  // row sums per pair that can meet, not per B x B: 2,000 bodies cost their neighbours, not 4e6
  // slots per row.
  void begin(std::int64_t rows, bool with_nodes, std::vector<std::int64_t> pairs = {}) {
    std::fill(force_.begin(), force_.end(), Vec<D>::Zero());
    std::fill(interface_force.begin(), interface_force.end(), InterfaceForce{});
    for (auto& row : node_rows_)
      row.clear(); // keeps the capacity: no allocation once warmed up
    rows_ = rows;
    pairs_ = std::move(pairs);
    if (rows == 0) return;
    force_rows_.assign(rows * static_cast<std::int64_t>(pairs_.size()), Vec<D>::Zero());
    work_rows_.assign(rows * B, 0.0);
    if (with_nodes && static_cast<std::int64_t>(node_rows_.size()) < rows) node_rows_.resize(rows);
    interface_rows_.assign(rows * interface_force.size(), InterfaceForce{});
  }
  // Row r's contributions: body k's contact force from `other` and work, an interface's forces
  // (slave side), a contact node.
  void add_force(std::int64_t r, int k, int other, const Vec<D>& f) {
    const std::int64_t key = std::int64_t{k} * B + other;
    const auto at = std::lower_bound(pairs_.begin(), pairs_.end(), key);
    if (at == pairs_.end() || *at != key)
      throw std::logic_error("contact between bodies whose boxes do not overlap");
    force_rows_[r * static_cast<std::int64_t>(pairs_.size()) + (at - pairs_.begin())] += f;
  }
  void add_work(std::int64_t r, int k, double w) { work_rows_[r * B + k] += w; }
  // A force on body k from `other` outside the node rows (after end(): law = "surface").
  void add_pair_force(int k, int other, const Vec<D>& f) { force_[k * B + other] += f; }
  void add_interface(std::int64_t r, int f, double cohesive, double frictional, double normal) {
    InterfaceForce& row = interface_rows_[r * interface_force.size() + f];
    row.cohesive += cohesive, row.frictional += frictional, row.normal += normal;
  }
  void add_node(std::int64_t r, const ContactNodeForce<D>& n) { node_rows_[r].push_back(n); }
  // The rows summed in row order into the step's totals and the bodies' work.
  void end() {
    const std::size_t P = pairs_.size();
    for (std::int64_t r = 0; r < rows_; ++r)
      for (std::size_t s = 0; s < P; ++s)
        force_[pairs_[s]] += force_rows_[r * P + s];
    for (std::int64_t r = 0; r < rows_; ++r)
      for (int b = 0; b < B; ++b)
        work[b] += work_rows_[r * B + b];
    const std::size_t F = interface_force.size();
    for (std::size_t f = 0; f < F; ++f) {
      interface_force[f] = InterfaceForce{};
      for (std::int64_t r = 0; r < rows_; ++r) {
        interface_force[f].cohesive += interface_rows_[r * F + f].cohesive;
        interface_force[f].frictional += interface_rows_[r * F + f].frictional;
        interface_force[f].normal += interface_rows_[r * F + f].normal;
      }
    }
  }
  // On several processes (solver/exchange.hpp): only the rows of node planes this process
  // owns stay (row r is plane first_plane + r), then sum_disjoint adds every process's rows, one
  // owner per row, so that end() sums the rows one process would form.
  template <class Owns, class SumDisjoint>
  void share_rows(std::int64_t first_plane, Owns&& owns, SumDisjoint&& sum_disjoint) {
    const std::size_t F = interface_force.size();
    for (std::int64_t r = 0; r < rows_; ++r) {
      if (owns(first_plane + r)) continue;
      std::fill_n(force_rows_.begin() + r * pairs_.size(), pairs_.size(), Vec<D>::Zero());
      std::fill_n(work_rows_.begin() + r * B, B, 0.0);
      std::fill_n(interface_rows_.begin() + r * F, F, InterfaceForce{});
      if (static_cast<std::int64_t>(node_rows_.size()) > r) node_rows_[r].clear();
    }
    static_assert(sizeof(Vec<D>) == D * sizeof(double) &&
                  sizeof(InterfaceForce) == 3 * sizeof(double));
    sum_disjoint(force_rows_.data()->data(), force_rows_.size() * D);
    sum_disjoint(work_rows_.data(), work_rows_.size());
    sum_disjoint(&interface_rows_.data()->cohesive, interface_rows_.size() * 3);
  }
  // The step's impulses join the time means.
  void accumulate(double dt) {
    for (std::size_t k = 0; k < force_.size(); ++k)
      impulse_[k] += dt * force_[k];
    for (std::size_t f = 0; f < interface_force.size(); ++f) {
      interface_impulse[f].cohesive += dt * interface_force[f].cohesive;
      interface_impulse[f].frictional += dt * interface_force[f].frictional;
      interface_impulse[f].normal += dt * interface_force[f].normal;
    }
    impulse_time += dt;
  }
  // A restored state's contact nodes (a checkpoint's), until the next step records its own.
  void restore_nodes(std::vector<ContactNodeForce<D>> nodes) {
    node_rows_.assign(1, std::move(nodes));
  }
  // The last recorded step's contact nodes, in node order.
  std::vector<ContactNodeForce<D>> nodes() const {
    std::vector<ContactNodeForce<D>> all;
    for (const auto& row : node_rows_)
      all.insert(all.end(), row.begin(), row.end());
    return all;
  }

private:
  std::int64_t rows_ = 0;
  std::vector<std::int64_t> pairs_;                         // the pairs that can meet
  std::vector<Vec<D>> force_rows_;                          // per row x pair of pairs_
  std::vector<double> work_rows_;                           // per row x B
  std::vector<InterfaceForce> interface_rows_;              // per row x interface
  std::vector<std::vector<ContactNodeForce<D>>> node_rows_; // per row
};

} // namespace talus
