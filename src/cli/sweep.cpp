#include "sweep.hpp"

#include "talus/case/parse.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <unistd.h>

namespace talus {

namespace {

// The values a parameter can take at its extremes: each is tried as an override before any run,
// so a key the case does not have or a value it refuses fails here, naming the sweep's line.
std::vector<std::string> extreme_values(const SweepParameter& p) {
  if (!p.values.empty()) return p.values;
  std::vector<std::string> v;
  if (p.lo) v = {fmt::format("{}", *p.lo), fmt::format("{}", *p.hi)};
  if (p.mean) v.push_back(fmt::format("{}", *p.mean));
  return v;
}

nlohmann::json parameter_json(const SweepParameter& p) {
  nlohmann::json j = {{"key", p.key}, {"distribution", p.distribution}};
  if (!p.values.empty()) j = {{"key", p.key}, {"values", p.values}};
  if (p.lo) j["range"] = {*p.lo, *p.hi};
  if (p.mean) j["mean"] = *p.mean;
  if (p.sd) j["sd"] = *p.sd;
  if (p.mode) j["mode"] = *p.mode;
  if (p.levels) j["levels"] = p.levels;
  return j;
}

} // namespace

int run_sweep(const SweepOptions& opt) {
  const Case c = parse_case_file(opt.case_file, opt.overrides);
  if (!c.sweep.present)
    throw CaseError(fmt::format("{}: no [sweep] table: a sweep needs its parameters "
                                "(docs/case-file.md, \"[sweep]\")",
                                opt.case_file));
  for (std::size_t i = 0; i < c.sweep.parameters.size(); ++i) {
    const SweepParameter& p = c.sweep.parameters[i];
    for (const std::string& value : extreme_values(p)) {
      std::vector<std::string> set = opt.overrides;
      set.push_back(p.key + "=" + value);
      try {
        parse_case_file(opt.case_file, set);
      } catch (const CaseError& e) {
        throw CaseError(fmt::format("{}:{}: sweep.parameter[{}].key: the case with {}={}: {}",
                                    opt.case_file, p.line, i, p.key, value, e.what()));
      }
    }
  }
  nlohmann::json plan;
  plan["case"] = std::filesystem::absolute(opt.case_file).string();
  plan["overrides"] = opt.overrides;
  plan["dimension"] = c.simulation.dimension;
  plan["maps"] = c.maps.enabled;
  plan["design"] = c.sweep.design;
  plan["runs"] = c.sweep.runs;
  plan["seed"] = c.sweep.seed;
  plan["parameters"] = nlohmann::json::array();
  for (const SweepParameter& p : c.sweep.parameters)
    plan["parameters"].push_back(parameter_json(p));
  plan["exceed"] = nlohmann::json::object();
  for (const auto& [field, thresholds] : c.sweep.exceed)
    plan["exceed"][field] = thresholds;
  if (c.observed.present) {
    nlohmann::json o;
    if (!c.observed.impact_area.empty())
      o["impact_area"] = std::filesystem::absolute(c.observed.impact_area).string();
    if (!c.observed.deposit_thickness.empty())
      o["deposit_thickness"] = std::filesystem::absolute(c.observed.deposit_thickness).string();
    o["deposit_threshold"] = c.observed.deposit_threshold;
    o["figures"] = nlohmann::json::object();
    for (const auto& [key, range] : c.observed.figures)
      o["figures"][key] = {range[0], range[1]};
    o["terrain_origin"] = {c.terrain_origin[0], c.terrain_origin[1], c.terrain_origin[2]};
    plan["observed"] = o;
  }
  const std::string out =
      opt.out_dir.empty()
          ? "runs/" + std::filesystem::path(opt.case_file).stem().string() + "_sweep"
          : opt.out_dir;
  std::vector<std::string> args = {
      "/usr/bin/python3", opt.source_dir + "/tools/sweep.py", "--talus", opt.self,   "--out", out,
      "--threads",        std::to_string(opt.threads),        "--plan",  plan.dump()};
  if (opt.jobs > 0) args.insert(args.end(), {"--jobs", std::to_string(opt.jobs)});
  if (!opt.launcher.empty()) args.insert(args.end(), {"--launcher", opt.launcher});
  std::vector<char*> argv;
  for (auto& a : args)
    argv.push_back(a.data());
  argv.push_back(nullptr);
  ::execv(argv[0], argv.data());
  fmt::print(stderr, "error: sweep: cannot run {}: {}\n", args[0], std::strerror(errno));
  return 2;
}

} // namespace talus
