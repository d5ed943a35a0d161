// Grid boundary conditions: the domain faces (fixed, slip) and velocity conditions on node sets.
#pragma once

#include "talus/case/case.hpp"
#include "talus/grid.hpp"
#include "talus/nodes.hpp"

#include <algorithm>
#include <vector>

namespace talus {

// One prescribed velocity component on a list of nodes.
struct NodeCondition {
  std::vector<std::int64_t> nodes;
  int component = 0;
  double velocity = 0.0;
};

// A Coulomb wall on a face of the domain: nodes moving into it lose their normal velocity and
// up to mu times that much of their tangential velocity.
struct FrictionWall {
  std::vector<std::int64_t> nodes;
  int axis = 0;
  double outward = -1.0; // -1 on a min face, +1 on a max face
  double mu = 0.0;
};

struct GridConditions {
  std::vector<NodeCondition> prescribed;
  std::vector<FrictionWall> walls;
};

// Expands the faces and the [[boundary]] boxes of a case into node lists.
template <int D>
GridConditions build_grid_conditions(const Case& c, const Grid<D>& grid);

// Applies the walls and then the prescribed components to a velocity array.
template <int D>
void apply_grid_conditions(const GridConditions& gc, std::vector<Vec<D>>& velocity) {
  for (const FrictionWall& w : gc.walls) {
    for (const std::int64_t n : w.nodes) {
      Vec<D>& v = velocity[n];
      const double v_in = w.outward * v[w.axis]; // > 0: moving into the wall
      if (v_in <= 0.0) continue;
      v[w.axis] = 0.0;
      const double vt = v.norm();
      if (vt > 0.0) v *= std::max(0.0, 1.0 - w.mu * v_in / vt);
    }
  }
  for (const NodeCondition& nc : gc.prescribed)
    for (const std::int64_t n : nc.nodes)
      velocity[n][nc.component] = nc.velocity;
}

} // namespace talus
