// Grid boundary conditions: the domain faces (fixed, slip) and velocity conditions on node sets.
#pragma once

#include "talus/case/case.hpp"
#include "talus/grid.hpp"
#include "talus/nodes.hpp"

#include <vector>

namespace talus {

// One prescribed velocity component on a list of nodes.
struct NodeCondition {
  std::vector<std::int64_t> nodes;
  int component = 0;
  double velocity = 0.0;
};

// Expands the faces and the [[boundary]] boxes of a case into per-component node lists.
template <int D>
std::vector<NodeCondition> build_node_conditions(const Case& c, const Grid<D>& grid);

// Sets the constrained components of a velocity array.
template <int D>
void apply_node_conditions(const std::vector<NodeCondition>& conds, std::vector<Vec<D>>& velocity) {
  for (const NodeCondition& nc : conds)
    for (const std::int64_t n : nc.nodes)
      velocity[n][nc.component] = nc.velocity;
}

} // namespace talus
