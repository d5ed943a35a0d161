// The particle check (solver/particle_check.cpp and the transfers' own checks): a run that goes
// bad stops with the step, time and particle that went bad.
#include "block_case.hpp"
#include "talus/solver/simulation.hpp"
#include "test_support.hpp"

#include <cmath>
#include <gtest/gtest.h>
#include <limits>
#include <string>
#include <vector>

namespace talus {
namespace {

using test::block_case;
using test::randomise;

// A run that goes bad stops with the step, time and particle: a bad state handed to the solver
// at its next step's start, and a state a step makes (here every particle carried off the grid in
// one step of 1 ms at 2 km/s) at the end of that step, before output or a checkpoint reads it.
TEST(BadState, StopsWithTheStepThatMadeIt) {
  for (const char* scheme : {"usf", "usl", "musl"})
    for (const char* shape : {"linear", "gimp", "bspline"}) {
      const std::string text = block_case<2>(shape, scheme, 1.0);
      const std::vector<std::string> fixed_dt{"simulation.dt=1e-3"};
      auto message = [&](auto&& spoil) {
        Simulation<2> sim(test::case_from(text, fixed_dt));
        spoil(sim.particles_mut());
        try {
          sim.step(); // one step: the bad state must be reported by the step that made it
        } catch (const SimulationError& e) {
          return std::string(e.what());
        }
        return std::string("(no error)");
      };
      const std::string ctx = std::string(scheme) + ", " + shape;
      std::string m = message([](Particles<2>& P) { P.v[7][1] = std::nan(""); });
      EXPECT_NE(m.find("step 0,"), std::string::npos) << ctx << ": " << m;
      EXPECT_NE(m.find("particle 7 "), std::string::npos) << ctx << ": " << m;
      EXPECT_NE(m.find("velocity is not finite"), std::string::npos) << ctx << ": " << m;
      m = message(
          [](Particles<2>& P) { P.stress[3][0] = std::numeric_limits<double>::infinity(); });
      EXPECT_NE(m.find("particle 3 "), std::string::npos) << ctx << ": " << m;
      EXPECT_NE(m.find("stress is not finite"), std::string::npos) << ctx << ": " << m;
      m = message([](Particles<2>& P) {
        for (auto& v : P.v)
          v = Vec<2>(2000.0, 0.0);
      });
      EXPECT_NE(m.find("step 1, time 0.001 s"), std::string::npos) << ctx << ": " << m;
      EXPECT_NE(m.find("left the grid"), std::string::npos) << ctx << ": " << m;
      // A stress the step's stress update makes non-finite, finite at the start: the Jaumann
      // spin term w (sigma_yy - sigma_xx) overflows under a rigid rotation of 1 rad/s (the
      // particle has no volume, so its huge stress exerts no force before). USL and MUSL update
      // the stress last: the stress pass's own check names it. USF goes on to map that stress
      // as forces, which spreads the NaN to its neighbours' positions within the same step.
      m = message([](Particles<2>& P) {
        for (std::size_t p = 0; p < P.size(); ++p)
          P.v[p] = Vec<2>(-(P.x[p][1] - 0.5), P.x[p][0] - 0.5);
        P.stress[3][0] = 1.7e308, P.stress[3][1] = -1.7e308, P.vol[3] = 0.0;
      });
      EXPECT_NE(m.find("step 1, time 0.001 s"), std::string::npos) << ctx << ": " << m;
      if (std::string(scheme) != "usf") {
        EXPECT_NE(m.find("(id 3)"), std::string::npos) << ctx << ": " << m; // sorted since
        EXPECT_NE(m.find("stress is not finite"), std::string::npos) << ctx << ": " << m;
      }
    }
}

} // namespace
} // namespace talus
