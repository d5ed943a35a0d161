// Particles<D>: plain structure-of-arrays state, stored contiguously by body: body b owns the
// index range [body_begin[b], body_begin[b+1]). Every per-particle array is listed in
// for_each_array, so sorting, checkpoints and the processes' exchange see all state (no hidden
// state); an optional array (for_each_optional: APIC's C) is empty or one entry a particle, and
// sorting, checkpoints and the processes' exchange (Distributed::each_array) take it too.
#pragma once

#include "talus/core/math.hpp"

#include <cstdint>
#include <tuple>
#include <vector>

namespace talus {

template <int D>
struct Particles {
  std::vector<Vec<D>> x;         // position
  std::vector<Vec<D>> x0;        // initial position (for displacement)
  std::vector<Vec<D>> v;         // velocity
  std::vector<double> m;         // mass
  std::vector<double> vol0;      // initial volume (per unit thickness in 2D)
  std::vector<double> vol;       // current volume = vol0 det F
  std::vector<Voigt> stress;     // Cauchy stress, tension positive
  std::vector<Mat<D>> F;         // deformation gradient
  std::vector<double> eps_p;     // equivalent plastic strain (0 for elastic materials)
  std::vector<std::uint32_t> id; // stable particle id (index at creation), survives sorting
  // Interface particles (paper section 2.4): interface index or -1, contact area A^p (length per
  // unit thickness in 2D), current cohesion c^p (Pa) and friction coefficient, accumulated slip.
  std::vector<std::int32_t> iface;
  std::vector<double> iface_area, cohesion, friction, slip;
  // An interface particle on an interface with pore pressure: the offset of its state in
  // Simulation's pool (Simulation::pore_state: its normal stress, band temperature and pore
  // pressure rises, then a band's profiles), or -1.
  std::vector<std::int64_t> pore;
  // The body velocity field the particle maps to: its own body's, or, for an orphan (a particle
  // cut off from its body inside another one, contact.orphan_fraction), that body's.
  std::vector<std::int32_t> field;
  // Under APIC (simulation.apic) the particle's affine velocity C_p (its field's velocity
  // gradient at its last G2P); empty otherwise. Optional arrays are either empty or of size();
  // sorting, checkpoints, the golden hashes (for_each_optional) and the processes' exchange
  // take them.
  std::vector<Mat<D>> C;

  std::vector<std::size_t> body_begin{0}; // size = bodies + 1

  std::size_t size() const { return x.size(); }
  int num_bodies() const { return static_cast<int>(body_begin.size()) - 1; }
  int body_of(std::size_t p) const {
    int b = 0;
    while (p >= body_begin[b + 1])
      ++b;
    return b;
  }

  // Every per-particle array, in the order checkpoints store them.
  static constexpr auto arrays() {
    return std::make_tuple(&Particles::x, &Particles::x0, &Particles::v, &Particles::m,
                           &Particles::vol0, &Particles::vol, &Particles::stress, &Particles::F,
                           &Particles::eps_p, &Particles::id, &Particles::iface,
                           &Particles::iface_area, &Particles::cohesion, &Particles::friction,
                           &Particles::slip, &Particles::field, &Particles::pore);
  }
  template <class Fn>
  void for_each_array(Fn&& f) {
    std::apply([&](auto... a) { (f(this->*a), ...); }, arrays());
  }
  // Every optional array (empty, or one entry per particle), in checkpoint order.
  template <class Fn>
  void for_each_optional(Fn&& f) {
    f(C);
  }
  // f(a's array, b's array) for every array of two particle sets.
  template <class Fn>
  static void for_each_array_pair(Particles& a, Particles& b, Fn&& f) {
    std::apply([&](auto... m) { (f(a.*m, b.*m), ...); }, arrays());
  }

  void reserve(std::size_t n) {
    for_each_array([n](auto& a) { a.reserve(n); });
  }

  void push_back(const Vec<D>& pos, const Vec<D>& vel, double mass, double volume) {
    x.push_back(pos);
    x0.push_back(pos);
    v.push_back(vel);
    m.push_back(mass);
    vol0.push_back(volume);
    vol.push_back(volume);
    stress.push_back(Voigt::Zero());
    F.push_back(Mat<D>::Identity());
    eps_p.push_back(0.0);
    id.push_back(static_cast<std::uint32_t>(id.size()));
    iface.push_back(-1);
    iface_area.push_back(0.0);
    cohesion.push_back(0.0);
    friction.push_back(0.0);
    slip.push_back(0.0);
    pore.push_back(-1);
    if (!C.empty()) C.push_back(Mat<D>::Zero()); // an optional array in use keeps one a particle
    field.push_back(num_bodies()); // the body being filled: body_begin grows when it is complete
  }
};

} // namespace talus
