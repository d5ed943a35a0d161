// The shear band of thermal pressurization (physics/band.hpp) against Rice (2006)'s closed forms,
// slip at a constant rate V with tau = mu (sigma_n - p):
// - undrained and adiabatic: tau = mu sigma_n exp(-d / L), L = rho c h / (mu Lambda);
// - slip on a plane with diffusion: tau = mu sigma_n exp(d / L*) erfc(sqrt(d / L*)),
//   L* = (4 / mu^2) (rho c / Lambda)^2 (sqrt(alpha_hy) + sqrt(alpha_th))^2 / V;
// - heating alone (Lambda = 0): the heat in the band and beside it is the frictional work.
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

} // namespace
} // namespace talus
