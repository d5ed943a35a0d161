// The stress a run starts from (a slide starts from a geostatic state).
#pragma once

#include "talus/case/case.hpp"
#include "talus/core/particles.hpp"

namespace talus {

// K0 procedure: in each grid column (cells of the vertical axis, the last one), the vertical
// stress of a particle is -|g| times the mass above it (all bodies, half its own) per unit
// column area, and the horizontal stresses are K0 times that. Exact for horizontal layers;
// for slopes a starting point that a short damped phase brings to equilibrium.
template <int D>
void apply_k0_stress(const Case& c, Particles<D>& P);

} // namespace talus
