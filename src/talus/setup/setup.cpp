#include "talus/setup/setup.hpp"

#include "talus/setup/interface.hpp"

#include <algorithm>
#include <cmath>

namespace talus {

template <int D>
Setup<D> make_setup(const Case& c, const Grid<D>& grid, const std::vector<double>& body_mass) {
  Setup<D> s;
  const int B = static_cast<int>(body_mass.size());
  const int F = static_cast<int>(c.interfaces.size());
  s.num_bodies = B, s.num_interfaces = F;
  for (int b = 0; b < B; ++b) {
    const BodySpec& spec = c.bodies[b];
    BodySetup<D> body;
    body.name = spec.name;
    body.material = c.materials[spec.material];
    body.material.prepare();
    body.density = c.materials[spec.material].density();
    body.gimp = GimpFactors(c.grid.cell_size, 0.5 * c.grid.cell_size / spec.particles_per_cell);
    body.particle_height = c.grid.cell_size / spec.particles_per_cell;
    // A water body below the level is the water itself: its full weight, held by its pressure.
    body.fluid = std::holds_alternative<Fluid>(c.materials[spec.material].model);
    if (c.water.level && !spec.rigid && !body.fluid) body.buoyancy = c.water.density / body.density;
    for (int d = 0; d < D; ++d)
      body.rigid_velocity[d] = spec.velocity[d];
    body.rigid = spec.rigid;
    body.fixed = spec.fixed(D);
    if (spec.geometric_normal) body.normal_geometry = spec.geometry[0];
    body.mass = body_mass[b];
    s.bodies.push_back(std::move(body));
  }
  s.interfaces = c.interfaces;
  // A band's grid reaches 8 diffusion lengths of the run (settling aside: nothing slips then),
  // and at least 10 band thicknesses.
  for (const InterfaceSpec& f : c.interfaces) {
    s.bands.emplace_back();
    s.interface_pressure.push_back(has_pore_state(f));
    s.pore_pressure = s.pore_pressure || s.interface_pressure.back();
    if (!f.thermal_pressurization) continue;
    const BandProperties& band = f.thermal_pressurization->band;
    const double alpha = std::max(band.thermal_diffusivity, band.hydraulic_diffusivity);
    s.bands.back().emplace(
        band, std::max(10.0 * band.thickness, 8.0 * std::sqrt(alpha * c.simulation.end_time)));
    s.heating = true;
  }
  // A pair slides with the default friction; an interface pair with its interface's initial
  // friction where no interface particle is (bodies that meet only later), unless a [[contact]]
  // entry names the pair.
  s.pair_friction.assign(B * B, c.contact.friction);
  s.pair_interface.assign(B * B, -1);
  for (int f = 0; f < F; ++f) {
    const int a = c.interfaces[f].a, b = c.interfaces[f].b;
    s.pair_interface[a * B + b] = s.pair_interface[b * B + a] = f;
    s.pair_friction[a * B + b] = s.pair_friction[b * B + a] = c.interfaces[f].friction.initial;
  }
  s.surface_rigid.assign(B, 0);
  for (const ContactPair& pair : c.contact.pairs) {
    s.pair_friction[pair.a * B + pair.b] = s.pair_friction[pair.b * B + pair.a] = pair.friction;
    if (!pair.surface) continue;
    const bool a_rigid = c.bodies[pair.a].rigid;
    const int soft = a_rigid ? pair.b : pair.a, rigid = a_rigid ? pair.a : pair.b;
    s.surface_pairs.push_back(
        {soft, rigid, c.bodies[soft].geometry[0], c.bodies[rigid].geometry[0]});
    s.surface_rigid[rigid] = 1;
  }
  // Each interface takes the next slot of each of its two bodies' fields.
  s.interface_slots.assign(B * F, -1);
  std::vector<int> slots(B, 0);
  for (int f = 0; f < F; ++f)
    for (const int b : {c.interfaces[f].a, c.interfaces[f].b})
      s.interface_slots[b * F + f] = slots[b]++;
  s.conditions = build_grid_conditions<D>(c, grid);
  s.contact_law.gap_cutoff = c.contact.gap_cutoff;
  // The B-spline's closed faces measure 9/8 the gap of linear and GIMP weights (ContactLaw).
  s.contact_law.gap_unit =
      c.grid.cell_size * (c.grid.shape == ShapeKind::bspline ? 9.0 / 8.0 : 1.0);
  for (int d = 0; d < D; ++d)
    s.gravity[d] = c.simulation.gravity[d];
  if (c.water.level) {
    s.water.on = true;
    s.water.level = *c.water.level;
    s.water.density = c.water.density;
    s.water.g = s.gravity.norm();
    s.water.up = -s.gravity / s.water.g;
  }
  s.scheme = c.simulation.scheme;
  s.shape = c.grid.shape;
  s.flip = c.simulation.flip;
  s.xpic = c.simulation.xpic;
  s.apic = c.simulation.apic;
  s.damping = c.simulation.damping;
  s.settle_damping = c.initial_state.settle_damping;
  s.hold_interfaces = c.initial_state.hold_interfaces;
  s.hold_contacts = c.initial_state.hold_contacts;
  s.normal_smoothing = c.contact.normal_smoothing;
  s.pairwise_nodes = c.contact.pairwise_nodes;
  s.orphan_fraction = c.contact.orphan_fraction;
  s.record_contact_nodes = c.output.contact_nodes;
  s.time_step.fixed_dt = c.simulation.dt;
  s.time_step.cfl = c.simulation.cfl;
  s.time_step.dt_max = c.simulation.dt_max;
  s.time_step.dt_min = c.simulation.dt_min;
  s.time_step.settle_cfl = c.initial_state.settle_cfl;
  return s;
}

template Setup<2> make_setup(const Case&, const Grid<2>&, const std::vector<double>&);
template Setup<3> make_setup(const Case&, const Grid<3>&, const std::vector<double>&);

} // namespace talus
