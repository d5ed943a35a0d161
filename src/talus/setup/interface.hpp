// Cohesive-frictional interfaces (paper section 2.4): which particles carry an interface, and how
// their cohesion and friction degrade with the slip they accumulate.
#pragma once

#include "talus/case/case.hpp"
#include "talus/core/particles.hpp"

#include <string>
#include <vector>

namespace talus {

// Marks, for each [[interface]] (a, b), the particles of a that have a particle of b within 1.5
// particle spacings, and vice versa: the first row of each body along the shared boundary. Each
// gets the contact area of its face, A^p = s^(D-1) (s the particle spacing of its body), and the
// interface's initial cohesion and friction. Returns a warning for each side with no such
// particle (bodies that do not touch at the start: the interface bonds nothing).
template <int D>
std::vector<std::string> mark_interface_particles(const Case& c, Particles<D>& P);
// The marking alone: returns the particles marked per interface f and side (2 f for a's, 2 f + 1
// for b's), counting only those with (*counted)[p] if counted is given.
template <int D>
std::vector<std::size_t> mark_interface_particles(const Case& c, Particles<D>& P,
                                                  const std::vector<char>* counted);
// The warnings for the sides that marked nothing.
std::vector<std::string> unbonded_interface_warnings(const Case& c,
                                                     const std::vector<std::size_t>& marked);

// Throws CaseError naming two bodies and a point if particles of different bodies lie closer than
// half a particle spacing (their shapes overlap; touching shapes keep a whole spacing).
template <int D>
void check_body_overlaps(const Case& c, const Particles<D>& P);
// The first particle (by body, then index) with (*checked)[p], or any if checked is null, that
// overlaps a later body's particle, and the error naming it in `message`; P.size() if none.
template <int D>
std::size_t find_body_overlap(const Case& c, const Particles<D>& P,
                              const std::vector<char>* checked, std::string& message);

// Whether an interface's particles carry pore-pressure state (Simulation::pore_state).
inline bool has_pore_state(const InterfaceSpec& f) {
  return f.pore_pressure != 0.0 || f.thermal_pressurization.has_value();
}

// Tensile strength of an interface particle with current cohesion c (degrades with it).
inline double tensile_strength(const InterfaceSpec& f, double c) {
  if (f.tensile_strength < 0.0) return c;
  return f.cohesion.initial > 0.0 ? f.tensile_strength * c / f.cohesion.initial
                                  : f.tensile_strength;
}

} // namespace talus
