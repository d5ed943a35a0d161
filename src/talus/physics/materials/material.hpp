// The set of material models. A body holds one Material; the solver visits it once per body per
// step and runs a loop specialised for that model, so no particle ever pays for a virtual call.
#pragma once

#include "talus/physics/materials/drucker_prager.hpp"
#include "talus/physics/materials/fluid.hpp"
#include "talus/physics/materials/linear_elastic.hpp"
#include "talus/physics/materials/mohr_coulomb.hpp"

#include <limits>
#include <string>
#include <variant>

namespace talus {

using MaterialModel = std::variant<LinearElastic, DruckerPrager, MohrCoulomb, Fluid>;

struct Material {
  std::string name;
  MaterialModel model;
  // The largest volume ratio J = V / V0 a particle of this material keeps (infinity: no limit).
  // Stretched past it, the particle's deformation gradient is scaled back isotropically: the
  // further opening is separation between particles (cracks, voids), not the particle's own
  // volume. See docs/formulation.md, "Volume limit".
  double max_volume_ratio = std::numeric_limits<double>::infinity();

  double density() const {
    return std::visit([](const auto& m) { return m.density; }, model);
  }
  // Takes a model's constants once where they cannot change (no softening): see
  // MohrCoulombStrength::prepare and DruckerPrager::prepare. The results are bitwise the same.
  void prepare() {
    std::visit(
        [](auto& m) {
          if constexpr (requires { m.prepare(); })
            m.prepare();
          else if constexpr (requires { m.strength.prepare(); })
            m.strength.prepare();
        },
        model);
  }
  double p_wave_modulus() const {
    return std::visit([](const auto& m) { return m.p_wave_modulus(); }, model);
  }
};

} // namespace talus
