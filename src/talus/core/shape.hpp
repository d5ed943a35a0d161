// Shape functions as kernels: linear (tent) and uniform GIMP. Both are tensor products of 1D
// weights, evaluated once per particle into a ShapeWeights record that the scatter (P2G) and the
// gather (G2P) both walk, so the two transfers can never disagree.
#pragma once

#include "talus/core/grid.hpp"

#include <algorithm>
#include <cmath>

namespace talus {

enum class ShapeKind { linear, gimp, bspline };

// Up to 3 nodes per direction (GIMP, B-spline); linear uses 2, and a B-spline 2 only on a grid of
// one cell in that direction (bspline_1d). GIMP's support holds 3 nodes in a
// direction only while the particle's domain (half-width lp) straddles a node line; otherwise
// the third node's weight is exactly zero and the record keeps 2 (k[d]), so the transfers visit
// the nodes with weight and no others (with lp = h/4: 2.5 x 2.5 of the 3 x 3 nodes on average in
// 2D). The sums are bitwise those of a 3 x 3 walk, which only added zeros (unless a node's value
// is already NaN or infinite, which the run's particle check reports anyway).
// Not zero-filled on construction (that cost a quarter of evaluate_shape): evaluate_shape writes
// every entry that for_each_node reads (the first k[d] per direction).
template <int D>
struct ShapeWeights {
  static constexpr int max_k = 3;
  Index<D> base;       // lowest node in the support, per direction
  int k[D];            // nodes per direction: 2 or 3
  double w[D][max_k];  // 1D weights
  double dw[D][max_k]; // 1D derivatives d/dx
};

// The reciprocals the GIMP weights need (of h, h lp, 2 h lp and 4 h lp), taken once per particle
// so that the weights of its nodes cost multiplications only.
struct GimpFactors {
  double h, lp, inv_h, inv_hlp, inv_2hlp, inv_4hlp;
  GimpFactors(double h_, double lp_)
      : h(h_), lp(lp_), inv_h(1.0 / h_), inv_hlp(1.0 / (h_ * lp_)), inv_2hlp(0.5 / (h_ * lp_)),
        inv_4hlp(0.25 / (h_ * lp_)) {}
};

inline void gimp_1d(double r, const GimpFactors& f, double& w, double& dw) {
  const double a = std::abs(r);
  const double s = r < 0.0 ? -1.0 : 1.0;
  if (a < f.lp) {
    w = 1.0 - (r * r + f.lp * f.lp) * f.inv_2hlp;
    dw = -r * f.inv_hlp;
  } else if (a < f.h - f.lp) {
    w = 1.0 - a * f.inv_h;
    dw = -s * f.inv_h;
  } else if (a < f.h + f.lp) {
    const double t = f.h + f.lp - a;
    w = t * t * f.inv_4hlp;
    dw = -s * t * f.inv_2hlp;
  } else {
    w = 0.0;
    dw = 0.0;
  }
}

// 1D uniform GIMP weight and derivative for a node at signed distance r = x_p - x_I, cell size h
// and particle half-width lp (Bardenhagen & Kober 2004).
inline void gimp_1d(double r, double h, double lp, double& w, double& dw) {
  gimp_1d(r, GimpFactors(h, lp), w, dw);
}

// The quadratic B-spline in direction d (Steffen, Kirby & Berzins 2008) at xi = (x - origin) / h,
// with the grid's faces at nodes lo <= 0 and hi of this grid's numbering. Inside, the uniform
// B-spline of each node (knots at the cell centres around it): the nodes base, base + 1,
// base + 2 with base = floor(xi - 1/2) and s = xi - base in [1/2, 3/2),
//   N_0 = (3/2 - s)^2 / 2,  N_1 = 3/4 - (s - 1)^2,  N_2 = (s - 1/2)^2 / 2,
// C1 across cell faces, summing to 1 with sum N_i x_i = x (linear fields reproduced). Within
// 5/2 cells of a face, the B-splines of the open knot vector (Piegl & Tiller 1997, ch. 2): the
// interior's knots with the two nearest the face replaced by a triple knot on it,
//   t_j = 0 (j <= 2),  j - 3/2 (3 <= j <= n),  n (j >= n + 1)   (cells from the lower face),
// node i's function on knots t_i .. t_{i+3}. Still one function per node, C1, non-negative and a
// partition of unity, and at the face only the face node has weight (N_i(0) = 1 for i = 0 and 0
// otherwise): a wall at the face holds the material there through its node, and a uniform
// stress puts no force on the nodes behind it. Linear fields are reproduced through each node's
// Greville point (t_{i+1} + t_{i+2}) / 2, which is the node itself except for the second node from
// a face (3/4 of a cell in). A grid of one cell in a direction folds the outer nodes instead.
namespace shape_detail {

// Knot j of the open knot vector over n >= 2 cells.
inline double open_knot(std::int64_t j, std::int64_t n) {
  if (j <= 2) return 0.0;
  if (j >= n + 1) return static_cast<double>(n);
  return static_cast<double>(j) - 1.5;
}

} // namespace shape_detail

template <int D>
inline void bspline_1d(ShapeWeights<D>& sw, int d, double xi, std::int64_t lo, std::int64_t hi,
                       double inv_h) {
  double* w = sw.w[d];
  double* dw = sw.dw[d];
  const std::int64_t n = hi - lo;
  const double t = xi - static_cast<double>(lo); // cells from the lower face
  if (n >= 2 && (t < 2.5 || t >= static_cast<double>(n) - 2.5)) {
    using shape_detail::open_knot;
    const double u = std::clamp(t, 0.0, static_cast<double>(n));
    // The knot span t_s <= u < t_{s+1} (the last span holds u = n); functions s - 2 .. s.
    const std::int64_t s =
        u < open_knot(3, n) ? 2 : std::min(static_cast<std::int64_t>(std::floor(u + 1.5)), n);
    const double k0 = open_knot(s - 1, n), k1 = open_knot(s, n), k2 = open_knot(s + 1, n),
                 k3 = open_knot(s + 2, n);
    // Cox-de Boor: the degree-1 functions of the span, then degree 2.
    const double a = (k2 - u) / (k2 - k1), b = (u - k1) / (k2 - k1); // N_{s-1,1}, N_{s,1}
    const double left = k2 - k0, right = k3 - k1;
    w[0] = (k2 - u) / left * a;
    w[2] = (u - k1) / right * b;
    w[1] = (u - k0) / left * a + (k3 - u) / right * b;
    // N'_{i,2} = 2 (N_{i,1} / (t_{i+2} - t_i) - N_{i+1,1} / (t_{i+3} - t_{i+1})).
    dw[0] = -2.0 * a / left * inv_h;
    dw[1] = 2.0 * (a / left - b / right) * inv_h;
    dw[2] = 2.0 * b / right * inv_h;
    sw.base[d] = lo + s - 2, sw.k[d] = 3;
    return;
  }
  const auto base = static_cast<std::int64_t>(std::floor(xi - 0.5));
  const double s = xi - static_cast<double>(base);
  w[0] = 0.5 * (1.5 - s) * (1.5 - s), dw[0] = (s - 1.5) * inv_h;
  w[1] = 0.75 - (s - 1.0) * (s - 1.0), dw[1] = -2.0 * (s - 1.0) * inv_h;
  w[2] = 0.5 * (s - 0.5) * (s - 0.5), dw[2] = (s - 0.5) * inv_h;
  sw.base[d] = base, sw.k[d] = 3;
  if (base < lo) { // one cell: node lo - 1 lies beyond the lower face, folded into node lo
    w[0] += w[1], dw[0] += dw[1];
    w[1] = w[2], dw[1] = dw[2];
    sw.base[d] = lo, sw.k[d] = 2;
  } else if (base + 2 > hi) { // node hi + 1 lies beyond the upper face
    w[1] += w[2], dw[1] += dw[2];
    sw.k[d] = 2;
  }
}

// Weights of the particle at x, with the GIMP factors of its half-width lp (GimpFactors(h, lp);
// ignored for linear, except their 1/h). Nodes outside the grid get zero weight (their index is
// clamped so the kernel loops never read out of range). The factors are the same for every
// particle of a body: taking them once per body saves five divisions per particle.
// Written in place (the solver's per-particle cache), not returned: a returned record was built
// on the stack and copied, 120 bytes per particle per step in 2D.
// The grid's faces are at nodes face_lo[d] <= 0 and face_hi[d] of `grid`'s numbering (a body's
// frame is part of the grid; only the B-spline asks where the faces are).
template <int D>
inline void evaluate_shape(ShapeWeights<D>& sw, const Grid<D>& grid, ShapeKind kind,
                           const GimpFactors& f, const Vec<D>& x, const std::int64_t* face_lo,
                           const std::int64_t* face_hi) {
  const double inv_h = f.inv_h;
  if (kind == ShapeKind::linear) {
    for (int d = 0; d < D; ++d) {
      sw.k[d] = 2;
      const double xi = (x[d] - grid.origin[d]) * inv_h;
      const auto base = static_cast<std::int64_t>(std::floor(xi));
      sw.base[d] = base;
      for (int a = 0; a < 2; ++a) {
        const std::int64_t node = base + a;
        const double r = xi - static_cast<double>(node);
        double w = 1.0 - std::abs(r), dw = (r < 0.0 ? 1.0 : -1.0) * inv_h;
        if (w < 0.0 || node < 0 || node >= grid.nodes[d]) w = dw = 0.0;
        sw.w[d][a] = w;
        sw.dw[d][a] = dw;
      }
    }
    return;
  }
  if (kind == ShapeKind::bspline) {
    for (int d = 0; d < D; ++d)
      bspline_1d(sw, d, (x[d] - grid.origin[d]) * inv_h, face_lo[d], face_hi[d], inv_h);
    return;
  }
  for (int d = 0; d < D; ++d) {
    const double xi = (x[d] - grid.origin[d]) * inv_h;
    const auto base = static_cast<std::int64_t>(std::floor(xi - 0.5));
    sw.base[d] = base;
    for (int a = 0; a < 3; ++a) {
      const std::int64_t node = base + a;
      double w, dw;
      gimp_1d((xi - static_cast<double>(node)) * grid.h, f, w, dw);
      if (node < 0 || node >= grid.nodes[d]) w = dw = 0.0;
      sw.w[d][a] = w;
      sw.dw[d][a] = dw;
    }
    // Drop an end node with no weight (and so no gradient: GIMP's tail vanishes with its
    // derivative), keeping at least 2 nodes.
    sw.k[d] = 3;
    if (sw.w[d][0] == 0.0 && sw.dw[d][0] == 0.0) {
      sw.base[d] = base + 1;
      sw.w[d][0] = sw.w[d][1], sw.dw[d][0] = sw.dw[d][1];
      sw.w[d][1] = sw.w[d][2], sw.dw[d][1] = sw.dw[d][2];
      sw.k[d] = 2;
    } else if (sw.w[d][2] == 0.0 && sw.dw[d][2] == 0.0) {
      sw.k[d] = 2;
    }
  }
}

// On a whole grid: its faces are its first and last nodes.
template <int D>
inline void evaluate_shape(ShapeWeights<D>& sw, const Grid<D>& grid, ShapeKind kind,
                           const GimpFactors& f, const Vec<D>& x) {
  Index<D> lo{}, hi{};
  for (int d = 0; d < D; ++d)
    hi[d] = grid.nodes[d] - 1;
  evaluate_shape(sw, grid, kind, f, x, lo.data(), hi.data());
}

template <int D>
inline ShapeWeights<D> evaluate_shape(const Grid<D>& grid, ShapeKind kind, const GimpFactors& f,
                                      const Vec<D>& x) {
  ShapeWeights<D> sw;
  evaluate_shape(sw, grid, kind, f, x);
  return sw;
}

template <int D>
inline ShapeWeights<D> evaluate_shape(const Grid<D>& grid, ShapeKind kind, double lp,
                                      const Vec<D>& x) {
  return evaluate_shape(grid, kind, GimpFactors(grid.h, lp), x);
}

namespace shape_detail {

// Node i of direction d, clamped to the grid (a node outside it has no weight).
template <int D>
[[gnu::always_inline]] inline std::int64_t clamp_node(const Grid<D>& grid, int d, std::int64_t i) {
  return i < 0 ? std::int64_t{0} : (i >= grid.nodes[d] ? grid.nodes[d] - 1 : i);
}

// The 3D walk over k0 x k1 x k2 nodes from sw.base, x-major.
template <class F>
[[gnu::always_inline]] inline void walk_3d(const Grid<3>& grid, const ShapeWeights<3>& sw, int k0,
                                           int k1, int k2, F&& f) {
  for (int a = 0; a < k0; ++a) {
    for (int b = 0; b < k1; ++b) {
      const std::int64_t row = (clamp_node(grid, 0, sw.base[0] + a) * grid.nodes[1] +
                                clamp_node(grid, 1, sw.base[1] + b)) *
                               grid.nodes[2];
      const double wab = sw.w[0][a] * sw.w[1][b];
      for (int c = 0; c < k2; ++c) {
        const double N = wab * sw.w[2][c];
        const Vec<3> g(sw.dw[0][a] * sw.w[1][b] * sw.w[2][c], sw.w[0][a] * sw.dw[1][b] * sw.w[2][c],
                       wab * sw.dw[2][c]);
        f(row + clamp_node(grid, 2, sw.base[2] + c), N, g);
      }
    }
  }
}

// The loops of for_each_node in 2D with the nodes per direction known at compile time, so that
// they unroll (K0, K1, K2: 2 or 3 each); in 3D, the walk over K0 x K1 x K2 nodes (the tests'
// full support).
template <int K0, int K1, int K2, int D, class F>
[[gnu::always_inline]] inline void for_each_node_k(const Grid<D>& grid, const ShapeWeights<D>& sw,
                                                   F&& f) {
  if constexpr (D == 2) {
    std::int64_t col[K1];
    for (int b = 0; b < K1; ++b)
      col[b] = clamp_node(grid, 1, sw.base[1] + b);
    for (int a = 0; a < K0; ++a) {
      const std::int64_t row = clamp_node(grid, 0, sw.base[0] + a) * grid.nodes[1];
      for (int b = 0; b < K1; ++b) {
        const double N = sw.w[0][a] * sw.w[1][b];
        const Vec<2> g(sw.dw[0][a] * sw.w[1][b], sw.w[0][a] * sw.dw[1][b]);
        f(row + col[b], N, g);
      }
    }
  } else {
    walk_3d(grid, sw, K0, K1, K2, f);
  }
}

} // namespace shape_detail

// Calls f(node_index, N, grad N) for every node in the support of sw, in a fixed order (x-major).
// Always inlined: through a call, a gather's sums (captured by reference) stay in memory, a
// store-to-load chain per node, and every array's data pointer is reloaded after each store.
template <int D, class F>
[[gnu::always_inline]] inline void for_each_node(const Grid<D>& grid, const ShapeWeights<D>& sw,
                                                 F&& f) {
  using namespace shape_detail;
  if constexpr (D == 2) {
    switch ((sw.k[0] - 2) * 2 + (sw.k[1] - 2)) {
    case 0:
      return for_each_node_k<2, 2, 0>(grid, sw, f);
    case 1:
      return for_each_node_k<2, 3, 0>(grid, sw, f);
    case 2:
      return for_each_node_k<3, 2, 0>(grid, sw, f);
    default:
      return for_each_node_k<3, 3, 0>(grid, sw, f);
    }
  } else {
    // In 3D the loops keep their run-time counts: unrolled for each of the 8 support sizes, f
    // (up to 27 copies in each) was too large to inline and became a call per node.
    walk_3d(grid, sw, sw.k[0], sw.k[1], sw.k[2], f);
  }
}

} // namespace talus
