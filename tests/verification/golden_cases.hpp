// The golden cases (golden_test.cpp) and the state hash they are checked by: every particle
// array and the contact, interface and energy totals (FNV-1a 64 over their bytes). The MPI tests
// (tests/mpi) check the same hashes on several processes.
#pragma once

#include "talus/case/parse.hpp"
#include "talus/output/checkpoint.hpp"
#include "talus/output/simulation_archive.hpp"
#include "talus/solver/diagnostics.hpp"
#include "talus/solver/simulation.hpp"

#include <cstdint>
#include <cstdlib>
#include <fmt/format.h>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace talus::golden {
// FNV-1a 64 over a sequence of byte ranges.
struct Hash {
  std::uint64_t h = 14695981039346656037ull;
  void bytes(const void* data, std::size_t n) {
    const auto* c = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < n; ++i)
      h = (h ^ c[i]) * 1099511628211ull;
  }
  template <class T>
  void add(const std::vector<T>& v) {
    const std::uint64_t n = v.size();
    bytes(&n, sizeof n);
    bytes(v.data(), v.size() * sizeof(T));
  }
  void add(double x) { bytes(&x, sizeof x); }
};

// The state's hash: every particle array, the clocks, and the totals the run folder records.
template <int D>
std::uint64_t state_hash(const Simulation<D>& sim) {
  Hash H;
  auto P = sim.particles(); // for_each_array is non-const
  // The band offsets (thermal pressurization) join the hash only where a case has bands: a dry
  // case's arrays are the dry model's, and its band offsets must all be -1.
  const bool banded = sim.setup().heating;
  P.for_each_array([&](const auto& a) {
    if (static_cast<const void*>(&a) != static_cast<const void*>(&P.pore) || banded) H.add(a);
  });
  P.for_each_optional([&](const auto& a) { // only where a case uses one (APIC's C)
    if (!a.empty()) H.add(a);
  });
  if (!banded)
    for (const auto o : P.pore)
      if (o != -1) throw std::logic_error("a band offset in a case without bands");
  if (banded) H.add(sim.pore_pool().data);
  H.add(sim.time()), H.add(sim.last_dt()), H.add(static_cast<double>(sim.steps()));
  const int B = sim.num_bodies();
  for (int a = 0; a < B; ++a)
    for (int b = 0; b < B; ++b)
      for (int d = 0; d < D; ++d)
        H.add(sim.contact_record().force(a, b)[d]), H.add(sim.contact_record().mean_force(a, b)[d]);
  for (std::size_t f = 0; f < sim.contact_record().interface_force.size(); ++f) {
    const InterfaceForce I = sim.contact_record().interface_force[f],
                         M = sim.contact_record().mean_interface_force(f);
    H.add(I.cohesive), H.add(I.frictional), H.add(I.normal);
    H.add(M.cohesive), H.add(M.frictional), H.add(M.normal);
  }
  for (int b = 0; b < B; ++b) {
    H.add(gravity_work(sim, b)), H.add(sim.contact_record().work[b]), H.add(sim.internal_work(b));
    H.add(strain_energy(sim, b)), H.add(sim.strain_energy_at_release(b));
  }
  for (const ContactNodeForce<D>& n : sim.contact_nodes()) {
    for (int d = 0; d < D; ++d)
      H.add(n.position[d]), H.add(n.force[d]), H.add(n.normal[d]);
    H.add(n.frictional), H.add(n.cohesive), H.add(static_cast<double>(n.body * 64 + n.other));
  }
  H.add(static_cast<double>(sim.orphans()));
  return H.h;
}

struct GoldenCase {
  const char* name;
  const char* file;
  std::vector<std::string> overrides;
  int settle_steps; // damped settling steps before release() (0: none)
  int steps;        // steps after release
  std::uint64_t hash;
};

// Runs the case and returns its hash; `restart_at` > 0 saves the state after that many steps
// into memory, restores it into a new simulation and finishes the run from there.
template <int D>
std::uint64_t run_case(const Case& c, const GoldenCase& g, int restart_at) {
  auto sim = std::make_unique<Simulation<D>>(c);
  const int total = g.settle_steps + g.steps;
  if (g.settle_steps > 0) sim->set_settling(true);
  for (int s = 0; s < total; ++s) {
    if (s == restart_at) {
      SaveArchive out;
      serialize_state(out, *sim, "memory");
      sim = std::make_unique<Simulation<D>>(c);
      LoadArchive in(out.bytes(), "memory");
      serialize_state(in, *sim, "memory");
    }
    if (s == g.settle_steps && g.settle_steps > 0) sim->release();
    sim->step(1.0);
  }
  if (std::getenv("TALUS_GOLDEN_PRINT"))
    fmt::print("golden {}: {} particles, {} orphans at the end\n", g.name, sim->particles().size(),
               sim->orphans());
  return state_hash(*sim);
}

inline std::uint64_t run_golden(const GoldenCase& g, int restart_at) {
  const Case c = parse_case_file(std::string(TALUS_SOURCE_DIR) + "/" + g.file, g.overrides);
  return c.simulation.dimension == 2 ? run_case<2>(c, g, restart_at)
                                     : run_case<3>(c, g, restart_at);
}

inline const std::vector<GoldenCase>& golden_cases() {
  static const std::vector<GoldenCase> cases = {
      // One deformable body (Drucker-Prager column) under each scheme and shape function.
      {"column_usf_linear",
       "cases/benchmarks/column_collapse.toml",
       {"grid.cell_size=0.01", "simulation.scheme=\"usf\"", "grid.shape_function=\"linear\""},
       0,
       200,
       0x5675e529275c3117ull},
      {"column_usl_linear",
       "cases/benchmarks/column_collapse.toml",
       {"grid.cell_size=0.01", "simulation.scheme=\"usl\"", "grid.shape_function=\"linear\""},
       0,
       200,
       0xb58c3232e999dcd2ull},
      {"column_musl_linear",
       "cases/benchmarks/column_collapse.toml",
       {"grid.cell_size=0.01", "simulation.scheme=\"musl\"", "grid.shape_function=\"linear\""},
       0,
       200,
       0xc033250ed9adb632ull},
      {"column_usf_gimp",
       "cases/benchmarks/column_collapse.toml",
       {"grid.cell_size=0.01", "simulation.scheme=\"usf\"", "grid.shape_function=\"gimp\""},
       0,
       200,
       0xca505df4485f5277ull},
      {"column_usl_gimp",
       "cases/benchmarks/column_collapse.toml",
       {"grid.cell_size=0.01", "simulation.scheme=\"usl\"", "grid.shape_function=\"gimp\""},
       0,
       200,
       0x3c807a162afc2ff2ull},
      {"column_musl_gimp",
       "cases/benchmarks/column_collapse.toml",
       {"grid.cell_size=0.01", "simulation.scheme=\"musl\"", "grid.shape_function=\"gimp\""},
       0,
       200,
       0x245cb42c3a06dcedull},
      // Quadratic B-splines (3 nodes per direction; open knots within 5/2 cells of a face).
      {"column_musl_bspline",
       "cases/benchmarks/column_collapse.toml",
       {"grid.cell_size=0.01", "simulation.scheme=\"musl\"", "grid.shape_function=\"bspline\""},
       0,
       200,
       0xe09957848d1207c1ull},
      // A block on a fixed rigid plane (the held field), with contact-node output, after
      // settling with the contact held (initial_state.hold_contacts).
      {"sliding_block",
       "cases/benchmarks/sliding_block.toml",
       {"contact.0.friction=0.174", "output.contact_nodes=true"},
       30,
       200,
       0x77365e87bf30f3ffull},
      // A cohesive interface that degrades with slip, after damped settling with the bond held.
      {"cohesive_block",
       "cases/benchmarks/cohesive_block.toml",
       {},
       60,
       200,
       0xfba917b9eb958cb0ull},
      // Three deformable bodies with interfaces, orphans and normal smoothing (the defaults),
      // K0 stresses and settling, under MUSL.
      {"vaiont_three",
       "cases/vaiont/three_bodies.toml",
       {"grid.cell_size=16", "interface.0.friction.slip=0.02", "interface.0.cohesion.slip=0.02",
        "output.contact_nodes=true"},
       50,
       200,
       0x84ae4ff05eb2588full},
      // The same with the reservoir (buoyant weights, K0 below the level) and thermal
      // pressurization of the clay layer (the pore pool, its restart).
      {"vaiont_three_wet",
       "cases/vaiont/three_bodies_wet.toml",
       {"grid.cell_size=16", "interface.0.friction.slip=0.02", "interface.0.cohesion.slip=0.02"},
       50,
       200,
       0x2b098ed6bb3f0c9cull},
      // The same with the lake as a water body below the level: the water's hydrostatic load
      // held where it meets the buoyed rock, an outflow face.
      {"vaiont_reservoir",
       "cases/vaiont/three_bodies_reservoir.toml",
       {"grid.cell_size=16", "interface.0.friction.slip=0.02", "interface.0.cohesion.slip=0.02"},
       50,
       200,
       0x3084fe8e695b7cc7ull},
      // The same three bodies under XPIC(3): v* by two gathers and scatters (their ghosts).
      {"vaiont_three_xpic",
       "cases/vaiont/three_bodies.toml",
       {"grid.cell_size=16", "interface.0.friction.slip=0.02", "interface.0.cohesion.slip=0.02",
        "simulation.xpic=3"},
       50,
       200,
       0xeb9c08ed63e0f29aull},
      // Five bodies: where orphans appear.
      {"vaiont_five",
       "cases/vaiont/five_bodies.toml",
       {"grid.cell_size=16", "initial_state.settle_time=0"},
       0,
       200,
       0xa798ccfdb09886b7ull},
      // Water as a body: a fluid (hydrostatic start, filled around a rigid slope) that an
      // elastic block, started at the waterline at 2 m/s, runs into; surface gauges.
      {"slide_into_tank",
       "cases/examples/slide_into_tank.toml",
       {"grid.cell_size=0.05",
        "body.slide.polygon=[[0.55, 0.35], [0.691421, 0.208579], [0.762132, 0.279289], "
        "[0.620711, 0.420711]]",
        "body.slide.velocity=[1.414214, -1.414214]"},
       0,
       200,
       0xc55328afe233362full},
      // The 3D sphere on a rigid plane.
      {"sphere_3d", "cases/benchmarks/rolling_sphere.toml", {}, 0, 200, 0xbaec6138267914f4ull},
      // APIC with quadratic B-splines: a disk rolling at its surface points (one process only:
      // the surface law).
      {"rolling_disk_apic",
       "cases/benchmarks/general_rolling_apic.toml",
       {"simulation.gravity=[4.905, -8.49570921113]", "contact.0.friction=10.0",
        "grid.cell_size=0.1"},
       0,
       200,
       0x9c5ef66b82ce7468ull},
      // The same disk node by node: APIC's C through the processes' exchange and checkpoints.
      {"rolling_disk_apic_node",
       "cases/benchmarks/general_rolling_apic.toml",
       {"simulation.gravity=[4.905, -8.49570921113]", "contact.0.friction=10.0",
        "grid.cell_size=0.1", "contact.0.law=\"nodes\""},
       0,
       200,
       0x6bfa28f96de0c414ull},
  };
  return cases;
}

} // namespace talus::golden
