// Failure initiation, two-block column (paper section 3.4, Table 4): cases/benchmarks/
// toppling_column.toml, in the plane's frame (x down the 45 degree slope). Statics (derived in
// docs/verification.md): the upper block slides first, with a = g (sin 45 - 0.28 cos 45) =
// 4.994 m/s^2, does not topple while it is supported (its effective load passes 0.07 m from its
// centre, inside its base), and tips off the lower block once its centre nears the edge
// (about 0.43 m of sliding, t = 0.415 s).
#include "talus/case/parse.hpp"
#include "talus/solver/simulation.hpp"

#include <cmath>
#include <cstdio>
#include <gtest/gtest.h>
#include <numbers>

namespace talus {
namespace {

constexpr int plane = 0, lower = 1, upper = 2;
const double a_slide = 9.81 * std::sin(std::numbers::pi / 4) * (1.0 - 0.28);

struct BodyState {
  Vec<2> displacement; // of the centroid
  double rotation_deg; // best-fit rigid rotation of the particles (positive anticlockwise)
};

BodyState body_state(const Particles<2>& P, int b) {
  Vec<2> c = Vec<2>::Zero(), c0 = Vec<2>::Zero();
  const std::size_t n = P.body_begin[b + 1] - P.body_begin[b];
  for (std::size_t p = P.body_begin[b]; p < P.body_begin[b + 1]; ++p)
    c += P.x[p], c0 += P.x0[p];
  c /= static_cast<double>(n), c0 /= static_cast<double>(n);
  double cross = 0, dot = 0;
  for (std::size_t p = P.body_begin[b]; p < P.body_begin[b + 1]; ++p) {
    const Vec<2> q = P.x0[p] - c0, r = P.x[p] - c;
    cross += q[0] * r[1] - q[1] * r[0], dot += q.dot(r);
  }
  return {c - c0, std::atan2(cross, dot) * 180.0 / std::numbers::pi};
}

// Mean slip of the lower block's interface particles (its base) along the plane.
double base_slip(const Particles<2>& P) {
  double s = 0;
  int n = 0;
  for (std::size_t p = P.body_begin[lower]; p < P.body_begin[lower + 1]; ++p)
    if (P.iface[p] >= 0) s += P.x[p][0] - P.x0[p][0], ++n;
  return s / n;
}

// The path each lower-block interface particle has travelled (sum of |x^{n+1} - x^n| over the
// steps), by particle id: the interface's relative displacement that a particle records (its
// slip history) cannot be longer, as the plane under it (E = 300 MPa) hardly moves.
struct Paths {
  std::vector<Vec<2>> last;
  std::vector<double> length;
  void update(const Particles<2>& P) { // first call: the start
    const bool start = last.empty();
    if (start) last.resize(P.size()), length.assign(P.size(), 0.0);
    for (std::size_t p = 0; p < P.size(); ++p) {
      const std::uint32_t i = P.id[p];
      if (!start) length[i] += (P.x[p] - last[i]).norm();
      last[i] = P.x[p];
    }
  }
  // Longest path of the plane's interface particles (its surface rings under the blocks).
  double plane_surface(const Particles<2>& P) const {
    double l = 0;
    for (std::size_t p = P.body_begin[plane]; p < P.body_begin[plane + 1]; ++p)
      if (P.iface[p] >= 0) l = std::max(l, length[P.id[p]]);
    return l;
  }
  // Largest excess of a particle's recorded slip over its path.
  double excess(const Particles<2>& P) const {
    double e = -1e300;
    for (std::size_t p = P.body_begin[lower]; p < P.body_begin[lower + 1]; ++p)
      if (P.iface[p] >= 0) e = std::max(e, P.slip[p] - length[P.id[p]]);
    return e;
  }
};

struct Snapshot {
  double t;
  BodyState up, low;
  double slip, excess, plane_path;
};

std::vector<Snapshot> run_column(const std::vector<std::string>& overrides,
                                 const std::vector<double>& times) {
  const Case c = parse_case_file(
      std::string(TALUS_SOURCE_DIR) + "/cases/benchmarks/toppling_column.toml", overrides);
  Simulation<2> sim(c);
  std::vector<Snapshot> out;
  Paths paths;
  paths.update(sim.particles());
  for (double t : times) {
    while (sim.time() < t - 1e-12) {
      sim.step(t - sim.time());
      paths.update(sim.particles());
    }
    out.push_back({t, body_state(sim.particles(), upper), body_state(sim.particles(), lower),
                   base_slip(sim.particles()), paths.excess(sim.particles()),
                   paths.plane_surface(sim.particles())});
    std::printf(
        "t = %.2f s: upper block displaced (%.3f, %.3f) m, rotated %.1f deg (sliding "
        "closed form %.3f m); lower block (%.4f, %.4f) m, %.2f deg, base slip %.2e m, "
        "recorded slip beyond a particle's path %+.2e m (the plane's surface travelled %.2e m)\n",
        t, out.back().up.displacement[0], out.back().up.displacement[1], out.back().up.rotation_deg,
        0.5 * a_slide * t * t, out.back().low.displacement[0], out.back().low.displacement[1],
        out.back().low.rotation_deg, out.back().slip, out.back().excess, out.back().plane_path);
  }
  return out;
}

// Table 4 as given (blocks E = 2.2 MPa): the order of events the statics predicts. The lower
// block does NOT stay still here (it leans and topples: docs/verification.md records the
// figures); that part of the paper's result is not reproduced and not asserted.
TEST(TopplingColumn, UpperBlockSlidesFirstThenTopplesOff) {
  const auto s = run_column({}, {0.31, 0.74, 0.97});
  EXPECT_GT(s[0].up.displacement[0], 0.15); // slid
  EXPECT_LT(std::abs(s[0].up.rotation_deg), 5.0);
  EXPECT_LT(s[1].up.rotation_deg, -20.0); // tipped downslope (clockwise in this frame)
  EXPECT_LT(s[2].up.rotation_deg, -40.0);
  EXPECT_LT(s[2].up.displacement[1], -0.5); // fell towards the plane
  // The lower block's base rocks, opens and rings: its interface particles' recorded slip (the
  // interface's relative displacement, sliding and opening) must still be no longer than the
  // path they travelled plus the plane surface's (which rings: 28 mm of path by 0.31 s). It
  // once summed the velocities of nodes the plane barely reached: 63 mm at 0.05 s on a particle
  // that had moved 0.1 mm, metres by 0.2 s. Measured excess: +1.8, -3.4, -280 mm.
  for (const Snapshot& x : s)
    EXPECT_LT(x.excess, x.plane_path) << "t = " << x.t;
}

// Stiff blocks (E = 220 MPa) on the same plane made rigid: the closed forms are rigid bodies'.
// The upper block follows x = a t^2 / 2 while supported, without rotating; the lower block's base
// holds (slip under 1 mm) until the upper block leaves it.
TEST(TopplingColumn, StiffBlocksFollowTheRigidClosedForm) {
  const auto s =
      run_column({"material.0.youngs_modulus=2.2e8", "body.plane.rigid=true"}, {0.2, 0.31, 0.4});
  for (const Snapshot& x : s) {
    const double exact = 0.5 * a_slide * x.t * x.t;
    EXPECT_NEAR(x.up.displacement[0], exact, 0.05 * exact) << "t = " << x.t;
    EXPECT_LT(std::abs(x.up.rotation_deg), 1.0) << "t = " << x.t;
    EXPECT_LT(std::abs(x.slip), 1e-3) << "t = " << x.t;
  }
}

} // namespace
} // namespace talus
