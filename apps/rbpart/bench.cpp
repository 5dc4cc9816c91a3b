// rbpart bench: the partitioning study (issue #6; docs/study.md) — Table 1 and Figures 3-5.
#include <cstdio>
#include <filesystem>
#include <memory>

#include "apps/rbpart/commands.hpp"
#include "core/error.hpp"
#include "partition/partition.hpp"
#include "study/figures.hpp"
#include "study/study.hpp"

namespace rbpart::cli {

namespace {

struct Options {
  std::string preset = "quick";
  std::vector<std::string> scenes, partitioners, refiners;
  std::vector<int> nmax, threads, scaling;
  int repeats = 0, steps = 0, every = 0;
  bool no_scaling = false, no_reference = false, no_plots = false, resume = false;
  std::string out;
};

// The preset, with each option given on the command line replacing the preset's value.
StudySpec study_spec(const Options& o, const CLI::App& cmd) {
  StudySpec spec = study_preset(o.preset);
  if (cmd.count("--scenes")) {
    spec.scenes.clear();
    for (const std::string& s : o.scenes) spec.scenes.push_back(parse_study_scene(s));
  }
  if (cmd.count("--partitioners")) {
    spec.partitioners.clear();
    for (const std::string& p : o.partitioners) spec.partitioners.push_back(parse_partitioner(p));
  }
  if (cmd.count("--refine")) {
    spec.refiners.clear();
    for (const std::string& r : o.refiners) spec.refiners.push_back(parse_refiner(r));
  }
  if (cmd.count("--nmax")) spec.nmax = o.nmax;
  if (cmd.count("--threads")) spec.threads = o.threads;
  if (cmd.count("--scaling")) spec.scaling_rocks = o.scaling;
  if (o.no_scaling) spec.scaling_rocks.clear();
  if (o.no_reference) spec.mindp_reference = false;
  if (cmd.count("--repeats")) spec.repeats = o.repeats;
  if (cmd.count("--steps")) {
    if (o.steps < 1) throw InputError("--steps: must be at least 1 (got " + std::to_string(o.steps) + ")");
    spec.steps = o.steps;
  }
  if (cmd.count("--every")) spec.every = o.every;
  return spec;
}

int run_bench(const Options& o, const CLI::App& cmd) {
  const StudySpec spec = study_spec(o, cmd);
  run_study(spec, o.out, stderr, o.resume);
  std::printf("bench: tables in %s (table1.md, table1.csv, steps.csv, scaling.csv, claims.md, machine.json)\n",
              o.out.c_str());
  if (o.no_plots) return 0;
  const std::string script = plot_script_path();
  const std::string python = find_plot_python();
  if (python.empty() || !std::filesystem::is_regular_file(script)) {
    std::printf("bench: figures not drawn (%s); draw them with: /usr/bin/python3 %s %s\n",
                python.empty() ? "no Python with matplotlib; Debian: apt-get install python3-matplotlib"
                               : "plotting script not found; set RBPART_PLOT_SCRIPT",
                script.c_str(), o.out.c_str());
    return 0;
  }
  std::fflush(stdout);
  if (draw_figures(python, o.out) != 0) {
    std::fprintf(stderr, "rbpart: internal error: %s %s %s failed\n", python.c_str(), script.c_str(), o.out.c_str());
    return 1;
  }
  return 0;
}

}  // namespace

Run add_bench(CLI::App& app) {
  CLI::App* cmd = app.add_subcommand(
      "bench", "The partitioning study: every partitioner x refinement on the same recorded steps (Table 1, Figures 3-5)");
  auto o = std::make_shared<Options>();
  cmd->add_option("--preset", o->preset,
                  "paper (the paper's scenes, 500 steps, scaling 50-800 rocks) or quick (CI)")
      ->capture_default_str();
  cmd->add_option("--scenes", o->scenes, "Scenes: built-in NAME[:key=value...] or scene files (replaces the preset's)")
      ->delimiter(',');
  cmd->add_option("--partitioners", o->partitioners, "Partitioners: bfs,mindp,maxdp,mr,mix,metis")->delimiter(',');
  cmd->add_option("--refine", o->refiners, "Refinements: none,kl,fm,fm-rollback (METIS is run unrefined)")
      ->delimiter(',');
  cmd->add_option("--nmax", o->nmax, "Most bodies per sub-system (a list sweeps it)")->delimiter(',');
  cmd->add_option("--threads", o->threads, "Solver threads (a list sweeps it; default: all hardware threads)")
      ->delimiter(',');
  cmd->add_option("--scaling", o->scaling, "Rock counts of the Rock Pile scaling study (Figure 4)")->delimiter(',');
  cmd->add_flag("--no-scaling", o->no_scaling, "No scaling study");
  cmd->add_flag("--no-reference", o->no_reference,
                "Do not add unrefined MinDP, the paper's reference, unless listed (no vs MinDP column, claims not measured)");
  cmd->add_option("--repeats", o->repeats, "Solves per step and configuration; the median is kept");
  cmd->add_option("--steps", o->steps, "Steps simulated per scene (default: the preset's, else the scene's)");
  cmd->add_option("--every", o->every, "Record and replay every K-th step");
  cmd->add_flag("--no-plots", o->no_plots, "Write the tables only");
  cmd->add_option("--out", o->out, "Output directory (created if missing)")->required();
  cmd->add_flag("--resume", o->resume,
                "Keep the scenes an earlier run of the same study finished in --out, and run the others");
  return [o, cmd]() { return run_bench(*o, *cmd); };
}

}  // namespace rbpart::cli
