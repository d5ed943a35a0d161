// Eigen aliases and the small tensor helpers the solver and the materials share.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <cstdint>

namespace talus {

template <int D>
using Vec = Eigen::Matrix<double, D, 1>;
template <int D>
using Mat = Eigen::Matrix<double, D, D>;
using Mat3 = Eigen::Matrix3d;

// Stress in Voigt order (xx, yy, zz, xy, yz, xz). Plane strain keeps sigma_zz, so both
// dimensions store all six components: the materials never branch on D.
using Voigt = Eigen::Matrix<double, 6, 1>;

// Integer node or cell coordinates.
template <int D>
using Index = std::array<std::int64_t, D>;

inline Mat3 to_tensor(const Voigt& s) {
  Mat3 t;
  t << s[0], s[3], s[5], s[3], s[1], s[4], s[5], s[4], s[2];
  return t;
}

inline Voigt to_voigt(const Mat3& t) {
  Voigt s;
  s << t(0, 0), t(1, 1), t(2, 2), 0.5 * (t(0, 1) + t(1, 0)), 0.5 * (t(1, 2) + t(2, 1)),
      0.5 * (t(0, 2) + t(2, 0));
  return s;
}

// A DxD tensor embedded in 3x3 with zeros out of plane (plane strain: d_zz = 0).
template <int D>
Mat3 embed(const Mat<D>& a) {
  Mat3 t = Mat3::Zero();
  t.template topLeftCorner<D, D>() = a;
  return t;
}

// The in-plane DxD block of a 3x3 tensor.
template <int D>
Mat<D> in_plane(const Mat3& t) {
  return t.template topLeftCorner<D, D>();
}

inline double trace(const Voigt& s) {
  return s[0] + s[1] + s[2];
}

// Mean stress p = tr(sigma)/3 (tension positive).
inline double mean_stress(const Voigt& s) {
  return trace(s) / 3.0;
}

// Deviator s = sigma - p I.
inline Voigt deviator(const Voigt& s) {
  Voigt d = s;
  const double p = mean_stress(s);
  d[0] -= p;
  d[1] -= p;
  d[2] -= p;
  return d;
}

// J2 = s:s / 2 for a symmetric tensor in Voigt order (shear terms count twice).
inline double second_invariant(const Voigt& dev) {
  return 0.5 * (dev[0] * dev[0] + dev[1] * dev[1] + dev[2] * dev[2]) + dev[3] * dev[3] +
         dev[4] * dev[4] + dev[5] * dev[5];
}

// The Jaumann correction of eq. 27: W sigma - sigma W, which is W sigma + (W sigma)^T for a
// skew W and a symmetric sigma. Integrated explicitly over dt with the stress increment.
inline Voigt jaumann_spin_term(const Voigt& sigma, const Mat3& W) {
  const Mat3 ws = W * to_tensor(sigma);
  return to_voigt(ws + ws.transpose());
}

} // namespace talus
