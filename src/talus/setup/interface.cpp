#include "talus/setup/interface.hpp"

#include "talus/case/parse.hpp"

#include <cmath>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <unordered_map>
#include <vector>

namespace talus {

// The interface degradation law (paper Figure 11): property value at slip s.
double Degradation::at(double s, DegradationCurve curve) const {
  const double r = s / slip;
  switch (curve) {
  case DegradationCurve::linear:
    return initial + (residual - initial) * std::min(1.0, r);
  case DegradationCurve::bilinear:
    return r <= 0.5 ? initial : initial + (residual - initial) * std::min(1.0, 2.0 * r - 1.0);
  case DegradationCurve::exponential:
    return residual + (initial - residual) * std::exp(-3.0 * r);
  }
  return initial;
}

namespace {

// Particles binned by grid cell, to visit those near a point (in the 3^D cells around it).
template <int D>
class CellBins {
public:
  CellBins(const Case& c, const Particles<D>& P, std::size_t begin, std::size_t end)
      : c_(c), P_(P) {
    for (std::size_t q = begin; q < end; ++q)
      bins_[key(P.x[q])].push_back(q);
  }
  template <class F>
  void for_each_near(const Vec<D>& x, F&& f) const {
    Index<D> o{};
    for (int d = 0; d < D; ++d)
      o[d] = -1;
    for (;;) {
      Vec<D> probe = x;
      for (int d = 0; d < D; ++d)
        probe[d] += static_cast<double>(o[d]) * c_.grid.cell_size;
      if (auto it = bins_.find(key(probe)); it != bins_.end())
        for (const std::size_t q : it->second)
          if (f(q)) return; // f returns true to stop
      int d = D - 1;
      while (d >= 0 && ++o[d] == 2)
        o[d] = -1, --d;
      if (d < 0) return;
    }
  }

private:
  std::int64_t key(const Vec<D>& x) const {
    std::int64_t k = 0;
    for (int d = 0; d < D; ++d)
      k = k * 2000003 +
          static_cast<std::int64_t>(std::floor((x[d] - c_.grid.origin[d]) / c_.grid.cell_size));
    return k;
  }
  const Case& c_;
  const Particles<D>& P_;
  std::unordered_map<std::int64_t, std::vector<std::size_t>> bins_;
};

double spacing(const Case& c, int body) {
  return c.grid.cell_size / c.bodies[body].particles_per_cell;
}

} // namespace

template <int D>
std::vector<std::size_t> mark_interface_particles(const Case& c, Particles<D>& P,
                                                  const std::vector<char>* counted) {
  std::vector<std::size_t> marked(2 * c.interfaces.size(), 0);
  for (std::size_t f = 0; f < c.interfaces.size(); ++f) {
    const InterfaceSpec& spec = c.interfaces[f];
    for (int side = 0; side < 2; ++side) {
      const int self = side == 0 ? spec.a : spec.b, other = side == 0 ? spec.b : spec.a;
      const CellBins<D> bins(c, P, P.body_begin[other], P.body_begin[other + 1]);
      const double s = spacing(c, self);
      const double reach = 1.5 * std::max(s, spacing(c, other));
      for (std::size_t p = P.body_begin[self]; p < P.body_begin[self + 1]; ++p) {
        bool near = false;
        bins.for_each_near(P.x[p],
                           [&](std::size_t q) { return near = (P.x[q] - P.x[p]).norm() <= reach; });
        if (!near) continue;
        marked[2 * f + side] += !counted || (*counted)[p];
        P.iface[p] = static_cast<std::int32_t>(f);
        P.iface_area[p] = std::pow(s, D - 1);
        P.cohesion[p] = spec.cohesion.initial;
        P.friction[p] = spec.friction.initial;
        P.slip[p] = 0.0;
      }
    }
  }
  return marked;
}

std::vector<std::string> unbonded_interface_warnings(const Case& c,
                                                     const std::vector<std::size_t>& marked) {
  std::vector<std::string> warnings;
  for (std::size_t f = 0; f < c.interfaces.size(); ++f) {
    const InterfaceSpec& spec = c.interfaces[f];
    for (int side = 0; side < 2; ++side) {
      if (marked[2 * f + side] > 0) continue;
      const int self = side == 0 ? spec.a : spec.b, other = side == 0 ? spec.b : spec.a;
      const double reach = 1.5 * std::max(spacing(c, self), spacing(c, other));
      warnings.push_back(fmt::format(
          "interface[{}] ({}-{}): no particle of '{}' lies within {:.3g} m of '{}' at the "
          "start, so the interface bonds nothing; where the bodies meet later they slide with "
          "its initial friction {}",
          f, c.bodies[spec.a].name, c.bodies[spec.b].name, c.bodies[self].name, reach,
          c.bodies[other].name, spec.friction.initial));
    }
  }
  return warnings;
}

template <int D>
std::vector<std::string> mark_interface_particles(const Case& c, Particles<D>& P) {
  return unbonded_interface_warnings(c, mark_interface_particles(c, P, nullptr));
}

template <int D>
std::size_t find_body_overlap(const Case& c, const Particles<D>& P,
                              const std::vector<char>* checked, std::string& message) {
  const CellBins<D> bins(c, P, 0, P.size());
  for (int b = 0; b < P.num_bodies(); ++b)
    for (std::size_t p = P.body_begin[b]; p < P.body_begin[b + 1]; ++p) {
      if (checked && !(*checked)[p]) continue;
      std::size_t hit = P.size();
      bins.for_each_near(P.x[p], [&](std::size_t q) {
        const int o = P.body_of(q);
        // Touching bodies keep half a spacing each from their boundary: a spacing apart.
        if (o > b && (P.x[q] - P.x[p]).norm() < 0.5 * std::min(spacing(c, b), spacing(c, o)))
          hit = q;
        return hit != P.size();
      });
      if (hit == P.size()) continue;
      message = fmt::format(
          "{}: bodies '{}' and '{}' overlap near ({:.6g}): each point may belong to one body "
          "only (the overlap would count its mass twice)",
          c.file, c.bodies[b].name, c.bodies[P.body_of(hit)].name,
          fmt::join(P.x[p].data(), P.x[p].data() + D, ", "));
      return p;
    }
  return P.size();
}

template <int D>
void check_body_overlaps(const Case& c, const Particles<D>& P) {
  std::string message;
  if (find_body_overlap(c, P, nullptr, message) != P.size()) throw CaseError(message);
}

template std::vector<std::string> mark_interface_particles<2>(const Case&, Particles<2>&);
template std::vector<std::string> mark_interface_particles<3>(const Case&, Particles<3>&);
template std::vector<std::size_t> mark_interface_particles<2>(const Case&, Particles<2>&,
                                                              const std::vector<char>*);
template std::vector<std::size_t> mark_interface_particles<3>(const Case&, Particles<3>&,
                                                              const std::vector<char>*);
template std::size_t find_body_overlap<2>(const Case&, const Particles<2>&,
                                          const std::vector<char>*, std::string&);
template std::size_t find_body_overlap<3>(const Case&, const Particles<3>&,
                                          const std::vector<char>*, std::string&);
template void check_body_overlaps<2>(const Case&, const Particles<2>&);
template void check_body_overlaps<3>(const Case&, const Particles<3>&);

} // namespace talus
