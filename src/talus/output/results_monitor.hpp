// The results monitor of a run (ResultsSpec): the headline figures in summary.json, tracked
// every step from StepFigures (one process's sums, or the same sums over several processes),
// and the energy budget of a body. Used by run/run.cpp only.
#pragma once

#include "talus/case/case.hpp"
#include "talus/output/frame_totals.hpp"
#include "talus/solver/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <vector>

namespace talus::results {

// Where the potential energy a body released went (since release): J, per metre in 2D.
template <int D>
nlohmann::json energy_budget(const Simulation<D>& sim, const FrameTotals<D>& totals, int b) {
  const BodyTotals<D>& T = totals.bodies[b];
  const double ke = T.kinetic_energy, gravity = T.gravity_work,
               contact = sim.contact_record().work[b];
  const double internal = sim.internal_work(b);
  const double elastic = T.strain_energy - sim.strain_energy_at_release(b);
  return {{"gravity_work_J", gravity},
          {"kinetic_J", ke},
          {"contact_work_J", contact},
          {"stress_work_J", internal},
          {"elastic_change_J", elastic},
          {"plastic_work_J", internal - elastic},
          {"unbalanced_J", gravity + contact - internal - ke}};
}

// What the results monitor tracks of one step, formed on one process or over several (Runner::
// step_figures): per probe its particle's speed, per interface its particles' largest pore
// pressure and band temperature (-inf: none), and the results body's sums of m and m |v| (in
// chunks of particle order, as Distributed::chunk_sums forms them), and per run-up probe the
// highest elevation of its body's particles over its region (-inf: none there) with the largest
// plan coordinates among the particles at that elevation.
struct StepFigures {
  std::vector<double> probe_speed, pore_peak, temperature_peak;
  std::vector<double> run_up, run_up_at; // run_up_at: D - 1 coordinates per probe
  double mass = 0.0, mass_speed = 0.0;
};
constexpr std::int64_t figure_chunk = 1024; // particles per chunk of the body sums

// The headline figures of a run (ResultsSpec), tracked every step.
template <int D>
class ResultsMonitor {
public:
  // `totals`: frame_totals(sim, probe_ids) of the state tracking starts from.
  ResultsMonitor(const Simulation<D>& sim, std::vector<std::uint32_t> probe_ids,
                 const FrameTotals<D>& totals)
      : body_(sim.case_().results.body), probe_ids_(std::move(probe_ids)) {
    probe_peak_.assign(probe_ids_.size(), 0.0);
    pore_peak_.assign(sim.setup().interfaces.size(), 0.0);
    temperature_peak_.assign(sim.setup().interfaces.size(), -inf);
    const std::size_t U = sim.case_().run_ups.size();
    run_up_.assign(U, -inf), run_up_time_.assign(U, 0.0), run_up_at_.assign(U * (D - 1), 0.0);
    if (body_ >= 0) centroid0_ = totals.bodies[body_].centroid;
  }

  int body() const { return body_; }
  const std::vector<std::uint32_t>& probe_ids() const { return probe_ids_; }

  // The step's figures (StepFigures), from this process's own particles and, on several
  // processes, a max or a chunk sum over all of them: the same bits on any number. Collective.
  StepFigures figures(const Simulation<D>& sim) {
    const auto& P = sim.particles();
    const std::size_t F = sim.setup().interfaces.size();
    StepFigures f;
    f.probe_speed.assign(probe_ids_.size(), 0.0);
    f.pore_peak.assign(F, -inf), f.temperature_peak.assign(F, -inf);
    for (std::size_t k = 0; k < probe_ids_.size(); ++k)
      if (const std::size_t p = sim.index_of(probe_ids_[k]);
          p < P.size() && P.id[p] == probe_ids_[k] && sim.is_own(p))
        f.probe_speed[k] = P.v[p].norm();
    for (std::size_t p = 0; p < P.size(); ++p) {
      if (P.pore[p] < 0 || !sim.is_own(p)) continue;
      const int i = P.iface[p];
      const InterfaceSpec& spec = sim.setup().interfaces[i];
      const ConstPoreRecord s = sim.pore_pool().at(P.pore[p]);
      f.pore_peak[i] = std::max(f.pore_peak[i], spec.pore_pressure + s.pressure_rise());
      if (spec.thermal_pressurization)
        f.temperature_peak[i] = std::max(
            f.temperature_peak[i], spec.thermal_pressurization->temperature + s.temperature_rise());
    }
    run_up_figures(sim, f);
    if (body_ >= 0) {
      const std::size_t begin = P.body_begin[body_], end = P.body_begin[body_ + 1];
      mass_.resize(P.size()), mass_speed_.resize(P.size());
      for (std::size_t p = begin; p < end; ++p)
        mass_[p] = P.m[p], mass_speed_[p] = P.m[p] * P.v[p].norm();
      f.mass = chunked_sum(sim, begin, end, mass_);
      f.mass_speed = chunked_sum(sim, begin, end, mass_speed_);
    }
    if (Exchange* ex = sim.exchange())
      for (std::vector<double>* v : {&f.probe_speed, &f.pore_peak, &f.temperature_peak}) {
        std::vector<double> lo(*v);
        ex->min_max(lo.data(), v->data(), static_cast<int>(v->size()));
      }
    return f;
  }

  // The run-up probes' step figures: the highest particle (with mass: not one an outflow face
  // emptied) of the probe's body over its region, ties to the largest plan coordinates, so that
  // the maximum over processes is the one process's.
  void run_up_figures(const Simulation<D>& sim, StepFigures& f) const {
    const auto& P = sim.particles();
    const std::vector<RunUpSpec>& ups = sim.case_().run_ups;
    f.run_up.assign(ups.size(), -inf), f.run_up_at.assign(ups.size() * (D - 1), -inf);
    for (std::size_t k = 0; k < ups.size(); ++k) {
      const RunUpSpec& u = ups[k];
      double* at = &f.run_up_at[k * (D - 1)];
      for (std::size_t p = P.body_begin[u.body]; p < P.body_begin[u.body + 1]; ++p) {
        if (P.m[p] <= 0.0 || !sim.is_own(p)) continue;
        bool inside = true;
        for (int d = 0; d < D - 1; ++d)
          inside = inside && P.x[p][d] >= u.min[d] && P.x[p][d] <= u.max[d];
        const double z = P.x[p][D - 1];
        if (!inside || z < f.run_up[k]) continue;
        if (z > f.run_up[k]) std::fill(at, at + D - 1, -inf);
        f.run_up[k] = z;
        for (int d = 0; d < D - 1; ++d)
          at[d] = std::max(at[d], P.x[p][d]);
      }
    }
    Exchange* ex = sim.exchange();
    if (!ex || ups.empty()) return;
    std::vector<double> lo(f.run_up), local(f.run_up);
    ex->min_max(lo.data(), f.run_up.data(), static_cast<int>(ups.size()));
    for (std::size_t k = 0; k < ups.size(); ++k) // only the processes that hold the highest
      if (local[k] < f.run_up[k])
        std::fill_n(f.run_up_at.begin() + static_cast<std::ptrdiff_t>(k * (D - 1)), D - 1, -inf);
    lo = f.run_up_at;
    ex->min_max(lo.data(), f.run_up_at.data(), static_cast<int>(f.run_up_at.size()));
  }

  void update(const StepFigures& f, double time, double stop_speed) {
    for (std::size_t k = 0; k < probe_ids_.size(); ++k)
      probe_peak_[k] = std::max(probe_peak_[k], f.probe_speed[k]);
    // The interfaces' largest excess pore pressure and band temperature so far.
    for (std::size_t i = 0; i < pore_peak_.size(); ++i) {
      pore_peak_[i] = std::max(pore_peak_[i], f.pore_peak[i]);
      temperature_peak_[i] = std::max(temperature_peak_[i], f.temperature_peak[i]);
    }
    for (std::size_t k = 0; k < run_up_.size(); ++k)
      if (f.run_up[k] > run_up_[k]) {
        run_up_[k] = f.run_up[k], run_up_time_[k] = time;
        std::copy_n(f.run_up_at.begin() + static_cast<std::ptrdiff_t>(k * (D - 1)), D - 1,
                    run_up_at_.begin() + static_cast<std::ptrdiff_t>(k * (D - 1)));
      }
    if (body_ < 0) return;
    const double speed = f.mass_speed / f.mass;
    if (speed > peak_) peak_ = speed, peak_time_ = time;
    if (speed >= stop_speed) last_moving_ = time;
    last_speed_ = speed;
  }

  // `totals`: frame_totals(sim, probe_ids()).
  nlohmann::json json(const Simulation<D>& sim, const FrameTotals<D>& totals,
                      double settle_ke) const {
    nlohmann::json j = nlohmann::json::object();
    const Case& c = sim.case_();
    if (c.initial_state.settle_time > 0.0) {
      j["settle_time_s"] = c.initial_state.settle_time;
      j["kinetic_energy_at_release_J"] = settle_ke;
    }
    nlohmann::json probes = nlohmann::json::object();
    for (std::size_t k = 0; k < probe_ids_.size(); ++k) {
      const ProbeState<D>& pr = totals.probes[k];
      probes[c.probes[k].name] = {{"peak_speed_m_s", probe_peak_[k]},
                                  {"displacement_x_m", pr.x[0] - pr.x0[0]},
                                  {"displacement_m", (pr.x - pr.x0).norm()}};
    }
    if (!probe_ids_.empty()) j["probes"] = probes;
    nlohmann::json water = nlohmann::json::object();
    for (std::size_t f = 0; f < c.interfaces.size(); ++f) {
      if (!sim.setup().interface_pressure[f]) continue;
      const std::string name =
          c.bodies[c.interfaces[f].a].name + "-" + c.bodies[c.interfaces[f].b].name;
      water[name]["peak_pore_pressure_Pa"] = pore_peak_[f];
      if (c.interfaces[f].thermal_pressurization)
        water[name]["peak_band_temperature_C"] = temperature_peak_[f];
    }
    if (!water.empty()) j["interfaces"] = water;
    // Run-up: the highest elevation reached over the region, above the probe's level (null:
    // the body never reached the region).
    nlohmann::json ups = nlohmann::json::object();
    for (std::size_t k = 0; k < run_up_.size(); ++k) {
      const RunUpSpec& u = c.run_ups[k];
      nlohmann::json& r = ups[u.name];
      r["body"] = c.bodies[u.body].name;
      r["level_m"] = u.level;
      if (!std::isfinite(run_up_[k])) {
        r["elevation_m"] = r["above_level_m"] = nullptr;
        continue;
      }
      r["elevation_m"] = run_up_[k];
      r["above_level_m"] = run_up_[k] - u.level;
      r["time_s"] = run_up_time_[k];
      for (int d = 0; d < D - 1; ++d)
        r[fmt::format("{}_m", "xy"[d])] = run_up_at_[k * (D - 1) + static_cast<std::size_t>(d)];
    }
    if (!ups.empty()) j["run_up"] = ups;
    if (body_ < 0) return j;
    j["body"] = c.bodies[body_].name;
    j["peak_mean_speed_m_s"] = peak_;
    j["peak_time_s"] = peak_time_;
    const bool stopped = last_speed_ < c.results.stop_speed;
    j["runout_duration_s"] = stopped ? nlohmann::json(last_moving_) : nlohmann::json(nullptr);
    j["still_moving_at_end"] = !stopped;
    j["centroid_displacement_x_m"] = totals.bodies[body_].centroid[0] - centroid0_[0];
    j["energy"] = energy_budget(sim, totals, body_);
    return j;
  }

  template <class Ar>
  void serialize(Ar& ar) {
    ar.io(probe_ids_), ar.io(probe_peak_), ar.io(centroid0_), ar.io(peak_), ar.io(peak_time_);
    ar.io(last_moving_), ar.io(last_speed_), ar.io(pore_peak_), ar.io(temperature_peak_);
    ar.io(run_up_), ar.io(run_up_time_), ar.io(run_up_at_);
  }

private:
  // The sum of value[begin, end) (the results body's), in chunks of figure_chunk particles in
  // particle order and then the chunks in order.
  double chunked_sum(const Simulation<D>& sim, std::size_t begin, std::size_t end,
                     const std::vector<double>& value) {
    std::vector<double>& sums = chunk_sums_;
    if (Exchange* ex = sim.exchange()) {
      ex->chunk_sums(body_, begin, end, value.data(), figure_chunk, sums);
    } else {
      sums.clear();
      for (std::size_t c = begin; c < end; c += figure_chunk) {
        double s = 0.0;
        for (std::size_t p = c; p < std::min<std::size_t>(end, c + figure_chunk); ++p)
          s += value[p];
        sums.push_back(s);
      }
    }
    double total = 0.0;
    for (const double s : sums)
      total += s;
    return total;
  }

  std::vector<double> mass_, mass_speed_, chunk_sums_; // figures()' scratch
  int body_;
  std::vector<std::uint32_t> probe_ids_;
  std::vector<double> probe_peak_;
  std::vector<double> pore_peak_, temperature_peak_;     // per interface
  std::vector<double> run_up_, run_up_time_, run_up_at_; // per run-up probe (at: D - 1 each)
  Vec<D> centroid0_ = Vec<D>::Zero();
  double peak_ = 0.0, peak_time_ = 0.0, last_moving_ = 0.0, last_speed_ = 0.0;
};

} // namespace talus::results
