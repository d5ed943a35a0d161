#include "talus/setup/boundary.hpp"

#include <cmath>

namespace talus {

template <int D>
GridConditions<D> build_grid_conditions(const Case& c, const Grid<D>& grid) {
  GridConditions<D> gc;
  NodeRange<D> all;
  for (int d = 0; d < D; ++d)
    all.lo[d] = 0, all.hi[d] = grid.nodes[d];
  // Domain faces: fixed constrains every component, slip the normal one, friction is a wall.
  for (int d = 0; d < D; ++d) {
    for (int side = 0; side < 2; ++side) {
      const FaceCondition fc = c.grid.faces[2 * d + side];
      if (fc == FaceCondition::free) continue;
      if (fc == FaceCondition::outflow) { // free for the nodes; fluid particles leave through it
        gc.outflow[2 * d + side] = true;
        continue;
      }
      gc.closed[2 * d + side] = true;
      NodeRange<D> face = all;
      face.lo[d] = side == 0 ? 0 : grid.nodes[d] - 1;
      face.hi[d] = face.lo[d] + 1;
      if (fc == FaceCondition::friction) {
        gc.walls.push_back({face, d, side == 0 ? -1.0 : 1.0, c.grid.face_friction[2 * d + side]});
        continue;
      }
      for (int e = 0; e < D; ++e)
        if (fc == FaceCondition::fixed || e == d) gc.prescribed.push_back({face, -1, e, 0.0});
    }
  }
  // [[boundary]] boxes: the nodes whose position lies inside [min, max].
  for (const BoundarySpec& b : c.boundaries) {
    NodeRange<D> r;
    for (int d = 0; d < D; ++d) {
      const double lo = (b.min[d] - grid.origin[d]) / grid.h,
                   hi = (b.max[d] - grid.origin[d]) / grid.h;
      r.lo[d] = std::isfinite(lo)
                    ? std::clamp<std::int64_t>(static_cast<std::int64_t>(std::ceil(lo - 1e-9)), 0,
                                               grid.nodes[d])
                    : 0;
      r.hi[d] = std::isfinite(hi)
                    ? std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor(hi + 1e-9)) + 1,
                                               0, grid.nodes[d])
                    : grid.nodes[d];
    }
    for (int d = 0; d < D; ++d)
      if (b.fixed[d]) gc.prescribed.push_back({r, b.body, d, b.velocity[d]});
  }
  return gc;
}

template GridConditions<2> build_grid_conditions<2>(const Case&, const Grid<2>&);
template GridConditions<3> build_grid_conditions<3>(const Case&, const Grid<3>&);

} // namespace talus
