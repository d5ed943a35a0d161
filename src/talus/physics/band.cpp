#include "talus/physics/band.hpp"

#include <algorithm>
#include <cmath>

namespace talus {

BandGrid::BandGrid(const BandProperties& props, double extent, int band_cells, double growth)
    : props_(props), band_cells_(band_cells) {
  const double half = 0.5 * props.thickness;
  face_.push_back(0.0);
  for (int i = 0; i < band_cells; ++i) {
    dy_.push_back(half / band_cells);
    face_.push_back(face_.back() + dy_.back());
  }
  // Cells past the band until the extent, as few as growth allows within max_cells.
  const double ratio = std::max(extent / half, 1.0);
  const double budget = static_cast<double>(max_cells - band_cells);
  growth = std::max(growth, std::pow(ratio, 1.0 / budget) * 1.0001);
  while (face_.back() < extent && dy_.size() < max_cells) {
    dy_.push_back(dy_.back() * growth);
    face_.push_back(face_.back() + dy_.back());
  }
  for (std::size_t i = 0; i + 1 < dy_.size(); ++i)
    gap_.push_back(0.5 * (dy_[i] + dy_[i + 1]));
  gap_.push_back(0.5 * dy_.back()); // the last centre to the far face, where T = p = 0
}

double BandGrid::band_mean(const double* v) const {
  double s = 0.0;
  for (int i = 0; i < band_cells_; ++i)
    s += v[i] * dy_[i];
  return s / face_[band_cells_];
}

double BandGrid::heat(const double* state) const {
  double s = 0.0;
  for (std::size_t i = 0; i < dy_.size(); ++i)
    s += state[i] * dy_[i];
  return 2.0 * props_.heat_capacity * s;
}

// Finite volumes: dy_i (x_i' - x_i) = dt alpha [(x_{i+1}' - x_i') / gap_i - (x_i' - x_{i-1}') /
// gap_{i-1}] with no flux through the middle (or, held at `middle`, the flux
// dt alpha (middle - x_0') / (dy_0 / 2) into the first cell) and x = 0 beyond the far face; rhs
// holds dy_i x_i + sources on entry. Thomas algorithm (the matrix is diagonally dominant).
void BandGrid::solve(double* x, double* c, double alpha, double dt, double middle) const {
  double held = 0.0; // the drained middle's coefficient on the first cell, dt alpha / (dy_0 / 2)
  if (!std::isnan(middle) && alpha > 0.0) {
    held = alpha * dt / (0.5 * dy_[0]);
    x[0] += held * middle;
  }
  const std::size_t n = dy_.size();
  if (alpha == 0.0) { // no coupling: the diagonal alone
    for (std::size_t i = 0; i < n; ++i)
      x[i] /= dy_[i];
    return;
  }
  const double k = alpha * dt;
  double prev_c = 0.0, prev_x = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double lower = i > 0 ? -k / gap_[i - 1] : 0.0;
    const double upper = i + 1 < n ? -k / gap_[i] : 0.0;
    const double diag = dy_[i] + k / gap_[i] + (i > 0 ? k / gap_[i - 1] : held);
    const double denom = diag - lower * prev_c;
    c[i] = upper / denom;
    x[i] = (x[i] - lower * prev_x) / denom;
    prev_c = c[i], prev_x = x[i];
  }
  for (std::size_t i = n - 1; i-- > 0;)
    x[i] -= c[i] * x[i + 1];
}

void BandGrid::step(double* state, double work, double dt, double ceiling) const {
  const std::size_t n = dy_.size();
  double* T = state;
  double* p = state + n;
  // Temperature: the work heats the band uniformly, rho c h dT = W (each half takes half of it).
  double rhs[max_cells], dT[max_cells], c[max_cells];
  const double heat = work / (props_.heat_capacity * props_.thickness);
  for (std::size_t i = 0; i < n; ++i)
    rhs[i] = dy_[i] * (T[i] + (static_cast<int>(i) < band_cells_ ? heat : 0.0));
  solve(rhs, c, props_.thermal_diffusivity, dt);
  for (std::size_t i = 0; i < n; ++i)
    dT[i] = rhs[i] - T[i], T[i] = rhs[i];
  // Pore pressure: the temperature rise drives it (Lambda dT), diffusion drains it; where that
  // takes the middle above the ceiling the band is open and the step is taken again with the
  // middle held at it.
  double drive[max_cells];
  for (std::size_t i = 0; i < n; ++i)
    rhs[i] = drive[i] = dy_[i] * (p[i] + props_.lambda * dT[i]);
  solve(rhs, c, props_.hydraulic_diffusivity, dt);
  const double held = std::max(ceiling, 0.0);
  if (rhs[0] > held && props_.hydraulic_diffusivity > 0.0) {
    std::copy(drive, drive + n, rhs);
    solve(rhs, c, props_.hydraulic_diffusivity, dt, held);
  }
  for (std::size_t i = 0; i < n; ++i)
    p[i] = rhs[i];
}

} // namespace talus
