// BodyField<D>: one body's velocity field on the grid (multi-velocity-field contact, paper
// section 2.3), structure of arrays. It covers only the box of nodes the body's particles reach,
// refitted every step, so a small body on a large grid costs a small field. On several processes
// each process stores only the part of the box its own and ghost particles reach.
#pragma once

#include "talus/core/grid.hpp"
#include "talus/core/shape.hpp"

#include <algorithm>
#include <cstdint>
#include <type_traits>
#include <vector>

namespace talus {

template <int D>
struct BodyField {
  Grid<D> box;       // the stored sub-grid: same cell size, origin at node `offset`
  Index<D> offset{}; // global node coordinates of the box's first node
  // The frame: the box spanning every process's particles of the body (on one process, the box
  // itself). Shape weights are taken relative to its origin, so they are one process's bits.
  Grid<D> frame;
  Index<D> frame_offset{};
  // The grid's first and last nodes in the frame's numbering (the B-spline's faces).
  Index<D> face_lo{}, face_hi{};
  std::vector<double> m;       // mass M_I (eq. 14)
  std::vector<Vec<D>> p;       // momentum p_I (eq. 16); MUSL: re-mapped from updated particles
  std::vector<Vec<D>> f;       // internal + external force (eq. 17-18)
  std::vector<Vec<D>> grad_m;  // sum m_p grad N_I(x_p) (eq. 30): points out of the body
  std::vector<Vec<D>> mx;      // mass-weighted position sum m_p N x_p (contact gap check)
  std::vector<Vec<D>> v;       // velocity at the start of the step, v_I^n
  std::vector<Vec<D>> v_new;   // velocity at the end of the step, v_I^{n+1} (eq. 20, 31-36)
  std::vector<Vec<D>> v_remap; // MUSL: velocity re-mapped from the updated particles
  // XPIC(m): the start-of-step velocity with contact, v_c, and then the series' terms
  // (I - S^+ S)^k v_c (xpic_w); their sum for k = 1 .. m - 1, v* - v_c (xpic_delta).
  std::vector<Vec<D>> xpic_w, xpic_delta;
  // Interface particles' contributions (paper eq. 37): the slave's cohesive and tensile capacity
  // shared over the nodes where the pair meets (Simulation::share_interface_loads),
  // sum N mu^p A^p and sum N A^p; and the slip rate contact measured against the interface
  // partner, with its weight 4 s (1 - s) (s: the partner's share of the two bodies' volume; only
  // where the body is held or its bond has opened), gathered back as slip. One slot per
  // interface of the body, at [node * slots + slot]: a node near two of a body's interfaces
  // (a thin body, a junction) keeps each interface's bond and slip apart.
  std::vector<double> cohesion, tension, friction_area, area, slip_rate, slip_weight;
  // With excess pore pressure on an interface: the pore pressure's force (N, per unit thickness
  // in 2D) on the nodes where the pair meets, which pushes the bodies apart
  // (Simulation::share_interface_loads); sum N A^p (1 - r^p), r^p = min(p^p / sigma_n^p, 1), which
  // shares the frictional heat out; and the contact's (effective) normal force per unit of the
  // body's interface area (Pa), shared out as the particles' normal stress; with thermal
  // pressurization the frictional work of the step per unit of that weight (J/m^2), shared out
  // as heat.
  std::vector<double> pore_force, heat_weight, normal_stress, heat;
  // A water body's hydrostatic load below the [water] level: the force its weight and the
  // hydrostatic pressure u = rho_w g (level - z) put on each node, sum N m g + V u grad N, which
  // is zero inside the water and, where a buoyed body meets it, the load that body's buoyancy
  // already stands for (Simulation::hold_hydrostatic_load).
  std::vector<Vec<D>> hydro;
  int slots = 0; // the body's interfaces

  // Which of the optional arrays the run uses: contact (grad_m, mx: two or more bodies),
  // interfaces (the six interface arrays: a body with an interface), MUSL's re-map (v_remap),
  // the interfaces' pore pressure and frictional heat (pressure, heating), a water body's
  // hydrostatic load beside buoyed bodies (hydro).
  // Arrays a run does not use stay empty: no memory, no clearing, no scatter.
  struct Needs {
    bool contact = true, interfaces = true, remap = true, pressure = false, heating = false,
         hydro = false, xpic = false;
  } needs;

  std::size_t size() const { return m.size(); }

  // Refits the box to global node range [lo, hi) and clears the mapped quantities. Vectors only
  // grow, so a steady run stops allocating after its first steps.
  void fit(const Grid<D>& grid, const Index<D>& lo, const Index<D>& hi) {
    fit(grid, lo, hi, lo, hi);
  }

  // Refits the frame to global node range [frame_lo, frame_hi) and the stored box to [lo, hi)
  // inside it, and clears the mapped quantities.
  void fit(const Grid<D>& grid, const Index<D>& frame_lo, const Index<D>& frame_hi,
           const Index<D>& lo, const Index<D>& hi) {
    frame_offset = frame_lo;
    frame = sub_grid(grid, frame_lo, frame_hi);
    for (int d = 0; d < D; ++d)
      face_lo[d] = -frame_lo[d], face_hi[d] = grid.nodes[d] - 1 - frame_lo[d];
    offset = lo;
    box = sub_grid(grid, lo, hi);
    std::size_t n = 1;
    for (int d = 0; d < D; ++d)
      n *= static_cast<std::size_t>(box.nodes[d]);
    for (auto* a : {&v, &v_new})
      a->resize(n);
    if (needs.remap) v_remap.resize(n);
    if (needs.xpic) xpic_w.resize(n), xpic_delta.resize(n);
    const std::size_t ns = n * static_cast<std::size_t>(slots);
    // The mapped quantities, each with its length and whether the body keeps it.
    auto each = [&](auto&& act) {
      act(m, n, true), act(p, n, true), act(f, n, true);
      act(grad_m, n, needs.contact), act(mx, n, needs.contact), act(hydro, n, needs.hydro);
      for (auto* a : {&cohesion, &tension, &friction_area, &area, &slip_rate, &slip_weight})
        act(*a, ns, needs.interfaces);
      for (auto* a : {&pore_force, &heat_weight, &normal_stress})
        act(*a, ns, needs.interfaces && needs.pressure);
      act(heat, ns, needs.interfaces && needs.heating);
    };
    // Sized first, then zeroed by the threads together: a body's box can be the whole grid, and
    // its arrays (with interface slots, 100-250 B a node) cleared by one thread every step
    // held the other idle.
    std::size_t bytes = 0;
    each([&](auto& a, std::size_t count, bool want) {
      if (want) a.resize(count), bytes += count * sizeof(a[0]);
    });
#pragma omp parallel if (bytes >= (std::size_t{1} << 20))
    each([](auto& a, std::size_t, bool want) {
      if (!want) return;
      using T = typename std::decay_t<decltype(a)>::value_type;
      const T nil = [] {
        if constexpr (std::is_same_v<T, double>)
          return 0.0;
        else
          return T(T::Zero());
      }();
      const auto count = static_cast<std::int64_t>(a.size());
#pragma omp for schedule(static) nowait
      for (std::int64_t i = 0; i < count; ++i)
        a[static_cast<std::size_t>(i)] = nil;
    });
  }

  // The shape weights of the point x, taken on the frame and indexed in the stored box: every
  // node of a particle's support lies in the box or outside the grid (zero weight, clamped).
  void weights(ShapeWeights<D>& sw, ShapeKind kind, const GimpFactors& f, const Vec<D>& x) const {
    evaluate_shape(sw, frame, kind, f, x, face_lo.data(), face_hi.data());
    for (int d = 0; d < D; ++d)
      sw.base[d] += frame_offset[d] - offset[d];
  }

  // Local index of global node coordinates, or -1 outside the box.
  std::int64_t local(const Index<D>& global) const {
    std::int64_t n = 0;
    for (int d = 0; d < D; ++d) {
      const std::int64_t i = global[d] - offset[d];
      if (i < 0 || i >= box.nodes[d]) return -1;
      n = n * box.nodes[d] + i;
    }
    return n;
  }

private:
  // The sub-grid of global node range [lo, hi), at least one node per direction.
  static Grid<D> sub_grid(const Grid<D>& grid, const Index<D>& lo, const Index<D>& hi) {
    Grid<D> g;
    g.h = grid.h;
    for (int d = 0; d < D; ++d) {
      g.nodes[d] = std::max<std::int64_t>(hi[d] - lo[d], 1);
      g.cells[d] = g.nodes[d] - 1;
      g.origin[d] = grid.origin[d] + grid.h * static_cast<double>(lo[d]);
    }
    return g;
  }
};

} // namespace talus
