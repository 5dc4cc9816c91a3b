// The Newton solver (solve/newton.hpp, monolithic backend) on fixed problem sets: the islands of
// every `every`-th step of a scene's run, each solved from the warm start that run's solve started
// from. Whole-run figures (steps above the residual 1e-9) follow trajectories that part by
// round-off after the first unsettled step, so two versions of the solver are different piles by
// the end; here every version meets the very same problems, island by island. The problems come
// from a run with the PGS solver and no position projection (which solves with the Newton
// solver): not the code under test (a Newton run would hand each version problems of its own),
// and fast. So the warm starts are PGS's, not the Newton solver's own: a resting island here is
// not solved by its first factorisation as in a Newton run.
//
// Set-up, once per scene and untimed: the PGS run, recording the solve stage's input of the chosen
// steps (set_problem_observer).
// Every benchmark iteration solves every recorded island once, on one thread, as the solve stage
// does on a cold step (a new backend per island, no island cache). Counters, over all recorded
// islands: islands and steps; unsettled islands and steps (residual above 1e-9); factorisations
// per island (mean, max); unsettled islands by size (rows < 50, 50-500, 500-2000, > 2000); the
// worst residual.
#include "solve/island_system.hpp"
#include "solve/monolithic.hpp"
#include "solve/newton.hpp"
#include "solve/newton_island.hpp"

#include "scenes/scenes.hpp"
#include "step/world_internals.hpp"

#include <rbpart/world.hpp>

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace rbpart {
namespace {

// One recorded step: the solve stage's input as the live World handed it over.
struct Problem {
  Rows rows;  // with the warm start the live solve started from
  Bodies bodies;
  Islands islands;
  std::vector<int> local_rows;  // local_row_index
};

using ProblemSet = std::vector<Problem>;

struct SceneCase {
  const char* scene;
  std::vector<std::pair<std::string, std::string>> overrides;
  int steps, every;
};

// The solver's scenes (bench/results/amd-epyc-2core/newton/README.md), every 10th to 25th step.
const std::map<std::string, SceneCase>& cases() {
  static const std::map<std::string, SceneCase> all = {
      {"box_pile_h60", {"box_pile", {{"mass_ratio_set", "1"}}, 300, 10}},
      {"box_pile_h100", {"box_pile", {{"mass_ratio_set", "1"}, {"dt", "0.01"}, {"layers", "12"}}, 500, 20}},
      {"chain_drop", {"chain_drop", {}, 500, 10}},
      {"rock_pile", {"rock_pile", {}, 500, 20}},
      {"large_rock_pile", {"large_rock_pile", {}, 500, 25}},
  };
  return all;
}

const ProblemSet& problems(const std::string& name) {
  static std::map<std::string, std::unique_ptr<ProblemSet>> cache;
  std::unique_ptr<ProblemSet>& cached = cache[name];
  if (!cached) {
    const SceneCase& c = cases().at(name);
    SolverParams solver;
    solver.kind = SolverKind::Pgs;
    // Baumgarte only: the position projection solves with the Newton solver, and would make the
    // problem set depend on the code under test.
    StepParams step;
    step.joint_projection_iterations = 0;
    cached = std::make_unique<ProblemSet>();
    World world(make_builtin_scene(c.scene, c.overrides), step, solver, PartitionParams{});
    bool record = false;
    set_problem_observer(world, [&](const Rows& rows, const Bodies& bodies, const Islands& islands,
                                    const ConstraintGraph&) {
      if (record) cached->push_back({rows, bodies, islands, local_row_index(rows, islands)});
    });
    for (int s = 1; s <= c.steps; ++s) {
      record = s % c.every == 0;
      world.step();
    }
  }
  return *cached;
}

void BM_NewtonReplay(benchmark::State& state, const std::string& name) {
  const tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
  const ProblemSet& set = problems(name);
  const SolverParams params;
  double islands = 0, unsettled = 0, unsettled_steps = 0, factorizations = 0, most = 0, worst = 0;
  double by_size[4] = {0, 0, 0, 0};
  for (auto _ : state) {
    islands = unsettled = unsettled_steps = factorizations = most = worst = 0;
    std::fill(std::begin(by_size), std::end(by_size), 0.0);
    for (const Problem& p : set) {
      bool step_unsettled = false;
      for (std::size_t i = 0; i < p.islands.count(); ++i) {
        IslandSystem s;
        s.gather(p.rows, p.bodies, p.islands, static_cast<int>(i), p.local_rows);
        MonolithicSystem system;
        system.assign(s);
        Eigen::VectorXd lambda;
        std::vector<RowState> row_state;
        island_warm_start(s, p.rows, lambda, row_state);
        NewtonWorkspace ws;
        const NewtonResult result = solve_newton(s, system, params.max_factorizations, lambda, row_state, ws);
        ++islands;
        factorizations += result.factorizations;
        most = std::max(most, static_cast<double>(result.factorizations));
        worst = std::max(worst, result.residual);
        if (result.settled) continue;
        ++unsettled;
        step_unsettled = true;
        ++by_size[s.rows < 50 ? 0 : s.rows < 500 ? 1 : s.rows < 2000 ? 2 : 3];
      }
      unsettled_steps += step_unsettled;
    }
  }
  state.counters["steps"] = static_cast<double>(set.size());
  state.counters["islands"] = islands;
  state.counters["unsettled_steps"] = unsettled_steps;
  state.counters["unsettled"] = unsettled;
  state.counters["fact_mean"] = factorizations / std::max(islands, 1.0);
  state.counters["fact_max"] = most;
  state.counters["uns_lt50"] = by_size[0];
  state.counters["uns_50_500"] = by_size[1];
  state.counters["uns_500_2k"] = by_size[2];
  state.counters["uns_gt2k"] = by_size[3];
  state.counters["worst_res"] = worst;
}

BENCHMARK_CAPTURE(BM_NewtonReplay, box_pile_h60, std::string("box_pile_h60"))->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK_CAPTURE(BM_NewtonReplay, box_pile_h100, std::string("box_pile_h100"))->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK_CAPTURE(BM_NewtonReplay, chain_drop, std::string("chain_drop"))->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK_CAPTURE(BM_NewtonReplay, rock_pile, std::string("rock_pile"))->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK_CAPTURE(BM_NewtonReplay, large_rock_pile, std::string("large_rock_pile"))->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace
}  // namespace rbpart

BENCHMARK_MAIN();
