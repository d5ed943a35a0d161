// The fluid material (physics/materials/fluid.hpp): its equation of state and inverse, its
// stored energy (p = -dW/dJ), the viscous deviator, the tension cut, and the case file's keys.
#include "talus/physics/materials/fluid.hpp"
#include "talus/setup/interface.hpp"
#include "talus/setup/seeds.hpp"
#include "talus/solver/simulation.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>
#include <string>

namespace talus {
namespace {

TEST(Fluid, EquationOfStateEnergyAndViscousStress) {
  for (const double tension : {0.0, 5.0e3}) {
    Fluid f{1000.0, 4.0e5, 2.0e-3, tension};
    for (const double p : {-tension, 0.0, 1.0e3, 2.0e4}) // J(p) inverts p(J)
      EXPECT_NEAR(f.pressure(f.volume_ratio(p)), p, 1e-9 * f.bulk) << p;
    EXPECT_EQ(f.pressure(1.5), -tension);                 // cut: the fluid separates
    for (const double J : {0.9, 0.97, 1.0, 1.004, 1.2}) { // p = -dW/dJ (central difference)
      const double e = 1e-6;
      const double dW = (f.stored_energy(J + e) - f.stored_energy(J - e)) / (2 * e);
      EXPECT_NEAR(-dW, f.pressure(J), 1e-3 * f.bulk * 1e-3 + 1e-6 * f.bulk) << J;
    }
    EXPECT_EQ(f.stored_energy(1.0), 0.0);
  }
  Fluid f{1000.0, 4.0e5, 2.0e-3, 0.0};
  Mat3 D = Mat3::Zero();
  D(0, 0) = 2.0, D(1, 1) = -1.0, D(0, 1) = D(1, 0) = 0.5;
  const Voigt s = fluid_stress(f, 100.0, D); // -p I + 2 mu (D - tr(D) / 3 I)
  EXPECT_DOUBLE_EQ(s[0], -100.0 + 2.0 * 2.0e-3 * (2.0 - 1.0 / 3.0));
  EXPECT_DOUBLE_EQ(s[1], -100.0 + 2.0 * 2.0e-3 * (-1.0 - 1.0 / 3.0));
  EXPECT_DOUBLE_EQ(s[2], -100.0 + 2.0 * 2.0e-3 * (-1.0 / 3.0));
  EXPECT_DOUBLE_EQ(s[3], 2.0 * 2.0e-3 * 0.5);
}

// A 2D case's first tables: 1 m x 1 m on 0.1 m cells.
const std::string square = R"(
[simulation]
dimension = 2
end_time = 1.0
[grid]
extent = [1.0, 1.0]
cell_size = 0.1
)";

// The square with water 0.5 m deep, its material's keys to follow.
const std::string water_case = square + R"(
[[body]]
name = "water"
material = "water"
box = { min = [0.0, 0.0], max = [1.0, 0.5] }
[[material]]
name = "water"
model = "fluid"
density = 1000.0
)";

TEST(Fluid, CaseKeysAreReadAndBadOnesNamed) {
  const std::string& head = water_case;
  const Case c = test::case_from(head + "sound_speed = 20.0\n");
  const auto& f = std::get<Fluid>(c.materials[0].model);
  EXPECT_DOUBLE_EQ(f.bulk, 4.0e5);
  EXPECT_DOUBLE_EQ(f.viscosity, 1.0e-3);
  EXPECT_EQ(f.tension, 0.0);
  auto error = [&](const std::string& keys) {
    try {
      test::case_from(head + keys);
    } catch (const CaseError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error("").find("material[0].bulk_modulus: give one of bulk_modulus"), std::string::npos)
      << error("");
  EXPECT_NE(error("sound_speed = 20.0\nbulk_modulus = 1e6\n").find("give one of"),
            std::string::npos);
  EXPECT_NE(error("sound_speed = 20.0\nyoungs_modulus = 1e6\n").find("not of model 'fluid'"),
            std::string::npos);
  EXPECT_NE(error("sound_speed = 0.1\n").find("material[0].sound_speed: must be between"),
            std::string::npos);
  EXPECT_NE(error("sound_speed = 20.0\nviscosity = -1.0\n").find("material[0].viscosity"),
            std::string::npos);
  EXPECT_NE(error("sound_speed = 20.0\ntension = 1e9\n").find("material[0].tension"),
            std::string::npos);
  // Not under APIC, whose affine velocities drive water into rigid walls (docs/formulation.md).
  std::string apic = head + "sound_speed = 20.0\n";
  apic.replace(apic.find("end_time = 1.0\n"), 15, "end_time = 1.0\napic = true\n");
  try {
    test::case_from(apic);
    ADD_FAILURE() << "a fluid body under simulation.apic was accepted";
  } catch (const CaseError& e) {
    EXPECT_NE(std::string(e.what()).find("body[0].material: a fluid body cannot run under "
                                         "simulation.apic"),
              std::string::npos)
        << e.what();
  }
  // A surface gauge ([[gauge]]): its point in plan inside the grid, its body named.
  const std::string gauge = "sound_speed = 20.0\n[[gauge]]\nbody = \"water\"\n";
  EXPECT_EQ(test::case_from(head + gauge + "at = 0.5\n").gauges.at(0).at[0], 0.5);
  EXPECT_NE(error(gauge + "at = 2.0\n").find("gauge[0].at: the point is outside the grid"),
            std::string::npos)
      << error(gauge + "at = 2.0\n");
  EXPECT_NE(error("sound_speed = 20.0\n[[gauge]]\nbody = \"x\"\nat = 0.5\n").find("gauge[0].body"),
            std::string::npos);
}

// A viscous fluid's step is held below the explicit diffusion limit, CFL rho h^2 / (2 D mu);
// water's wave step is far shorter than its.
TEST(Fluid, AViscousFluidsStepIsItsDiffusionLimit) {
  const std::string text = water_case + "sound_speed = 20.0\n";
  const Case thick = test::case_from(text + "viscosity = 1.0e4\n");
  const Simulation<2> a(thick);
  EXPECT_DOUBLE_EQ(a.compute_time_step(), thick.simulation.cfl * 1000.0 * 0.01 / (4.0 * 1.0e4));
  const Case water = test::case_from(text);
  const Simulation<2> b(water);
  EXPECT_NEAR(b.compute_time_step(), water.simulation.cfl * 0.1 / 20.0, 1e-3 * 0.1 / 20.0);
}

// A body that fills around the others (fill_around: a reservoir around a slope) takes its
// geometry's lattice less every other body's: the two together fill the box, without overlap.
TEST(Fluid, AReservoirFillsAroundTheOtherBodies) {
  const std::string text = square + R"(
[[material]]
name = "water"
model = "fluid"
density = 1000.0
sound_speed = 20.0
[[material]]
name = "rock"
density = 2000.0
youngs_modulus = 1e7
poisson_ratio = 0.3
[[body]]
name = "rock"
material = "rock"
polygon = [[0.0, 0.0], [1.0, 0.0], [0.0, 0.7]]
[[body]]
name = "water"
material = "water"
box = { min = [0.0, 0.0], max = [1.0, 0.5] }
fill_around = true
)";
  const Case c = test::case_from(text);
  const Particles<2> P = fill_particles<2>(c);
  // 0.05 m spacing: 20 x 10 seeds below the level, less those inside the rock's triangle.
  std::size_t in_rock_below = 0;
  for (std::size_t p = P.body_begin[0]; p < P.body_begin[1]; ++p)
    in_rock_below += P.x[p][1] < 0.5;
  EXPECT_EQ(P.body_begin[2] - P.body_begin[1], 200 - in_rock_below);
  for (std::size_t p = P.body_begin[1]; p < P.body_begin[2]; ++p)
    EXPECT_GT(P.x[p][1] + 0.7 * P.x[p][0] - 0.7, 0.0) << "a water seed inside the rock";
  EXPECT_NO_THROW(check_body_overlaps<2>(c, P));
  std::string rotated = text;
  rotated.insert(rotated.rfind("fill_around"), "lattice_angle = 10.0\n");
  EXPECT_THROW(test::case_from(rotated), CaseError);
}

} // namespace
} // namespace talus
