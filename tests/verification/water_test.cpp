// Water (docs/formulation.md, "Water"): below a hydrostatic level a particle weighs its buoyant
// weight, so a block sliding on a submerged plane and a block entering the water follow the
// closed forms of the effective-stress equations of motion.
#include "talus/solver.hpp"
#include "test_support.hpp"

#include <cmath>
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <numbers>

namespace talus {
namespace {

constexpr double g = 9.81, theta = std::numbers::pi / 6.0, mu = 0.174;
const Vec<2> down_plane(std::cos(theta), -std::sin(theta));

// The 30 degree sliding block (cases/benchmarks/sliding_block.toml) with extra overrides.
Case sliding_block(std::vector<std::string> set) {
  set.push_back(fmt::format("contact.0.friction={}", mu));
  return parse_case_file(std::string(TALUS_SOURCE_DIR) + "/cases/benchmarks/sliding_block.toml",
                         set);
}

struct Motion {
  double s = 0.0, v = 0.0; // along the plane: centroid displacement and velocity
};

Motion block_motion(const Simulation<2>& sim) {
  const auto& P = sim.particles();
  double m = 0.0;
  Vec<2> mu_ = Vec<2>::Zero(), mv = Vec<2>::Zero();
  for (std::size_t p = P.body_begin[0]; p < P.body_begin[1]; ++p)
    m += P.m[p], mu_ += P.m[p] * (P.x[p] - P.x0[p]), mv += P.m[p] * P.v[p];
  return {(mu_ / m).dot(down_plane), (mv / m).dot(down_plane)};
}

// Fully submerged: a = (1 - rho_w / rho) g (sin - mu cos); the weight and the friction both
// scale with the buoyant weight. The block's density is 2000, the water's 1000 and 1025.
TEST(Water, BlockOnASubmergedPlaneWithinHalfAPercent) {
  for (const double rho_w : {1000.0, 1025.0}) {
    const Case c = sliding_block({"water.level=20", fmt::format("water.density={}", rho_w)});
    Simulation<2> sim(c);
    for (const double t : {0.5, 1.0, 1.5, 2.0}) {
      while (sim.time() < t - 1e-12)
        sim.step(t - sim.time());
      const double exact =
          0.5 * (1.0 - rho_w / 2000.0) * g * t * t * (std::sin(theta) - mu * std::cos(theta));
      const double err = block_motion(sim).s / exact - 1.0;
      std::printf("submerged block, rho_w %.0f, t %.1f s: %.5f m (closed form %.5f), %+.3f %%\n",
                  rho_w, t, block_motion(sim).s, exact, 100 * err);
      EXPECT_LT(std::abs(err), 0.005);
    }
    // The buoyancy is in the work of the body force: (1 - rho_w / rho) m g sin(theta) s.
    const double m = sim.setup().bodies[0].mass;
    const double work = (1.0 - rho_w / 2000.0) * m * g * std::sin(theta) * block_motion(sim).s;
    EXPECT_NEAR(sim.gravity_work(0), work, 1e-3 * work);
  }
}

// The share of a polygon below the height `level`.
double share_below(std::vector<Vec<2>> poly, double level) {
  auto area = [](const std::vector<Vec<2>>& q) {
    double a = 0.0;
    for (std::size_t i = 0; i < q.size(); ++i) {
      const Vec<2>&u = q[i], &w = q[(i + 1) % q.size()];
      a += u[0] * w[1] - w[0] * u[1];
    }
    return 0.5 * std::abs(a);
  };
  std::vector<Vec<2>> below; // Sutherland-Hodgman against y <= level
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Vec<2>&u = poly[i], &w = poly[(i + 1) % poly.size()];
    if (u[1] <= level) below.push_back(u);
    if ((u[1] <= level) != (w[1] <= level))
      below.push_back(u + (w - u) * ((level - u[1]) / (w[1] - u[1])));
  }
  return below.size() < 3 ? 0.0 : area(below) / area(poly);
}

// Half in, half out: the block starts with its centroid at the level and slides in. Its
// acceleration is g (sin - mu cos) (1 - rho_w / rho phi(s)), phi the submerged share of the block
// moved s down the plane, so v(s)^2 = 2 g (sin - mu cos) int_0^s (1 - rho_w / rho phi) ds.
// Compared where the block's top corner reaches the water line (fully under).
TEST(Water, BlockEnteringTheWaterReachesTheLineWithTheClosedFormSpeed) {
  const std::vector<Vec<2>> block = {
      {1.433013, 6.75}, {2.299038, 6.25}, {2.799038, 7.116025}, {1.933013, 7.616025}};
  const double level = 6.933013, top = 7.616025, B = 1000.0 / 2000.0;
  const Case c = sliding_block({fmt::format("water.level={}", level)});
  Simulation<2> sim(c);
  const double s_full = (top - level) / std::sin(theta);
  while (block_motion(sim).s < s_full)
    sim.step();
  const Motion at = block_motion(sim);
  double integral = 0.0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    const double s = (i + 0.5) * at.s / n;
    std::vector<Vec<2>> moved = block;
    for (auto& x : moved)
      x += s * down_plane;
    integral += (1.0 - B * share_below(moved, level)) * at.s / n;
  }
  const double exact = std::sqrt(2.0 * g * (std::sin(theta) - mu * std::cos(theta)) * integral);
  const double dry = std::sqrt(2.0 * g * (std::sin(theta) - mu * std::cos(theta)) * at.s);
  std::printf("block entering the water at s = %.4f m: v %.5f m/s (closed form %.5f, dry %.5f), "
              "%+.3f %%\n",
              at.s, at.v, exact, dry, 100 * (at.v / exact - 1.0));
  EXPECT_LT(std::abs(at.v / exact - 1.0), 0.005);
}

} // namespace
} // namespace talus
