// rbpart simulate: run a scene for N steps; write per-step stats (CSV) and the final state (JSON).
#include <rbpart/world.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <stdexcept>

#include "apps/rbpart/commands.hpp"
#include "core/error.hpp"
#include "core/interrupt.hpp"
#include "core/progress.hpp"
#include "core/timer.hpp"
#include "io/atomic_file.hpp"
#include "scene/limits.hpp"
#include "io/recording.hpp"
#include "io/scene_json.hpp"
#include "io/state_json.hpp"
#include "io/stats_csv.hpp"
#include "io/text_format.hpp"
#include "graph/constraint_graph.hpp"
#include "step/world_internals.hpp"

namespace rbpart::cli {

namespace {

struct Options {
  std::string scene;
  std::vector<std::string> sets;
  int steps = -1;
  double dt = 0;
  std::string solver = "direct";
  SolverParams solver_params;
  StepParams step_params;
  std::string stats_path, state_path, initial_state_path;
  std::string record_path, record_partitioners;
  bool quiet = false;
  PartitionOptions partition;
};

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

int run_simulate(const Options& o) {
  const PartitionParams partition_params = rbpart::cli::partition_params(o.partition);
  SceneDef scene = resolve_scene(o.scene, o.sets);
  if (o.dt > 0) scene.dt = o.dt;
  SolverParams solver_params = o.solver_params;
  solver_params.kind = o.solver == "pgs"             ? SolverKind::Pgs
                       : o.solver == "substructured" ? SolverKind::Substructured
                                                     : SolverKind::Direct;

  World world(scene, o.step_params, solver_params, partition_params);
  // A resumed run continues the step numbers and, by default, runs the scene's steps left.
  int steps = o.steps;
  if (!o.initial_state_path.empty()) {
    const SceneState initial = load_state_file(o.initial_state_path, world.scene());
    try {
      world.restart(initial.time, initial.bodies);
    } catch (const std::invalid_argument& e) {  // what the file's checks leave: a time too long for dt
      throw InputError(o.initial_state_path + ": " + e.what());
    }
  }
  if (steps < 0) steps = std::max(scene.steps - world.step_count(), 0);
  // Outputs are opened before the run so a bad path fails fast, and committed only at the end.
  ParamList params = run_parameters(o.step_params, solver_params, partition_params);
  params.insert(params.begin(), {{"scene", scene.name}, {"dt", round_trip(scene.dt)}, {"steps", std::to_string(steps)}});
  if (!o.initial_state_path.empty())
    params.insert(params.begin() + 3, {{"initial_state", o.initial_state_path},
                                       {"first_step", std::to_string(world.step_count() + 1)}});
  std::optional<StatsCsvWriter> stats;
  if (!o.stats_path.empty()) {
    stats.emplace(o.stats_path, params);
  }
  std::optional<AtomicFile> state;  // written at the end, but a bad path must not wait for the run
  if (!o.state_path.empty()) state.emplace(o.state_path);
  std::optional<RecordingWriter> recording;
  std::vector<PartitionParams> recorded;  // the recording's channels beyond the run's own
  std::vector<ChannelPartition> recorded_parts;
  if (!o.record_path.empty()) {
    const std::string run_channel =
        partition_params.partitioner == PartitionerKind::None ? "islands" : channel_name(partition_params);
    recorded = parse_channel_list(o.record_partitioners, partition_params);
    recorded_parts.resize(recorded.size());
    recording.emplace(o.record_path, world, params, run_channel, recorded);
  }

  std::vector<double> total_ms, solve_ms;
  double max_penetration = 0, max_residual = 0;
  int unsettled_steps = 0, last_unsettled = 0, slowest = 0;
  double work_ms = 0, critical_path_ms = 0;
  Progress progress("simulate " + scene.name, steps);
  const Timer run_timer;
  // Ctrl-C or SIGTERM ends the run after the step under way; the steps done are kept (below).
  defer_interrupts(true);
  int done = 0;
  const int first_step = world.step_count() + 1;
  for (int i = 0; i < steps && !interrupt_signal(); ++i, ++done) {
    const StepStats& s = world.step();
    if (stats) stats->write(s);
    if (recording) {
      // The extra channels partition the step's graph afresh; the writer only stores them.
      for (std::size_t c = 0; c < recorded.size(); ++c)
        recorded_parts[c].quality = partition_and_refine(world_graph(world), recorded[c], recorded_parts[c].partition);
      recording->write_step(world, s, recorded_parts);
    }
    if (s.profile.total_ms > (total_ms.empty() ? -1.0 : total_ms[slowest])) slowest = i;
    total_ms.push_back(s.profile.total_ms);
    solve_ms.push_back(s.profile.solve_ms);
    max_penetration = std::max(max_penetration, s.max_penetration);
    max_residual = std::max(max_residual, s.solve.residual);
    work_ms += s.solve.work_ms;
    critical_path_ms += s.solve.critical_path_ms;
    if (s.solve.unsettled > 0) {
      ++unsettled_steps;
      last_unsettled = s.step;
    }
    progress.update(i + 1);
  }
  const double run_s = run_timer.ms() / 1000;
  progress.finish();
  if (const int signal = interrupt_signal()) {
    // The recording and the state are dropped (their temporary files with them): a recording cut
    // short and a state that is not the last step's would pass for a whole run.
    const std::string why = std::string("stopped by ") + signal_name(signal) + " after " + std::to_string(done) +
                            " of " + std::to_string(steps) + " steps";
    if (stats) stats->finish_incomplete(why);
    std::fprintf(stderr, "rbpart: %s%s\n", why.c_str(),
                 stats ? ("; the statistics of those are in " + o.stats_path).c_str() : "");
    return 128 + signal;
  }
  if (stats) stats->finish();
  if (recording) recording->finish();
  if (state) {
    state->write(state_to_json(world.scene(), world_bodies(world), world.time(), params));
    state->commit();
  }

  if (!o.quiet) {
    int dynamic = 0;
    for (const BodyDef& b : scene.bodies) dynamic += !b.is_static;
    std::printf("scene %s: %d dynamic bodies, %zu joints, %d steps of %.4g s, solver %s\n", scene.name.c_str(),
                dynamic, scene.joints.size(), steps, scene.dt, o.solver.c_str());
    double solve_total_ms = 0;
    for (double ms : solve_ms) solve_total_ms += ms;
    std::printf("total %.3g s (solve %.3g s); median step %.3f ms (solve %.3f ms)", run_s, solve_total_ms / 1000,
                median(total_ms), median(solve_ms));
    if (steps > 0)
      std::printf("; slowest step %d: %.3f ms (solve %.3f ms)", first_step + slowest, total_ms[slowest],
                  solve_ms[slowest]);
    std::printf("\n");
    if (unsettled_steps > 0)
      std::printf("unsettled steps: %d of %d, the last at step %d\n", unsettled_steps, steps, last_unsettled);
    else
      std::printf("unsettled steps: none\n");
    std::printf("max penetration %.3g m; max BLCP residual %.3g\n", max_penetration, max_residual);
    if (solver_params.kind == SolverKind::Substructured)
      std::printf("substructured solve: work %.3g s, critical path %.3g s\n", work_ms / 1000, critical_path_ms / 1000);
    const ConstraintGraph& g = world_graph(world);
    WeightSum max_degree = 0, total_degree = 0;
    for (int i = 0; i < g.node_count(); ++i) {
      max_degree = std::max(max_degree, g.degree(i));
      total_degree += g.degree(i);
    }
    std::printf("constraint graph at the last step: %d nodes, %d edges, mean degree %.2f, max degree %lld\n",
                g.node_count(), g.edge_count(), g.node_count() ? double(total_degree) / g.node_count() : 0.0,
                static_cast<long long>(max_degree));
    std::printf("state hash %016llx\n", static_cast<unsigned long long>(world.state_hash()));
  }
  return 0;
}

}  // namespace

Run add_simulate(CLI::App& app) {
  CLI::App* cmd = app.add_subcommand("simulate", "Simulate a scene and report per-step statistics");
  auto o = std::make_shared<Options>();
  cmd->add_option("--scene", o->scene, "Built-in scene name (see `rbpart scenes`) or scene file (.json)")
      ->required();
  cmd->add_option("--set", o->sets, "Built-in scene parameter key=value (repeatable)");
  cmd->add_option("--steps", o->steps,
                  "Number of steps (default: the scene's; from --initial-state, the scene's steps left)")
      ->check(at_least(0));
  cmd->add_option("--dt", o->dt, "Time step in seconds (default: the scene's)")->check(open_closed(0, limits::kMaxDt));
  cmd->add_option("--solver", o->solver,
                  "Contact solver: direct (the Newton solver on the whole island), substructured (the same "
                  "through the partition; needs --partitioner) or pgs (the iterative baseline)")
      ->check(CLI::IsMember({"direct", "pgs", "substructured"}))
      ->capture_default_str();
  cmd->add_option("--threads", o->solver_params.threads, "Worker threads (0: all cores)")
      ->check(at_least(0))
      ->capture_default_str();
  cmd->add_option("--max-factorizations", o->solver_params.max_factorizations,
                  "Direct and substructured solvers: factorisations per island and step (the budget)")
      ->check(positive())
      ->capture_default_str();
  cmd->add_option("--pgs-iterations", o->solver_params.pgs_iterations, "PGS sweeps per step")
      ->check(positive())
      ->capture_default_str();
  cmd->add_option("--pgs-tolerance", o->solver_params.pgs_tolerance, "PGS stops when impulses change less")
      ->check(at_least(0))
      ->capture_default_str();
  cmd->add_option("--sigma-floor", o->step_params.sigma_floor,
                  "Regularisation floor relative to each row's diagonal of J M^-1 J^T")
      ->check(positive())
      ->capture_default_str();
  cmd->add_option("--contact-prox", o->step_params.contact_prox,
                  "Persisting contacts' friction yields towards the step before's impulse by this much of its diagonal")
      ->check(at_least(0))
      ->capture_default_str();
  cmd->add_option("--contact-margin", o->step_params.contact_margin,
                  "Contacts are generated up to this separation (m), handled speculatively")
      ->check(at_least(0))
      ->capture_default_str();
  cmd->add_option("--erp", o->step_params.erp, "Error reduction per step (Baumgarte), in (0, 1]")
      ->check(open_closed(0, 1))
      ->capture_default_str();
  cmd->add_option("--slop", o->step_params.slop, "Penetration left uncorrected (m)")
      ->check(at_least(0))
      ->capture_default_str();
  cmd->add_option("--stats", o->stats_path, "Per-step statistics as CSV (its parameters in FILE.json beside it)");
  cmd->add_option("--state", o->state_path, "Final state as JSON");
  cmd->add_option("--initial-state", o->initial_state_path,
                  "Continue from a state JSON (what --state writes) of this scene: its time and step numbers "
                  "go on; the first step is solved cold (no warm start)");
  CLI::Option* record = cmd->add_option("--record", o->record_path, "Recording for `rbpart view` (docs/viewer.md)");
  cmd->add_option("--record-partitioners", o->record_partitioners,
                  "Also record these partitions of every step's graph, e.g. mindp,mix+fm,bfs")
      ->needs(record);
  add_partition_options(cmd, o->partition, false);
  cmd->add_flag("-q,--quiet", o->quiet, "No summary on stdout");
  return [o]() { return run_simulate(*o); };
}

}  // namespace rbpart::cli
