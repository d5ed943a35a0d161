// talus: run | check | --version. A thin shell over the library; every error is one clear line.
#include "bench.hpp"
#include "sweep.hpp"
#include "talus/case/geometry.hpp"
#include "talus/case/parse.hpp"
#include "talus/case/size.hpp"
#include "talus/core/threads.hpp"
#include "talus/output/checkpoint.hpp"
#include "talus/output/files.hpp"
#include "talus/parallel/decomposition.hpp"
#include "talus/parallel/processes.hpp"
#include "talus/run/run.hpp"
#include "talus/setup/interface.hpp"
#include "talus/setup/seeds.hpp"
#include "talus/version.hpp"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fmt/format.h>
#include <iostream>
#include <limits>
#include <unistd.h>

namespace {

// Fills the bodies as a run would (so overlaps and interfaces that bond nothing are reported
// here too) and returns the particle count of each body.
template <int D>
std::vector<std::size_t> fill_for_check(const talus::Case& c) {
  talus::Particles<D> P = talus::fill_particles<D>(c);
  talus::check_body_overlaps<D>(c, P);
  for (const std::string& w : talus::mark_interface_particles<D>(c, P))
    fmt::print(stderr, "warning: {}\n", w);
  std::vector<std::size_t> n;
  for (int b = 0; b < P.num_bodies(); ++b)
    n.push_back(P.body_begin[b + 1] - P.body_begin[b]);
  return n;
}

int check(const talus::Case& c) {
  const int dim = c.simulation.dimension;
  const std::vector<std::size_t> counts = dim == 2 ? fill_for_check<2>(c) : fill_for_check<3>(c);
  fmt::print("case {}: {}\n", c.file, c.title);
  for (std::size_t b = 0; b < c.bodies.size(); ++b)
    fmt::print("  body {:<16} {:>10} particles  material {}\n", c.bodies[b].name, counts[b],
               c.materials[c.bodies[b].material].name);
  const talus::RunPlan plan = talus::plan_run(c, counts);
  constexpr double assumed_rate = 5e6; // particle-updates/s on 2 threads (docs/performance.md)
  fmt::print("  {} particles, {:.0f} grid nodes ({}D, cell {} m)\n", plan.particles,
             talus::grid_nodes(c.grid, dim), dim, c.grid.cell_size);
  fmt::print("  time step {:.3g} s ({}), about {:.3g} steps to {} s{}\n", plan.dt,
             c.simulation.dt ? "fixed" : "CFL at rest", plan.steps, c.simulation.end_time,
             c.initial_state.settle_time > 0.0
                 ? fmt::format(" after {} s of settling", c.initial_state.settle_time)
                 : std::string());
  fmt::print("  memory about {:.1f} MB (this machine: {:.1f} GB); run time about {:.3g} "
             "s at {:.0e} particle-updates/s\n",
             plan.memory_bytes / 1e6, talus::machine_memory() / 1e9,
             static_cast<double>(plan.particles) * plan.steps / assumed_rate, assumed_rate);
  // The frames and their size before compression (an upper bound: a frame compresses to 0.1-0.3
  // of it; docs/case-file.md, "Frame size").
  fmt::print("  output about {:.6g} frames, at most about {:.3g} GB before compression "
             "({:.0f} bytes per particle per frame)\n",
             plan.frames, plan.output_bytes / 1e9, plan.frame_bytes);
  for (const std::string& w : plan.warnings)
    fmt::print(stderr, "warning: {}\n", w);
  if (!plan.refusal.empty()) throw talus::CaseError(fmt::format("{}: {}", c.file, plan.refusal));
  if (!plan.disk_full.empty())
    throw talus::CaseError(fmt::format("{}: {}", c.file, plan.disk_full));
  return 0;
}

// TALUS_INJECT_SIGNAL=SIGNAL:STEP raises SIGNAL right after STEP (the restart tests' faults).
void inject_faults(talus::RunOptions& opt) {
  const char* spec = std::getenv("TALUS_INJECT_SIGNAL");
  if (!spec) return;
  int sig = 0;
  long long step = -1;
  if (std::sscanf(spec, "%d:%lld", &sig, &step) == 2)
    opt.inject_signal = sig, opt.inject_signal_step = step;
}

// Runs, prints the outcome (rank 0 of several processes), and maps it to the exit status:
// 0 completed, 1 failed (physics), 2 bad input or no checkpoint, 3 output error, 128 + signal
// when interrupted.
template <class F>
int run_and_report(F&& go) {
  const bool says = talus::process_rank() == 0;
  auto say = [&](std::FILE* to, const std::string& text) {
    if (says) fmt::print(to, "{}\n", text);
  };
  try {
    const talus::RunResult r = go();
    if (r.status == "interrupted") {
      say(stderr, "talus: " + r.message);
      return 128 + r.signal;
    }
    if (r.status == "stopped") {
      say(stdout, "talus: " + r.message);
      return 0;
    }
    if (r.status != "completed") {
      say(stderr, fmt::format("error: run {}: {}", r.status, r.message));
      return 1;
    }
    say(stdout,
        fmt::format("done: {} steps, {:.4g} s simulated, {:.1f} s wall, {:.3g} particle-updates/s",
                    r.steps, r.simulated_time, r.wall_seconds, r.particle_updates_per_second));
  } catch (const talus::OutputError& e) {
    say(stderr, fmt::format("error: output: {}", e.what()));
    return 3;
  } catch (const talus::CaseError& e) {
    say(stderr, fmt::format("error: {}", e.what()));
    return 2;
  } catch (const talus::CheckpointError& e) {
    say(stderr, fmt::format("error: restart: {}", e.what()));
    return 2;
  } catch (const talus::RunFolderError& e) {
    say(stderr, fmt::format("error: run folder: {}", e.what()));
    return 2;
  } catch (const talus::DecompositionError& e) {
    say(stderr, fmt::format("error: processes: {}", e.what()));
    return 2;
  }
  return 0;
}

// This program's own path (verify and sweep hand it to their Python drivers); empty if unknown.
std::string self_path() {
  char self[4096];
  const ssize_t n = ::readlink("/proc/self/exe", self, sizeof self - 1);
  if (n <= 0) return {};
  self[n] = 0;
  return self;
}

} // namespace

int main(int argc, char** argv) {
  talus::share_cores(argv);      // idle OpenMP threads sleep: runs side by side do not collapse
  std::signal(SIGXFSZ, SIG_IGN); // a full file-size limit becomes a write error, not a kill
  std::signal(SIGPIPE, SIG_IGN); // a closed stdout (run | head) loses the log, not the run
  talus::ProcessSession processes(&argc, &argv); // MPI, in the mpi preset
  CLI::App app{"Talus: multi-body Material Point Method for landslides"};
  app.set_version_flag("--version", std::string("talus ") + talus::version);
  app.require_subcommand(1);

  std::string case_file, out_dir;
  std::vector<std::string> overrides;
  int threads = 0;
  long long max_steps = -1;
  auto* run = app.add_subcommand("run", "run a case into a run folder");
  std::string restart_dir;
  auto* case_opt = run->add_option("case", case_file, "case file (TOML)")->check(CLI::ExistingFile);
  auto* restart_opt = run->add_option("--restart", restart_dir,
                                      "continue the run in this folder from its newest checkpoint");
  restart_opt->excludes(case_opt);
  run->add_option("--out,-o", out_dir, "run folder (default: runs/<case name>)");
  run->add_option("--set", overrides, "override a key: --set grid.cell_size=4 (repeatable)")
      ->excludes(restart_opt);
  run->add_option("--threads,-t", threads,
                  "OpenMP threads (default: one per 25,000 particles, at most the cores)")
      ->check(CLI::Range(1, 1024));
  bool overwrite = false, force = false;
  run->add_flag("--force", force,
                "run even if the output cannot fit in the free disk space (talus check)");
  run->add_flag("--overwrite", overwrite,
                "empty the run folder of an earlier run first (a fresh run refuses a non-empty "
                "folder)")
      ->excludes(restart_opt);
  run->add_option("--max-steps", max_steps,
                  "stop after this many steps with a checkpoint (status \"stopped\"; continue "
                  "with --restart)")
      ->check(CLI::Range(1LL, std::numeric_limits<long long>::max()));

  auto* chk = app.add_subcommand("check", "validate a case and estimate its size and run time");
  chk->add_option("case", case_file, "case file (TOML)")->required()->check(CLI::ExistingFile);
  chk->add_option("--set", overrides, "override a key (repeatable)");

  talus::BenchOptions bench_opt;
  auto* bench =
      app.add_subcommand("bench", "throughput of fixed problems (particle-updates per second)");
  bench->add_option("--threads", bench_opt.threads, "thread counts to run (default: 1 2)")
      ->check(CLI::Range(1, 1024))
      ->delimiter(',');
  bench
      ->add_option(
          "--problems", bench_opt.problems,
          "column, column_4x, vaiont, vaiont_3d, column_bspline, vaiont_bspline, "
          "vaiont_wet, tank, vaiont_reservoir, vaiont_reservoir_xpic, volcano (default: column "
          "column_4x vaiont)")
      ->check(CLI::IsMember(talus::bench_problem_names()))
      ->delimiter(',');
  bench->add_option("--json", bench_opt.json_out, "also write the figures as JSON here")
      ->check([](const std::string& path) -> std::string {
        const std::filesystem::path p(path);
        std::error_code ec;
        if (std::filesystem::is_directory(p, ec)) return path + ": is a folder; give a file name";
        const std::filesystem::path dir = p.has_parent_path() ? p.parent_path() : ".";
        if (!std::filesystem::is_directory(dir, ec))
          return path + ": its folder " + dir.string() + " does not exist";
        return {};
      });
  bench->add_option("--source", bench_opt.source_dir, "the Talus source folder (default: .)");

  // verify: the suite lives in tools/verify.py (it drives this program and plots with
  // matplotlib); this subcommand hands over to it.
  std::vector<std::string> verify_cases;
  std::string verify_out = "verification", source_dir = TALUS_SOURCE_DIR, also_shape, also_set;
  bool verify_full = false, verify_quick = false, update_docs = false;
  int verify_jobs = 1;
  auto* verify = app.add_subcommand(
      "verify", "run every benchmark against its reference and write DIR/report.html");
  verify->add_flag("--quick", verify_quick, "CI resolution (the default)");
  verify->add_flag("--full", verify_full, "the paper's resolution")->excludes("--quick");
  verify->add_option("--out", verify_out, "report folder (default: verification)");
  auto* cases_opt = verify->add_option("--cases", verify_cases, "only these cases (file stems)");
  verify->add_option("--source", source_dir, "the Talus source folder");
  verify
      ->add_option("--threads", threads,
                   "at most this many OpenMP threads per run (each takes one per 25,000 "
                   "particles, as talus run does)")
      ->check(CLI::Range(1, 1024));
  verify
      ->add_option("--jobs,-j", verify_jobs,
                   "runs at once (default 1); each then takes at most the cores over the jobs "
                   "in threads")
      ->check(CLI::Range(1, 64));
  verify->add_flag("--update-docs", update_docs, "write the table into docs/verification.md");
  auto* also_shape_opt =
      verify
          ->add_option("--also-shape", also_shape,
                       "run every check again with this shape function: a column of the report")
          ->check(CLI::IsMember({"linear", "gimp", "bspline"}));
  verify
      ->add_option("--also-set", also_set,
                   "run every check again with KEY=VALUE overridden (e.g. simulation.xpic=2): a "
                   "column of the report")
      ->check([](const std::string& kv) -> std::string {
        return kv.find('=') == std::string::npos || kv.front() == '=' ? "needs KEY=VALUE" : "";
      })
      ->excludes(also_shape_opt);

  talus::SweepOptions sweep_opt;
  sweep_opt.source_dir = TALUS_SOURCE_DIR;
  auto* sweep = app.add_subcommand(
      "sweep", "an ensemble of runs of a case ([sweep]): a table, probability maps, a ranking");
  sweep->add_option("case", sweep_opt.case_file, "case file (TOML) with a [sweep] table")
      ->required()
      ->check(CLI::ExistingFile);
  sweep->add_option("--out,-o", sweep_opt.out_dir,
                    "sweep folder (default: runs/<case name>_sweep); an existing one is resumed");
  sweep->add_option("--set", sweep_opt.overrides, "override a key for every run (repeatable)");
  sweep->add_option("--jobs,-j", sweep_opt.jobs, "runs at once (default: the cores / threads)")
      ->check(CLI::Range(1, 1024));
  sweep->add_option("--threads,-t", sweep_opt.threads, "OpenMP threads per run (default: 1)")
      ->check(CLI::Range(1, 1024));
  sweep->add_option("--launcher", sweep_opt.launcher,
                    "run each run under this command (e.g. \"mpirun -np 2\" with the mpi build)");
  sweep->add_option("--source", sweep_opt.source_dir, "the Talus source folder");

  // Command-line errors exit with status 2, as case-file errors do (help and version: 0).
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return 2;
  }
  if (verify->parsed()) {
    // A bare --cases is not "all cases" (the parser hands it the options after it as names).
    if (cases_opt->count() > 0 &&
        (verify_cases.empty() ||
         std::any_of(verify_cases.begin(), verify_cases.end(),
                     [](const std::string& s) { return s.empty() || s[0] == '-'; }))) {
      fmt::print(stderr, "error: verify: --cases needs case names (file stems), not options\n");
      return 2;
    }
    const std::string self = self_path();
    if (self.empty()) {
      fmt::print(stderr, "error: verify: cannot find this program's path\n");
      return 2;
    }
    std::vector<std::string> args = {"/usr/bin/python3",
                                     source_dir + "/tools/verify.py",
                                     "--talus",
                                     self,
                                     "--source",
                                     source_dir,
                                     "--out",
                                     verify_out,
                                     verify_full ? "--full" : "--quick"};
    if (threads > 0) args.insert(args.end(), {"--threads", std::to_string(threads)});
    if (verify_jobs > 1) args.insert(args.end(), {"--jobs", std::to_string(verify_jobs)});
    if (update_docs) args.emplace_back("--update-docs");
    if (!also_shape.empty()) args.insert(args.end(), {"--also-shape", also_shape});
    if (!also_set.empty()) args.insert(args.end(), {"--also-set", also_set});
    if (!verify_cases.empty()) {
      args.emplace_back("--cases");
      args.insert(args.end(), verify_cases.begin(), verify_cases.end());
    }
    std::vector<char*> argv2;
    for (auto& a : args)
      argv2.push_back(a.data());
    argv2.push_back(nullptr);
    ::execv(argv2[0], argv2.data());
    fmt::print(stderr, "error: verify: cannot run {}: {}\n", args[0], std::strerror(errno));
    return 2;
  }
  if (sweep->parsed()) {
    sweep_opt.self = self_path();
    try {
      return talus::run_sweep(sweep_opt);
    } catch (const talus::CaseError& e) {
      fmt::print(stderr, "error: {}\n", e.what());
      return 2;
    }
  }
  if (bench->parsed()) {
    try {
      return talus::run_bench(bench_opt);
    } catch (const talus::CaseError& e) {
      fmt::print(stderr, "error: {}\n", e.what());
      return 2;
    } catch (const talus::OutputError& e) {
      fmt::print(stderr, "error: output: {}\n", e.what());
      return 3;
    }
  }

  if (run->parsed() && !restart_dir.empty()) {
    talus::RunOptions opt;
    opt.out_dir = restart_dir;
    opt.threads = threads;
    if (max_steps >= 0) opt.max_steps = max_steps;
    opt.log = talus::process_rank() == 0 ? &std::cout : nullptr;
    inject_faults(opt);
    return run_and_report([&] { return talus::restart_run(opt); });
  }
  if (case_file.empty()) {
    fmt::print(stderr, "error: run: give a case file, or --restart RUN_DIR\n");
    return 2;
  }

  talus::Case c;
  try {
    // Every process reads the case; a check that fails on one machine alone (its memory) stops
    // them all, and rank 0 reports the first failing process's error.
    talus::agreed<talus::CaseError>(
        [&] { c = talus::parse_case_file(case_file, overrides, talus::this_machine_budget()); });
  } catch (const talus::CaseError& e) {
    if (talus::process_rank() == 0) fmt::print(stderr, "error: {}\n", e.what());
    return 2;
  }
  if (chk->parsed()) {
    try {
      return check(c);
    } catch (const talus::CaseError& e) {
      fmt::print(stderr, "error: {}\n", e.what());
      return 2;
    }
  }

  if (out_dir.empty()) {
    const auto stem = std::filesystem::path(case_file).stem().string();
    out_dir = "runs/" + stem;
  }
  talus::RunOptions opt;
  opt.out_dir = out_dir;
  opt.threads = threads;
  if (max_steps >= 0) opt.max_steps = max_steps;
  opt.overwrite = overwrite;
  opt.force = force;
  opt.log = talus::process_rank() == 0 ? &std::cout : nullptr;
  inject_faults(opt);
  return run_and_report([&] { return talus::run_case(c, opt); });
}
