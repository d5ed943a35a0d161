#include "talus/case/read_sweep.hpp"

#include "talus/case/terrain.hpp"

#include <cmath>
#include <fmt/format.h>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

namespace talus::case_reading {

namespace {

// A TOML value as the text `--set KEY=TEXT` takes (a string quoted, a number in its shortest
// form that reads back to the same double).
std::string toml_text(const toml::node& n) {
  if (n.is_floating_point()) return fmt::format("{}", n.value<double>().value());
  std::ostringstream os;
  n.visit([&](const auto& v) { os << v; });
  return os.str();
}

SweepParameter read_parameter(TableReader& r, const std::string& design) {
  SweepParameter p;
  p.key = r.string("key");
  if (p.key.empty() || p.key.find('=') != std::string::npos)
    r.fail("key", "must be a key path as --set takes it (e.g. interface.0.friction.residual)");
  if (p.key.rfind("sweep.", 0) == 0 || p.key.rfind("observed.", 0) == 0)
    r.fail("key", "a sweep varies the case, not its own [sweep] or [observed] tables");
  p.line = r.raw().get("key")->source().begin.line;
  if (const toml::array* a = r.array("values")) {
    if (a->size() < (design == "grid" ? 1u : 2u))
      r.fail("values", design == "grid" ? "give at least one value" : "give at least two values");
    for (const toml::node& v : *a) {
      if (v.is_table() || v.is_array())
        r.fail("values", "each value must be a number, a string or true/false");
      if (v.is_floating_point() && !std::isfinite(v.value<double>().value()))
        r.fail("values", "each number must be finite");
      p.values.push_back(toml_text(v));
    }
    for (const char* k : {"range", "distribution", "mean", "sd", "mode", "levels"})
      if (r.has(k)) r.fail(k, "a parameter takes either `values` or a range and distribution");
    return p;
  }
  p.distribution =
      r.choice("distribution", {"uniform", "normal", "lognormal", "triangular"}, "uniform");
  if (r.has("range")) {
    const Vec3a v = r.vector("range", 2);
    require(r, "range", v[0] < v[1], "must be [low, high] with low < high");
    p.lo = v[0], p.hi = v[1];
  }
  p.mean = r.optional_number("mean");
  p.sd = r.optional_number("sd");
  p.mode = r.optional_number("mode");
  const bool centred = p.distribution == "normal" || p.distribution == "lognormal";
  if (!centred && !p.lo) r.fail_missing("range");
  if (centred) {
    if (!p.mean) r.fail_missing("mean");
    if (!p.sd) r.fail_missing("sd");
    require(r, "sd", *p.sd > 0.0, "must be > 0");
    if (p.distribution == "lognormal") {
      require(r, "mean", *p.mean > 0.0, "must be > 0 for a lognormal value");
      if (p.lo) require(r, "range", *p.lo >= 0.0, "a lognormal value is positive");
    }
    if (p.lo) require(r, "mean", *p.mean > *p.lo && *p.mean < *p.hi, "must lie inside the range");
  } else {
    for (const char* k : {"mean", "sd"})
      if (r.has(k)) r.fail(k, fmt::format("not used by a {} distribution", p.distribution));
  }
  if (p.distribution == "triangular") {
    if (!p.mode) r.fail_missing("mode");
    require(r, "mode", *p.mode >= *p.lo && *p.mode <= *p.hi, "must lie inside the range");
  } else if (p.mode) {
    r.fail("mode", "only a triangular distribution has a mode");
  }
  if (design == "grid") {
    if (p.distribution != "uniform")
      r.fail("distribution", "a grid design takes evenly spaced levels: use the Latin hypercube "
                             "(design = \"lhs\") for a distribution");
    p.levels = r.integer("levels", 0, 2, 1000);
    if (p.levels == 0) r.fail_missing("levels");
  } else if (r.has("levels")) {
    r.fail("levels", "only a grid design (design = \"grid\") has levels");
  }
  return p;
}

// An observed outline: GeoJSON (as talus writes its own) holding at least one polygon, in the
// maps' coordinates (read as they are: GeoJSON without a "crs" member is not taken as degrees).
void check_outline(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (j.is_discarded() || !j.is_object())
    throw CaseError(fmt::format("{}: not GeoJSON (a JSON object)", path));
  std::vector<nlohmann::json> geometries;
  if (j.value("type", "") == "FeatureCollection" && j.contains("features") &&
      j["features"].is_array()) {
    for (const auto& f : j["features"])
      if (f.is_object() && f.contains("geometry")) geometries.push_back(f["geometry"]);
  } else {
    geometries.push_back(j.value("type", "") == "Feature" && j.contains("geometry") ? j["geometry"]
                                                                                    : j);
  }
  for (const auto& g : geometries)
    if (g.is_object() && g.contains("coordinates") &&
        (g.value("type", "") == "Polygon" || g.value("type", "") == "MultiPolygon"))
      return;
  throw CaseError(fmt::format("{}: no Polygon or MultiPolygon in it", path));
}

} // namespace

// [sweep] and its [[sweep.parameter]] entries.
void read_sweep(TableReader& root, Case& c) {
  const toml::table* t = root.table("sweep");
  if (!t) return;
  TableReader rs(*t, "sweep", root.where());
  SweepSettings& s = c.sweep;
  s.present = true;
  s.design = rs.choice("design", {"lhs", "grid"}, "lhs");
  if (s.design == "lhs") {
    s.runs = rs.integer("runs", 0, 1, 100000);
    if (s.runs == 0) rs.fail_missing("runs");
  } else if (rs.has("runs")) {
    rs.fail("runs", "a grid design runs every combination of the levels: leave `runs` out");
  }
  if (const toml::node* n = rs.find("seed")) {
    if (!n->is_integer() || n->value<long long>().value() < 0)
      rs.fail("seed", "expected an integer >= 0");
    s.seed = n->value<long long>().value();
  }
  const toml::array* params = rs.array("parameter");
  if (!params || params->empty())
    rs.fail("parameter", "give at least one [[sweep.parameter]] (the values a sweep varies)");
  long long combinations = 1;
  for (std::size_t i = 0; i < params->size(); ++i) {
    const toml::node* n = params->get(i);
    if (!n->is_table())
      rs.where().fail(n->source(), fmt::format("sweep.parameter[{}]", i),
                      "expected a table: write [[sweep.parameter]] sections");
    TableReader r(*n->as_table(), fmt::format("sweep.parameter[{}]", i), rs.where());
    SweepParameter p = read_parameter(r, s.design);
    for (const SweepParameter& q : s.parameters)
      if (q.key == p.key) r.fail("key", "two parameters vary this key");
    r.finish();
    combinations *= p.values.empty() ? p.levels : static_cast<long long>(p.values.size());
    if (s.design == "grid" && combinations > 100000)
      r.fail("levels", "the grid has more than 100,000 runs");
    s.parameters.push_back(std::move(p));
  }
  if (const toml::table* e = rs.table("exceed")) {
    TableReader re(*e, "sweep.exceed", rs.where());
    for (const char* field :
         {"peak_thickness", "peak_speed", "peak_kinetic_energy", "peak_pressure"}) {
      const toml::array* a = re.array(field);
      if (!a) continue;
      std::vector<double> thresholds;
      for (std::size_t k = 0; k < a->size(); ++k) {
        const double v = re.as_number(*a->get(k), fmt::format("{}[{}]", field, k));
        if (!(v > 0.0)) re.fail(field, "each threshold must be > 0");
        thresholds.push_back(v);
      }
      if (thresholds.empty()) re.fail(field, "give at least one threshold");
      s.exceed.emplace_back(field, thresholds);
    }
    re.finish();
  }
  rs.finish();
}

// [observed]: an impact outline, a deposit raster and figures, for a sweep's back-analysis.
void read_observed(TableReader& root, Case& c, InputFiles& files) {
  const toml::table* t = root.table("observed");
  if (!t) return;
  TableReader ro(*t, "observed", root.where());
  ObservedSettings& o = c.observed;
  o.present = true;
  const bool on_map = c.simulation.dimension == 3;
  auto file = [&](const char* key) {
    const std::string written = ro.string(key);
    if (written.empty()) ro.fail(key, "the file name is empty");
    if (!on_map) ro.fail(key, "an observed map needs a 3D case with [maps]; in 2D give `figures`");
    if (!c.maps.enabled) ro.fail(key, "scoring against a map needs the run's [maps]");
    const std::string path = files.resolve(written);
    try {
      check_input_file(path, max_input_bytes);
      files.add_sidecars(path);
      if (std::string(key) == "impact_area") {
        check_outline(path);
      } else {
        read_raster(path, {0.0, 0.0, 0.0});
      }
    } catch (const CaseError& e) {
      ro.fail(key, e.what());
    }
    return path;
  };
  if (ro.has("impact_area")) o.impact_area = file("impact_area");
  if (ro.has("deposit_thickness")) o.deposit_thickness = file("deposit_thickness");
  o.deposit_threshold = ro.number("deposit_threshold", 0.1);
  require(ro, "deposit_threshold", o.deposit_threshold > 0.0, "must be > 0 m");
  if (const toml::table* f = ro.table("figures")) {
    TableReader rf(*f, "observed.figures", ro.where());
    for (auto&& [k, v] : *f) {
      const std::string key(k.str());
      rf.has(key);
      std::array<double, 2> range{};
      if (v.is_array()) {
        const Vec3a r2 = rf.vector(key, 2);
        if (!(r2[0] <= r2[1])) rf.fail(key, "a range must be [low, high] with low <= high");
        range = {r2[0], r2[1]};
      } else {
        const double x = rf.number(key);
        range = {x, x};
      }
      if (range[0] == 0.0 && range[1] == 0.0)
        rf.fail(key, "an observed figure of 0 has no relative miss: give a range around it");
      o.figures.emplace_back(key, range);
    }
    rf.finish();
  }
  if (o.impact_area.empty() && o.deposit_thickness.empty() && o.figures.empty())
    ro.fail("impact_area", "give what was observed: impact_area, deposit_thickness or figures");
  ro.finish();
}

} // namespace talus::case_reading
