#include "talus/boundary.hpp"

namespace talus {

template <int D>
GridConditions build_grid_conditions(const Case& c, const Grid<D>& grid) {
  GridConditions gc;
  auto& conds = gc.prescribed;
  // Domain faces: fixed constrains every component, slip the normal one.
  for (int d = 0; d < D; ++d) {
    for (int side = 0; side < 2; ++side) {
      const FaceCondition fc = c.grid.faces[2 * d + side];
      if (fc == FaceCondition::free) continue;
      std::vector<std::int64_t> nodes;
      const std::int64_t plane = side == 0 ? 0 : grid.nodes[d] - 1;
      for (std::int64_t n = 0; n < grid.num_nodes(); ++n)
        if (grid.node_coords(n)[d] == plane) nodes.push_back(n);
      if (fc == FaceCondition::friction) {
        gc.walls.push_back({nodes, d, side == 0 ? -1.0 : 1.0, c.grid.face_friction[2 * d + side]});
        continue;
      }
      for (int e = 0; e < D; ++e)
        if (fc == FaceCondition::fixed || e == d) conds.push_back({nodes, e, 0.0});
    }
  }
  // [[boundary]] boxes. With one shared velocity field a condition on a body's nodes is a
  // condition on the nodes in its box.
  for (const BoundarySpec& b : c.boundaries) {
    std::vector<std::int64_t> nodes;
    for (std::int64_t n = 0; n < grid.num_nodes(); ++n) {
      const Vec<D> x = grid.node_position(grid.node_coords(n));
      bool in = true;
      for (int d = 0; d < D; ++d)
        in = in && x[d] >= b.min[d] && x[d] <= b.max[d];
      if (in) nodes.push_back(n);
    }
    for (int d = 0; d < D; ++d)
      if (b.fixed[d]) conds.push_back({nodes, d, b.velocity[d]});
  }
  return gc;
}

template GridConditions build_grid_conditions<2>(const Case&, const Grid<2>&);
template GridConditions build_grid_conditions<3>(const Case&, const Grid<3>&);

} // namespace talus
