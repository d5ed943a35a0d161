// Thermal pressurization of a shear band (Rice 2006; Noda & Lapusta 2010): the frictional work
// heats a band of thickness h, and the heat raises the pore pressure where the band is undrained,
// both relaxed by diffusion across it. One-dimensional across the band, symmetric about its
// middle, on a grid of cells that are uniform inside the half band and grow geometrically beyond:
//
//   dT/dt = alpha_th d2T/dy2 + tau V / (rho c h)     inside the band, |y| < h / 2
//   dp/dt = alpha_hy d2p/dy2 + Lambda dT/dt
//
// stepped with backward Euler (stable at any dt), zero flux at the middle, T = p = 0 (the
// ambient values) at the far face. With both diffusivities zero it is the undrained, adiabatic
// band: T = W / (rho c h), p = Lambda T for a work W per unit area.
//
// Unloading: a band whose pore pressure exceeds the normal stress across it opens along its
// middle (sigma_n' < 0: the grains part, a hydraulic fracture), and the opening, filled with
// water that carries the normal stress, holds p = sigma_n there. The band then drains into it:
// the middle becomes a drained boundary, p(0, t) = sigma_n - p_ambient (a `ceiling` on the
// rise), so the excess decays at the band's own hydraulic diffusion rate,
// erf-like over a time (h / 2)^2 / alpha_hy, and not at all in an undrained band
// (alpha_hy = 0). Loading is Rice's: at or below sigma_n the middle has no flux.
#pragma once

#include <cstddef>
#include <limits>
#include <vector>

namespace talus {

struct BandProperties {
  double thickness = 0.0;             // h, m
  double heat_capacity = 0.0;         // rho c, J/(m^3 K)
  double thermal_diffusivity = 0.0;   // alpha_th, m^2/s
  double hydraulic_diffusivity = 0.0; // alpha_hy, m^2/s
  double lambda = 0.0;                // Lambda, Pa/K: pore pressure rise per degree, undrained
};

// The grid across one half of the band and the medium beside it, shared by every particle of an
// interface. A particle's state is `2 * cells()` numbers: T rise per cell, then p rise per cell.
class BandGrid {
public:
  static constexpr std::size_t max_cells = 160; // the step's work arrays live on the stack

  // Cells: `band_cells` across the half band, then growing by `growth` to reach `extent` (m from
  // the middle; at least the half band), the growth raised if that would take more than
  // max_cells.
  BandGrid(const BandProperties& props, double extent, int band_cells = 4, double growth = 1.2);

  std::size_t cells() const { return dy_.size(); }
  std::size_t state_size() const { return 2 * cells(); }
  double extent() const { return face_.back(); }

  // Advances one particle's state by dt with the frictional work `work` (J/m^2) done over dt.
  // `ceiling`: the largest pore-pressure rise the middle holds (the normal stress across the
  // band less the ambient pore pressure, at least 0); where the step would take the middle above
  // it the band is open there and drains into the opening (see above).
  void step(double* state, double work, double dt,
            double ceiling = std::numeric_limits<double>::infinity()) const;

  // Band means (over |y| < h / 2) of the temperature and pore pressure rises.
  double mean_temperature(const double* state) const { return band_mean(state); }
  double mean_pressure(const double* state) const { return band_mean(state + cells()); }
  // The heat held across the whole band and both sides of it, J/m^2: 2 rho c sum T_i dy_i.
  double heat(const double* state) const;

private:
  double band_mean(const double* v) const;
  // Solves (dy_i - dt alpha L) x = rhs in place (the tridiagonal system of one diffusion step);
  // c: workspace of cells() numbers. `middle`: NaN for no flux through the middle, else the
  // value held there (a drained boundary half a cell from the first centre).
  void solve(double* x, double* c, double alpha, double dt,
             double middle = std::numeric_limits<double>::quiet_NaN()) const;

  BandProperties props_;
  int band_cells_;
  std::vector<double> dy_;   // cell widths
  std::vector<double> face_; // face positions, face_[0] = 0 (the middle)
  std::vector<double> gap_;  // gap_[i]: distance between centres i and i+1 (last: to the face)
};

} // namespace talus
