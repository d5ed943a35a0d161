// The shear band of thermal pressurization (physics/band.hpp) against Rice (2006)'s closed forms,
// slip at a constant rate V with tau = mu (sigma_n - p):
// - undrained and adiabatic: tau = mu sigma_n exp(-d / L), L = rho c h / (mu Lambda);
// - slip on a plane with diffusion: tau = mu sigma_n exp(d / L*) erfc(sqrt(d / L*)),
//   L* = (4 / mu^2) (rho c / Lambda)^2 (sqrt(alpha_hy) + sqrt(alpha_th))^2 / V;
// - heating alone (Lambda = 0): the heat in the band and beside it is the frictional work;
// - unloading: a pressurized band whose normal stress falls below its pore pressure opens and
//   drains into the opening, p(0, t) held at the ceiling: the diffusion closed form of a slab
//   of pressure p0 and half-width a against a drained face.
#include "talus/physics/band.hpp"

#include <cmath>
#include <gtest/gtest.h>
#include <vector>

namespace talus {
namespace {

constexpr double mu = 0.6, sigma = 10e6, V = 1.0, rho_c = 2.7e6, Lambda = 0.3e6;

// Slips at V for `slip` metres in steps of dt; returns tau at each multiple of `every` metres.
std::vector<double> drive(const BandGrid& band, double slip, double every, double dt) {
  std::vector<double> state(band.state_size(), 0.0), out;
  double d = 0.0, next = every;
  while (d < slip - 1e-12) {
    const double tau = mu * (sigma - band.mean_pressure(state.data()));
    band.step(state.data(), tau * V * dt, dt);
    d += V * dt;
    if (d >= next - 1e-12) {
      out.push_back(mu * (sigma - band.mean_pressure(state.data())));
      next += every;
    }
  }
  return out;
}

TEST(Band, UndrainedAdiabaticWeakensOverL) {
  const BandProperties props{1e-3, rho_c, 0.0, 0.0, Lambda};
  const double L = rho_c * props.thickness / (mu * Lambda); // 0.015 m
  const BandGrid band(props, 10 * props.thickness);
  const auto tau = drive(band, 4 * L, 0.5 * L, 1e-5);
  ASSERT_EQ(tau.size(), 8u);
  for (std::size_t k = 0; k < tau.size(); ++k) {
    const double d = 0.5 * L * static_cast<double>(k + 1);
    const double exact = mu * sigma * std::exp(-d / L);
    std::printf("undrained adiabatic, d = %.2f L: tau %.5g Pa (closed form %.5g), %+.3f %%\n",
                d / L, tau[k], exact, 100 * (tau[k] / exact - 1));
    EXPECT_LT(std::abs(tau[k] / exact - 1), 0.01);
  }
}

TEST(Band, SlipOnAPlaneFollowsRicesClosedForm) {
  const double a_hy = 1e-5, a_th = 1e-6;
  const double Ls = 4 / (mu * mu) * std::pow(rho_c / Lambda, 2) *
                    std::pow(std::sqrt(a_hy) + std::sqrt(a_th), 2) / V; // 0.0156 m
  const double slip = 5 * Ls;
  const BandProperties props{1e-6, rho_c, a_th, a_hy, Lambda};
  const BandGrid band(props, 8 * std::sqrt(a_hy * slip / V));
  const auto tau = drive(band, slip, 0.5 * Ls, 2e-6);
  ASSERT_EQ(tau.size(), 10u);
  for (std::size_t k = 0; k < tau.size(); ++k) {
    const double x = 0.5 * static_cast<double>(k + 1);
    const double exact = mu * sigma * std::exp(x) * std::erfc(std::sqrt(x));
    std::printf("slip on a plane, d = %.1f L*: tau %.5g Pa (closed form %.5g), %+.3f %%\n", x,
                tau[k], exact, 100 * (tau[k] / exact - 1));
    EXPECT_LT(std::abs(tau[k] / exact - 1), 0.02);
  }
}

TEST(Band, HeatingAloneHoldsTheFrictionalWork) {
  for (const double a_th : {0.0, 1e-6}) {
    const BandProperties props{2e-3, rho_c, a_th, 1e-5, 0.0};
    const BandGrid band(props, 0.05);
    std::vector<double> state(band.state_size(), 0.0);
    const double W = 5e5, dt = 1e-3; // J/m^2 over 1 s
    for (int i = 0; i < 1000; ++i)
      band.step(state.data(), W / 1000, dt);
    const double T_band = band.mean_temperature(state.data());
    if (a_th == 0.0) {
      EXPECT_NEAR(T_band, W / (rho_c * props.thickness), 1e-9 * T_band);
    } else {
      EXPECT_LT(T_band, W / (rho_c * props.thickness)); // some heat left the band
      EXPECT_NEAR(band.heat(state.data()), W, 1e-6 * W);
    }
    EXPECT_EQ(band.mean_pressure(state.data()), 0.0); // Lambda = 0: no pressure
  }
}

// The band mean over (0, a) of the pressure that starts at p0 in the band (|y| < a) and 0 beyond,
// with the middle held at c from t = 0 (the opening) in a medium that reaches far: by the odd
// image about the middle, u = p - c is
// u = B erf(y / s) + (A - B) / 2 (2 erf(y / s) - erf((y - a) / s) - erf((y + a) / s)),
// s = 2 sqrt(alpha t), A = p0 - c, B = -c; its mean by the midpoint rule on 4000 points.
double drained_slab_mean(double p0, double c, double a, double alpha, double t) {
  const double s = 2.0 * std::sqrt(alpha * t), A = p0 - c, B = -c;
  const int n = 4000;
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    const double y = a * (i + 0.5) / n;
    sum += c + B * std::erf(y / s) +
           0.5 * (A - B) * (2.0 * std::erf(y / s) - std::erf((y - a) / s) - std::erf((y + a) / s));
  }
  return sum / n;
}

TEST(Band, UnloadedBelowItsPressureDrainsIntoTheOpening) {
  // A 1 mm band (a = 0.5 mm) sheared undrained in an instant to p0 = Lambda W / (rho c h), then
  // its normal stress dropped so that it holds at most c above the ambient pressure: drained
  // through its middle at its hydraulic diffusion rate, over t_d = a^2 / alpha_hy = 2.5 s. It
  // stays open while the flux at the middle is outward, p0 (1 - exp(-a^2 / s^2)) > c: for
  // c = p0 / 2, until 0.36 t_d.
  const double h = 1e-3, a = 0.5 * h, alpha = 1e-7, td = a * a / alpha;
  const BandProperties props{h, rho_c, 0.0, alpha, Lambda};
  const BandGrid band(props, 40 * h, 40, 1.05);
  const double W = 2e4;                       // J/m^2
  const double p0 = Lambda * W / (rho_c * h); // 2.2 MPa
  for (const double share : {0.0, 0.5}) {
    std::vector<double> state(band.state_size(), 0.0);
    band.step(state.data(), W, 1e-12); // the shear: heat and pressure, no time to diffuse
    EXPECT_NEAR(band.mean_pressure(state.data()), p0, 1e-6 * p0);
    const double c = share * p0, dt = td / 20000;
    double t = 0.0;
    for (const double at : {0.02, 0.05, 0.1, 0.2, 0.3}) {
      while (t < at * td - 0.5 * dt)
        band.step(state.data(), 0.0, dt, c), t += dt;
      const double p = band.mean_pressure(state.data());
      const double exact = drained_slab_mean(p0, c, a, alpha, t);
      std::printf("band opened at %.1f p0, t %.2f t_d: mean p %.4g Pa (closed form %.4g), %+.3f %% "
                  "of p0\n",
                  share, t / td, p, exact, 100 * (p - exact) / p0);
      EXPECT_LT(std::abs(p - exact), 0.002 * p0);
    }
  }
  // Loading is Rice's: a ceiling above the pressure changes nothing, bit for bit.
  std::vector<double> free(band.state_size(), 0.0), capped(band.state_size(), 0.0);
  for (int i = 0; i < 100; ++i) {
    band.step(free.data(), W / 100, td / 1000);
    band.step(capped.data(), W / 100, td / 1000, 2 * p0);
  }
  EXPECT_EQ(free, capped);
  // An undrained band (alpha_hy = 0) cannot drain: it keeps its pressure.
  const BandGrid sealed(BandProperties{h, rho_c, 0.0, 0.0, Lambda}, 40 * h);
  std::vector<double> state(sealed.state_size(), 0.0);
  sealed.step(state.data(), W, 1e-12);
  for (int i = 0; i < 100; ++i)
    sealed.step(state.data(), 0.0, td / 100, 0.0);
  EXPECT_NEAR(sealed.mean_pressure(state.data()), p0, 1e-9 * p0);
}

} // namespace
} // namespace talus
