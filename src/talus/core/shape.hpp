// Shape functions as kernels: linear (tent) and uniform GIMP. Both are tensor products of 1D
// weights, evaluated once per particle into a ShapeWeights record that the scatter (P2G) and the
// gather (G2P) both walk, so the two transfers can never disagree.
#pragma once

#include "talus/core/grid.hpp"

#include <cmath>

namespace talus {

enum class ShapeKind { linear, gimp, bspline };

// Up to 3 nodes per direction (GIMP, B-spline); linear uses 2, and a B-spline 2 at a face of the
// grid (its node beyond the face folded into the face's). GIMP's support holds 3 nodes in a
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

// The quadratic B-spline in direction d (Steffen, Kirby & Berzins 2008) at xi = (x - origin) / h:
// the nodes base, base + 1, base + 2 with base = floor(xi - 1/2) and s = xi - base in [1/2, 3/2),
//   N_0 = (3/2 - s)^2 / 2,  N_1 = 3/4 - (s - 1)^2,  N_2 = (s - 1/2)^2 / 2,
// C1 across cell faces, summing to 1 with sum N_i x_i = x (linear fields reproduced). At a face
// of the grid the node beyond it is folded into the face node (N_face + N_beyond, and likewise
// the derivatives), so the weights still sum to 1 and their gradients to 0 there: the face node
// carries what a wall at the face holds.
template <int D>
inline void bspline_1d(ShapeWeights<D>& sw, int d, double xi, std::int64_t nodes, double inv_h) {
  const auto base = static_cast<std::int64_t>(std::floor(xi - 0.5));
  const double s = xi - static_cast<double>(base);
  double* w = sw.w[d];
  double* dw = sw.dw[d];
  w[0] = 0.5 * (1.5 - s) * (1.5 - s), dw[0] = (s - 1.5) * inv_h;
  w[1] = 0.75 - (s - 1.0) * (s - 1.0), dw[1] = -2.0 * (s - 1.0) * inv_h;
  w[2] = 0.5 * (s - 0.5) * (s - 0.5), dw[2] = (s - 0.5) * inv_h;
  sw.base[d] = base, sw.k[d] = 3;
  if (base < 0) { // node -1 lies beyond the lower face: fold it into node 0
    w[0] += w[1], dw[0] += dw[1];
    w[1] = w[2], dw[1] = dw[2];
    sw.base[d] = 0, sw.k[d] = 2;
  } else if (base + 2 >= nodes) { // node `nodes` lies beyond the upper face
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
template <int D>
inline void evaluate_shape(ShapeWeights<D>& sw, const Grid<D>& grid, ShapeKind kind,
                           const GimpFactors& f, const Vec<D>& x) {
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
      bspline_1d(sw, d, (x[d] - grid.origin[d]) * inv_h, grid.nodes[d], inv_h);
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

// The loops of for_each_node with the nodes per direction known at compile time, so that they
// unroll (K0, K1, K2: 2 or 3 each).
template <int K0, int K1, int K2, int D, class F>
inline void for_each_node_k(const Grid<D>& grid, const ShapeWeights<D>& sw, F&& f) {
  auto clamp = [&](int d, std::int64_t i) {
    return i < 0 ? std::int64_t{0} : (i >= grid.nodes[d] ? grid.nodes[d] - 1 : i);
  };
  if constexpr (D == 2) {
    std::int64_t col[K1];
    for (int b = 0; b < K1; ++b)
      col[b] = clamp(1, sw.base[1] + b);
    for (int a = 0; a < K0; ++a) {
      const std::int64_t row = clamp(0, sw.base[0] + a) * grid.nodes[1];
      for (int b = 0; b < K1; ++b) {
        const double N = sw.w[0][a] * sw.w[1][b];
        const Vec<2> g(sw.dw[0][a] * sw.w[1][b], sw.w[0][a] * sw.dw[1][b]);
        f(row + col[b], N, g);
      }
    }
  } else {
    for (int a = 0; a < K0; ++a) {
      for (int b = 0; b < K1; ++b) {
        const std::int64_t row =
            (clamp(0, sw.base[0] + a) * grid.nodes[1] + clamp(1, sw.base[1] + b)) * grid.nodes[2];
        const double wab = sw.w[0][a] * sw.w[1][b];
        for (int c = 0; c < K2; ++c) {
          const double N = wab * sw.w[2][c];
          const Vec<3> g(sw.dw[0][a] * sw.w[1][b] * sw.w[2][c],
                         sw.w[0][a] * sw.dw[1][b] * sw.w[2][c], wab * sw.dw[2][c]);
          f(row + clamp(2, sw.base[2] + c), N, g);
        }
      }
    }
  }
}

} // namespace shape_detail

// Calls f(node_index, N, grad N) for every node in the support of sw, in a fixed order (x-major).
template <int D, class F>
inline void for_each_node(const Grid<D>& grid, const ShapeWeights<D>& sw, F&& f) {
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
    switch ((sw.k[0] - 2) * 4 + (sw.k[1] - 2) * 2 + (sw.k[2] - 2)) {
    case 0:
      return for_each_node_k<2, 2, 2>(grid, sw, f);
    case 1:
      return for_each_node_k<2, 2, 3>(grid, sw, f);
    case 2:
      return for_each_node_k<2, 3, 2>(grid, sw, f);
    case 3:
      return for_each_node_k<2, 3, 3>(grid, sw, f);
    case 4:
      return for_each_node_k<3, 2, 2>(grid, sw, f);
    case 5:
      return for_each_node_k<3, 2, 3>(grid, sw, f);
    case 6:
      return for_each_node_k<3, 3, 2>(grid, sw, f);
    default:
      return for_each_node_k<3, 3, 3>(grid, sw, f);
    }
  }
}

} // namespace talus
