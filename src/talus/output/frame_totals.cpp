#include "talus/output/frame_totals.hpp"

#include "talus/core/exact_sum.hpp"
#include "talus/solver/diagnostics.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace talus {

namespace {

// A body's exact sums, in `size` consecutive entries from s: count, m, m |v|, m |v|^2 / 2,
// gravity work, elastic energy, orphans, m x, m v.
template <int D>
struct BodySums {
  static constexpr int size = 7 + 2 * D;
  ExactSum* s;
  ExactSum& count() { return s[0]; }
  ExactSum& mass() { return s[1]; }
  ExactSum& mass_speed() { return s[2]; }
  ExactSum& kinetic() { return s[3]; }
  ExactSum& gravity() { return s[4]; }
  ExactSum& strain() { return s[5]; }
  ExactSum& orphans() { return s[6]; }
  ExactSum& mx(int d) { return s[7 + d]; }
  ExactSum& mv(int d) { return s[7 + D + d]; }
};

} // namespace

template <int D>
FrameTotals<D> frame_totals(const Simulation<D>& sim, const std::vector<std::uint32_t>& probe_ids) {
  const auto& P = sim.particles();
  const int B = sim.num_bodies();
  const std::size_t F = sim.setup().interfaces.size();
  // Every exact sum in one array (bodies, all particles' kinetic energy and momentum, then per
  // interface its area and area-weighted pressure and temperature), every largest value in another.
  const std::size_t all = static_cast<std::size_t>(B) * BodySums<D>::size;
  std::vector<ExactSum> sums(all + 1 + D + 3 * F);
  const std::vector<GaugeSpec>& gauges = sim.case_().gauges;
  // Largest values: each body's speed, each interface's pressure and temperature, and each
  // gauge's particle tops row by row (the grid's rows along the vertical).
  const std::int64_t rows = sim.grid().nodes[D - 1];
  std::vector<double> largest(B + 2 * F + gauges.size() * static_cast<std::size_t>(rows),
                              -std::numeric_limits<double>::infinity());
  auto body = [&](int b) { return BodySums<D>{&sums[b * BodySums<D>::size]}; };
  ExactSum* total = &sums[all];
  ExactSum* water = &sums[all + 1 + D];
  for (int b = 0; b < B; ++b) {
    BodySums<D> S = body(b);
    double& max_speed = largest[b];
    max_speed = 0.0;
    for (std::size_t p = P.body_begin[b]; p < P.body_begin[b + 1]; ++p) {
      if (!sim.is_own(p)) continue;
      const double speed = P.v[p].norm(), ke = 0.5 * P.m[p] * speed * speed;
      S.count() += 1.0;
      S.mass() += P.m[p];
      S.mass_speed() += P.m[p] * speed;
      S.kinetic() += ke;
      total[0] += ke;
      S.orphans() += P.field[p] != b ? 1.0 : 0.0;
      for (int d = 0; d < D; ++d) {
        S.mx(d) += P.m[p] * P.x[p][d];
        S.mv(d) += P.m[p] * P.v[p][d];
        total[1 + d] += P.m[p] * P.v[p][d];
      }
      max_speed = std::max(max_speed, speed);
    }
    add_energy_terms(sim, b, true, S.gravity(), S.strain());
  }
  // The interfaces' particles on their own body's field.
  for (std::size_t p = 0; p < P.size(); ++p) {
    const int f = P.iface[p];
    if (f < 0 || !sim.setup().interface_pressure[f] || P.field[p] != P.body_of(p) || !sim.is_own(p))
      continue;
    const double A = P.iface_area[p], pp = sim.interface_pore_pressure(p);
    water[3 * f] += A;
    water[3 * f + 1] += pp * A;
    largest[B + 2 * f] = std::max(largest[B + 2 * f], pp);
    if (sim.setup().bands[f]) {
      const double T = band_temperature(sim, p);
      water[3 * f + 2] += T * A;
      largest[B + 2 * f + 1] = std::max(largest[B + 2 * f + 1], T);
    }
  }
  // The gauges: the tops (centre + half a spacing) of the body's particles within half a cell of
  // the gauge's point in plan, the highest in each grid row (the column read after the sums).
  const double h = sim.grid().h, half = 0.5 * h, z0 = sim.grid().origin[D - 1];
  for (std::size_t k = 0; k < gauges.size(); ++k) {
    const GaugeSpec& g = gauges[k];
    const double top = 0.5 * h / sim.case_().bodies[g.body].particles_per_cell;
    double* row_top = &largest[B + 2 * F + k * static_cast<std::size_t>(rows)];
    for (std::size_t p = P.body_begin[g.body]; p < P.body_begin[g.body + 1]; ++p) {
      bool over = sim.is_own(p);
      for (int d = 0; d < D - 1 && over; ++d)
        over = std::abs(P.x[p][d] - g.at[d]) <= half;
      if (!over) continue;
      const auto r = std::clamp<std::int64_t>(
          static_cast<std::int64_t>(std::floor((P.x[p][D - 1] - z0) / h)), 0, rows - 1);
      row_top[r] = std::max(row_top[r], P.x[p][D - 1] + top);
    }
  }
  // The probes' particles, from the process that owns each (one contributor per entry).
  std::vector<double> probes(probe_ids.size() * 3 * D, 0.0);
  for (std::size_t k = 0; k < probe_ids.size(); ++k) {
    const std::size_t p = sim.index_of(probe_ids[k]);
    if (p >= P.size() || P.id[p] != probe_ids[k] || !sim.is_own(p)) continue;
    for (int d = 0; d < D; ++d)
      probes[3 * D * k + d] = P.x[p][d], probes[3 * D * k + D + d] = P.v[p][d],
                         probes[3 * D * k + 2 * D + d] = P.x0[p][d];
  }
  if (Exchange* ex = sim.exchange()) {
    ex->sum_exact(sums.data(), sums.size());
    std::vector<double> lo(largest);
    ex->min_max(lo.data(), largest.data(), static_cast<int>(largest.size()));
    ex->sum_disjoint(probes.data(), probes.size());
  }

  FrameTotals<D> t;
  for (int b = 0; b < B; ++b) {
    BodySums<D> S = body(b);
    BodyTotals<D> T;
    T.particles = static_cast<std::size_t>(S.count().value());
    T.mass = S.mass().value();
    for (int d = 0; d < D; ++d)
      T.centroid[d] = S.mx(d).value() / T.mass, T.velocity[d] = S.mv(d).value() / T.mass;
    T.mean_speed = S.mass_speed().value() / T.mass;
    T.max_speed = largest[b];
    T.kinetic_energy = S.kinetic().value();
    T.gravity_work = S.gravity().value();
    T.strain_energy = S.strain().value();
    T.orphans = static_cast<std::size_t>(S.orphans().value());
    t.bodies.push_back(T);
  }
  t.kinetic_energy = total[0].value();
  for (int d = 0; d < D; ++d)
    t.momentum[d] = total[1 + d].value();
  for (std::size_t f = 0; f < F; ++f) {
    InterfaceWater w;
    if (sim.setup().interface_pressure[f]) {
      const double area = water[3 * f].value();
      const bool band = sim.setup().bands[f].has_value();
      w.pressure_mean = area > 0.0 ? water[3 * f + 1].value() / area : 0.0;
      w.pressure_max = std::max(largest[B + 2 * f], 0.0);
      w.temperature_mean = band ? (area > 0.0 ? water[3 * f + 2].value() / area : 0.0)
                                : std::numeric_limits<double>::quiet_NaN();
      w.temperature_max = band ? largest[B + 2 * f + 1] : std::numeric_limits<double>::quiet_NaN();
    }
    t.water.push_back(w);
  }
  // Each gauge's surface: the top of its column from the lowest particle up to the first row
  // with none, so that spray thrown clear of the surface does not count (dry: no data).
  for (std::size_t k = 0; k < gauges.size(); ++k) {
    const double* row_top = &largest[B + 2 * F + k * static_cast<std::size_t>(rows)];
    std::int64_t r = 0;
    while (r < rows && !std::isfinite(row_top[r]))
      ++r;
    double high = -std::numeric_limits<double>::infinity();
    for (; r < rows && std::isfinite(row_top[r]); ++r)
      high = std::max(high, row_top[r]);
    t.gauges.push_back(std::isfinite(high) ? high : std::numeric_limits<double>::quiet_NaN());
  }
  for (std::size_t k = 0; k < probe_ids.size(); ++k) {
    ProbeState<D> s;
    for (int d = 0; d < D; ++d)
      s.x[d] = probes[3 * D * k + d], s.v[d] = probes[3 * D * k + D + d],
      s.x0[d] = probes[3 * D * k + 2 * D + d];
    t.probes.push_back(s);
  }
  return t;
}

template FrameTotals<2> frame_totals(const Simulation<2>&, const std::vector<std::uint32_t>&);
template FrameTotals<3> frame_totals(const Simulation<3>&, const std::vector<std::uint32_t>&);

} // namespace talus
