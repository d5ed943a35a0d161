// Grid boundary conditions: the domain faces (fixed, slip, Coulomb walls) and velocity conditions
// on boxes of nodes, optionally for one body's field only. Conditions are stored as global node
// ranges and applied to each body field where its box overlaps them.
#pragma once

#include "talus/case/case.hpp"
#include "talus/core/nodes.hpp"

#include <algorithm>
#include <array>
#include <vector>

namespace talus {

// Global node coordinates [lo, hi) per direction.
template <int D>
struct NodeRange {
  Index<D> lo{}, hi{};
};

// One prescribed velocity component on a range of nodes.
template <int D>
struct NodeCondition {
  NodeRange<D> nodes;
  int body = -1; // -1: every body
  int component = 0;
  double velocity = 0.0;
};

// A Coulomb wall on a face of the domain: nodes moving into it lose their normal velocity and
// up to mu times that much of their tangential velocity.
template <int D>
struct FrictionWall {
  NodeRange<D> nodes;
  int axis = 0;
  double outward = -1.0; // -1 on a min face, +1 on a max face
  double mu = 0.0;
};

template <int D>
struct GridConditions {
  std::vector<NodeCondition<D>> prescribed;
  std::vector<FrictionWall<D>> walls;
  // Which domain faces are walls (fixed, slip or friction; index 2 d + side): impenetrable to
  // particles as well as to the nodes' velocity.
  std::array<bool, 2 * D> closed{};
  // Which domain faces let a fluid body's particles out of the run (outflow): free for the nodes.
  std::array<bool, 2 * D> outflow{};
};

template <int D>
GridConditions<D> build_grid_conditions(const Case& c, const Grid<D>& grid);

// Calls f(local index) for every node of `field` inside the global range r.
template <int D, class F>
void for_each_node_in(const BodyField<D>& field, const NodeRange<D>& r, F&& f) {
  Index<D> lo, hi;
  for (int d = 0; d < D; ++d) {
    lo[d] = std::max(r.lo[d], field.offset[d]) - field.offset[d];
    hi[d] = std::min(r.hi[d], field.offset[d] + field.box.nodes[d]) - field.offset[d];
    if (lo[d] >= hi[d]) return;
  }
  Index<D> i = lo;
  while (true) {
    f(field.box.node_index(i));
    int d = D - 1;
    while (d >= 0 && ++i[d] == hi[d])
      i[d] = lo[d], --d;
    if (d < 0) return;
  }
}

// Applies the walls and then the prescribed components to one of body b's velocity arrays.
template <int D>
void apply_grid_conditions(const GridConditions<D>& gc, int b, const BodyField<D>& field,
                           std::vector<Vec<D>>& velocity) {
  for (const FrictionWall<D>& w : gc.walls) {
    for_each_node_in(field, w.nodes, [&](std::int64_t n) {
      Vec<D>& v = velocity[n];
      const double v_in = w.outward * v[w.axis]; // > 0: moving into the wall
      if (v_in <= 0.0) return;
      v[w.axis] = 0.0;
      const double vt = v.norm();
      if (vt > 0.0) v *= std::max(0.0, 1.0 - w.mu * v_in / vt);
    });
  }
  for (const NodeCondition<D>& nc : gc.prescribed)
    if (nc.body < 0 || nc.body == b)
      for_each_node_in(field, nc.nodes,
                       [&](std::int64_t n) { velocity[n][nc.component] = nc.velocity; });
}

} // namespace talus
