// The fluid material (physics/materials/fluid.hpp): its equation of state and inverse, its
// stored energy (p = -dW/dJ), the viscous deviator, the tension cut, and the case file's keys.
#include "talus/physics/materials/fluid.hpp"
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

TEST(Fluid, CaseKeysAreReadAndBadOnesNamed) {
  const std::string head = R"(
[simulation]
dimension = 2
end_time = 1.0
[grid]
extent = [1.0, 1.0]
cell_size = 0.1
[[body]]
name = "water"
material = "water"
box = { min = [0.0, 0.0], max = [1.0, 0.5] }
[[material]]
name = "water"
model = "fluid"
density = 1000.0
)";
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
}

} // namespace
} // namespace talus
