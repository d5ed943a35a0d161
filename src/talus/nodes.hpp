// NodeFields<D>: one velocity field on the grid, structure of arrays. All bodies share one field
// in this version; multi-velocity-field contact gives each body its own.
#pragma once

#include "talus/math.hpp"

#include <vector>

namespace talus {

template <int D>
struct NodeFields {
  std::vector<double> m;       // mass M_I (eq. 14)
  std::vector<Vec<D>> p;       // momentum p_I (eq. 16); in MUSL re-mapped from updated particles
  std::vector<Vec<D>> f;       // internal + external force (eq. 17-18)
  std::vector<Vec<D>> v;       // velocity at the start of the step, v_I^n
  std::vector<Vec<D>> v_new;   // velocity at the end of the step, v_I^{n+1} (eq. 20)
  std::vector<Vec<D>> v_remap; // MUSL: velocity re-mapped from the updated particles

  void resize(std::size_t n) {
    m.assign(n, 0.0);
    p.assign(n, Vec<D>::Zero());
    f.assign(n, Vec<D>::Zero());
    v.assign(n, Vec<D>::Zero());
    v_new.assign(n, Vec<D>::Zero());
    v_remap.assign(n, Vec<D>::Zero());
  }
  std::size_t size() const { return m.size(); }
};

} // namespace talus
