// Reading [[material]]: the solid models (elastic, Drucker-Prager, Mohr-Coulomb with optional
// softening) and the fluid, each key checked against its model.
#include "talus/case/read_materials.hpp"

#include <algorithm>
#include <fmt/format.h>
#include <string>
#include <utility>
#include <vector>

namespace talus::case_reading {
namespace {

constexpr double degrees = 3.14159265358979323846 / 180.0;

// Strength of the Mohr-Coulomb family in engineers' terms: angles in degrees, stresses in Pa.
MohrCoulombStrength read_strength(TableReader& r) {
  MohrCoulombStrength s;
  const double phi = r.number("friction_angle");
  require(r, "friction_angle", phi >= 0.0 && phi < 90.0, "must be in [0, 90) degrees");
  const double psi = r.number("dilation_angle", 0.0);
  require(r, "dilation_angle", psi >= 0.0 && psi <= phi, "must be in [0, friction_angle] degrees");
  s.friction_angle = phi * degrees;
  s.dilation_angle = psi * degrees;
  s.cohesion = r.number("cohesion", 0.0);
  require(r, "cohesion", s.cohesion >= 0.0, "must be >= 0 Pa");
  s.tension_cutoff = r.number("tension_cutoff", inf);
  require(r, "tension_cutoff", s.tension_cutoff >= 0.0, "must be >= 0 Pa");
  require(r, "friction_angle", phi > 0.0 || s.cohesion > 0.0,
          "a material with no friction needs cohesion");
  if (r.has("softening_strain")) {
    s.softening_strain = r.number("softening_strain");
    require(r, "softening_strain", s.softening_strain > 0.0, "must be > 0");
    s.residual_cohesion = r.number("residual_cohesion", s.cohesion);
    require(r, "residual_cohesion", s.residual_cohesion >= 0.0 && s.residual_cohesion <= s.cohesion,
            "must be in [0, cohesion] Pa");
    const double phi_r = r.number("residual_friction_angle", phi);
    require(r, "residual_friction_angle", phi_r >= 0.0 && phi_r <= phi,
            "must be in [0, friction_angle] degrees");
    s.residual_friction_angle = phi_r * degrees;
  }
  return s;
}

// model = "fluid": a weakly compressible Newtonian fluid (physics/materials/fluid.hpp).
Material read_fluid(TableReader& r, Material m, double density) {
  const std::string solid = "a key of the solid models, not of model 'fluid': remove it";
  for (const char* key : {"youngs_modulus", "poisson_ratio", "friction_angle", "dilation_angle",
                          "cohesion", "tension_cutoff", "softening_strain", "residual_cohesion",
                          "residual_friction_angle", "match", "max_volume_ratio"})
    r.belongs_elsewhere(key, solid);
  Fluid f;
  f.density = density;
  if (r.has("bulk_modulus") == r.has("sound_speed"))
    r.fail(r.has("bulk_modulus") ? "sound_speed" : "bulk_modulus",
           "give one of bulk_modulus (Pa) and sound_speed (m/s, K = rho c^2)");
  if (r.has("sound_speed")) {
    const double c = r.number("sound_speed");
    require(r, "sound_speed", c >= 1.0 && c <= 1e4, "must be between 1 and 10,000 m/s");
    f.bulk = density * c * c;
  } else {
    f.bulk = r.number("bulk_modulus");
    require(r, "bulk_modulus", f.bulk >= 1.0 && f.bulk <= 1e11, "must be between 1 Pa and 100 GPa");
  }
  f.viscosity = r.number("viscosity", 1.0e-3);
  require(r, "viscosity", f.viscosity >= 0.0 && f.viscosity <= 1e9,
          "must be between 0 and 1e9 Pa s");
  f.tension = r.number("tension", 0.0);
  require(r, "tension", f.tension >= 0.0 && f.tension < f.bulk,
          "must be >= 0 Pa and below the bulk modulus");
  m.model = f;
  return m;
}

Material read_material(TableReader& r) {
  Material m;
  m.name = r.name("name", "");
  const std::string model = r.choice(
      "model", {"linear_elastic", "drucker_prager", "mohr_coulomb", "fluid"}, "linear_elastic");
  const double density = r.number("density");
  require(r, "density", density > 0.0, "must be > 0 kg/m^3");
  // Beyond what any material on Earth has (osmium: 22,590), a density is a typo; its time step
  // and run would be absurd.
  require(r, "density", density >= 1.0 && density <= 1e5,
          "must be between 1 and 100,000 kg/m^3 (a material on Earth)");
  if (model == "fluid") return read_fluid(r, std::move(m), density);
  const double E = r.number("youngs_modulus");
  require(r, "youngs_modulus", E >= 1.0,
          "must be >= 1 Pa (a solid; softer than that the time step exceeds any run)");
  const double nu = r.number("poisson_ratio");
  require(r, "poisson_ratio", nu >= 0.0 && nu < 0.5, "must be in [0, 0.5)");
  // Another model's keys, named as such if given.
  const std::string plastic = fmt::format(
      "a key of models drucker_prager and mohr_coulomb, not of model '{}': set model or remove it",
      model);
  for (const char* key : {"friction_angle", "dilation_angle", "cohesion", "tension_cutoff",
                          "softening_strain", "residual_cohesion", "residual_friction_angle"})
    if (model == "linear_elastic") r.belongs_elsewhere(key, plastic);
  if (model != "drucker_prager")
    r.belongs_elsewhere("match",
                        fmt::format("a key of model drucker_prager, not of model '{}'", model));
  if (model == "linear_elastic") {
    m.model = LinearElastic{density, E, nu};
  } else if (model == "drucker_prager") {
    DruckerPrager dp{density, E, nu, DruckerPragerMatch::inner, read_strength(r), {}};
    const std::string match = r.choice("match", {"inner", "outer", "plane_strain"}, "inner");
    dp.match = match == "outer"          ? DruckerPragerMatch::outer
               : match == "plane_strain" ? DruckerPragerMatch::plane_strain
                                         : DruckerPragerMatch::inner;
    m.model = dp;
  } else {
    m.model = MohrCoulomb{density, E, nu, read_strength(r)};
  }
  m.max_volume_ratio = r.number("max_volume_ratio", inf);
  require(r, "max_volume_ratio", m.max_volume_ratio > 1.0, "must be > 1");
  require(r, "max_volume_ratio", model != "linear_elastic" || !r.has("max_volume_ratio"),
          "only for the plastic models: an elastic particle's tension would keep growing while "
          "its volume stays at the limit");
  return m;
}

} // namespace

// [[material]]: the named materials (at least one).
void read_materials(TableReader& root, Case& c) {
  std::vector<std::string> material_names;
  for_each_entry(root, "material", [&](TableReader& r, std::size_t) {
    c.materials.push_back(read_material(r));
    if (std::count(material_names.begin(), material_names.end(), c.materials.back().name))
      r.fail("name", "two materials have this name");
    material_names.push_back(c.materials.back().name);
  });
  if (c.materials.empty()) root.fail_missing("material");
}

} // namespace talus::case_reading
