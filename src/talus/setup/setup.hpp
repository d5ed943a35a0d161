// Setup<D>: what is fixed for the whole run, derived once from the Case (and the particles'
// masses) when the simulation is built. The phases of the step read this, never the Case.
#pragma once

#include "talus/case/case.hpp"
#include "talus/core/grid.hpp"
#include "talus/core/particles.hpp"
#include "talus/core/shape.hpp"
#include "talus/physics/band.hpp"
#include "talus/physics/contact.hpp"
#include "talus/physics/materials/material.hpp"
#include "talus/physics/water.hpp"
#include "talus/setup/boundary.hpp"

#include <optional>
#include <string>
#include <vector>

namespace talus {

// One body as the phases see it.
template <int D>
struct BodySetup {
  std::string name;
  Material material;                       // prepared (derived constants filled)
  GimpFactors gimp{1.0, 0.5};              // GIMP factors (cell, particle half-width)
  Vec<D> rigid_velocity = Vec<D>::Zero();  // the prescribed velocity of a rigid body
  bool rigid = false;                      // prescribed velocity, infinite mass in contact
  bool fixed = false;                      // rigid with velocity zero: its field never changes
  std::optional<Geometry> normal_geometry; // geometric_normal: the shape whose normal it uses
  double mass = 0.0;                       // total: the master of a contact pair is heavier
  double density = 0.0;                    // the material's: nodal volume shares m / rho
  double buoyancy = 0.0;                   // rho_w / rho below the water level (0: dry)
  bool fluid = false;                      // model = "fluid": a water body (never buoyed)
  double particle_height = 0.0;            // its particles' spacing (how they cross the level)
};

// The hydrostatic water level, as heights along `up` (against gravity).
template <int D>
struct WaterSetup {
  bool on = false;
  double level = 0.0, density = 0.0, g = 0.0; // m, kg/m^3, |gravity|
  Vec<D> up = Vec<D>::Zero();
};

// Time-step control (simulation.dt, cfl, dt_max, dt_min; initial_state.settle_cfl).
struct TimeStepSetup {
  std::optional<double> fixed_dt;
  double cfl = 0.4, dt_max = inf;
  std::optional<double> dt_min, settle_cfl;
};

template <int D>
struct Setup {
  int num_bodies = 0, num_interfaces = 0;
  std::vector<BodySetup<D>> bodies;
  std::vector<InterfaceSpec> interfaces; // degradation curves and tensile strengths
  // Per interface with thermal pressurization: its band's grid (physics/band.hpp), else empty.
  std::vector<std::optional<BandGrid>> bands;
  std::vector<char> interface_pressure; // per interface: an excess pore pressure or a band
  bool pore_pressure = false;           // any interface has one
  bool heating = false;              // an interface has a band: contact records the shear traction
  std::vector<double> pair_friction; // B x B: Coulomb coefficient of each pair
  std::vector<int> pair_interface;   // B x B: interface index or -1
  std::vector<int> interface_slots;  // B x F: the interface's slot in the body's field
  // law = "surface": each pair (deformable body, rigid body, their shapes); per body, a pair's
  // rigid one.
  struct SurfacePair {
    int body = 0, rigid = 0;
    Geometry shape, rigid_shape;
  };
  std::vector<SurfacePair> surface_pairs;
  std::vector<char> surface_rigid;
  GridConditions<D> conditions; // velocity conditions of the faces and boxes
  ContactLaw contact_law;
  Vec<D> gravity = Vec<D>::Zero();
  WaterSetup<D> water;
  Scheme scheme = Scheme::musl;
  ShapeKind shape = ShapeKind::gimp;
  double flip = 1.0;
  int xpic = 0;                               // XPIC(m)'s order, 0 off
  bool apic = false;                          // APIC transfers
  double damping = 0.0, settle_damping = 0.0; // local damping in motion and while settling
  bool hold_interfaces = true;                // settling holds bonded interfaces outright
  bool hold_contacts = false;                 // settling sticks every contact
  int normal_smoothing = 1;                   // cells
  bool pairwise_nodes = true;                 // contact.node_law = "pairs"
  double orphan_fraction = 0.0;
  bool record_contact_nodes = false; // output.contact_nodes
  TimeStepSetup time_step;

  double friction(int a, int b) const { return pair_friction[a * num_bodies + b]; }
  int interface_of(int a, int b) const { return pair_interface[a * num_bodies + b]; }
  // Whether the pair (a, b) meets at surface points (law = "surface"), not node by node.
  bool surface(int a, int b) const {
    for (const SurfacePair& p : surface_pairs)
      if ((p.body == a && p.rigid == b) || (p.body == b && p.rigid == a)) return true;
    return false;
  }
  // Body `body`'s slot for interface f in its field's interface arrays.
  int slot(int body, int f) const { return interface_slots[body * num_interfaces + f]; }

  // The body force of a particle of mass m of body b at x: m g, less the weight of the water it
  // displaces below the level (its submerged share of m rho_w / rho).
  Vec<D> weight(double m, int b, const Vec<D>& x) const {
    if (!water.on) return m * gravity;
    const BodySetup<D>& body = bodies[b];
    const double f = submerged_fraction(water.level, water.up.dot(x), body.particle_height);
    return (m * (1.0 - body.buoyancy * f)) * gravity;
  }
};

// Builds the setup of case c on its grid, with each body's total mass (Seeded::body_mass).
template <int D>
Setup<D> make_setup(const Case& c, const Grid<D>& grid, const std::vector<double>& body_mass);

} // namespace talus
