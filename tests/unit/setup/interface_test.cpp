// Interfaces: the degradation law's curves at their defining points (paper Figure 11), the
// tensile strength that degrades with the cohesion, which particles carry an interface and their
// areas, and overlapping bodies refused.
#include "talus/case/geometry.hpp"
#include "talus/case/parse.hpp"
#include "talus/setup/interface.hpp"
#include "talus/setup/seeds.hpp"
#include "two_bodies.hpp"

#include <cmath>
#include <gtest/gtest.h>

namespace talus {
namespace {

TEST(Degradation, CurvesAtTheirDefiningPoints) {
  const Degradation g{0.6, 0.2, 0.1}; // v0, vr, s_c
  using C = DegradationCurve;
  // Linear: v0 + (vr - v0) min(1, s / s_c).
  EXPECT_DOUBLE_EQ(g.at(0.0, C::linear), 0.6);
  EXPECT_DOUBLE_EQ(g.at(0.05, C::linear), 0.6 + (0.2 - 0.6) * 0.5);
  EXPECT_DOUBLE_EQ(g.at(0.3, C::linear), 0.2);
  // Bilinear: v0 until s_c / 2, then linear to vr at s_c.
  EXPECT_DOUBLE_EQ(g.at(0.05, C::bilinear), 0.6);
  EXPECT_DOUBLE_EQ(g.at(0.075, C::bilinear), 0.6 + (0.2 - 0.6) * 0.5);
  EXPECT_DOUBLE_EQ(g.at(0.2, C::bilinear), 0.2);
  // Exponential: vr + (v0 - vr) exp(-3 s / s_c).
  EXPECT_DOUBLE_EQ(g.at(0.1, C::exponential), 0.2 + 0.4 * std::exp(-3.0));
  EXPECT_DOUBLE_EQ(g.at(0.0, C::exponential), 0.6);
}

TEST(Degradation, TensileStrengthFollowsTheCohesion) {
  InterfaceSpec f;
  f.cohesion = {2000.0, 0.0, 0.1};
  EXPECT_DOUBLE_EQ(tensile_strength(f, 500.0), 500.0); // default: equal to the cohesion
  f.tensile_strength = 1000.0;
  EXPECT_DOUBLE_EQ(tensile_strength(f, 500.0), 1000.0 * 500.0 / 2000.0);
}

// The interface particles are the rows along the shared face, each with area s (the spacing in
// 2D), the initial cohesion and friction; bodies that do not touch get a warning.
TEST(InterfaceParticles, TheRowsAlongTheSharedFace) {
  const Case c = test::case_from(test::two_blocks(R"(
[[interface]]
bodies = ["upper", "lower"]
friction = { initial = 0.5, residual = 0.3, slip = 0.1 }
cohesion = { initial = 1000, residual = 0, slip = 0.1 }
)"));
  Particles<2> P = fill_particles<2>(c);
  const auto warnings = mark_interface_particles<2>(c, P);
  EXPECT_TRUE(warnings.empty());
  const double s = c.grid.cell_size / 2; // particle spacing
  int lower = 0, upper = 0;
  for (std::size_t p = 0; p < P.size(); ++p) {
    if (P.iface[p] < 0) continue;
    const int b = P.body_of(p);
    const double y = P.x[p][1];
    // The first row of each body next to y = 0.4, under the upper block's footprint (with the
    // 1.5-spacing reach either side of it).
    EXPECT_NEAR(std::abs(y - 0.4), 0.5 * s, 1e-12) << p;
    EXPECT_GE(P.x[p][0], 0.6 - 1.5 * s - 1e-12);
    EXPECT_LE(P.x[p][0], 1.0 + 1.5 * s + 1e-12);
    EXPECT_DOUBLE_EQ(P.iface_area[p], s);
    EXPECT_DOUBLE_EQ(P.cohesion[p], 1000.0);
    EXPECT_DOUBLE_EQ(P.friction[p], 0.5);
    (b == 0 ? lower : upper)++;
  }
  EXPECT_EQ(upper, static_cast<int>(std::lround(0.4 / s))); // the upper block's whole base
  EXPECT_GE(lower, upper);
}

TEST(InterfaceParticles, BodiesThatDoNotTouchAreWarned) {
  std::string text = test::two_blocks(R"(
[[interface]]
bodies = ["upper", "lower"]
friction = { initial = 0.5 }
cohesion = { initial = 0 }
)");
  text.replace(text.find("min = [0.6, 0.4], max = [1.0, 0.6]"), 34,
               "min = [0.6, 0.6], max = [1.0, 0.8]");
  const Case c = test::case_from(text);
  Particles<2> P = fill_particles<2>(c);
  EXPECT_EQ(mark_interface_particles<2>(c, P).size(), 2u);
}

TEST(BodyOverlap, OverlappingShapesAreRefused) {
  std::string text = test::two_blocks();
  text.replace(text.find("min = [0.6, 0.4]"), 16, "min = [0.6, 0.3]");
  const Case c = test::case_from(text);
  const Particles<2> P = fill_particles<2>(c);
  EXPECT_THROW(check_body_overlaps<2>(c, P), CaseError);
  const Case touching = test::case_from(test::two_blocks());
  EXPECT_NO_THROW(check_body_overlaps<2>(touching, fill_particles<2>(touching)));
}

} // namespace
} // namespace talus
