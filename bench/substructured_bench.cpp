// The substructured solver (docs/design.md#substructured) against the monolithic direct solver on recorded
// step problems of formed piles: rock_pile (200 rocks) and large_rock_pile (600 rocks, masses from {10, 100,
// 1000} kg). Set-up, once per scene and untimed: the scene runs `kFormed` steps with the monolithic direct
// solver (as `rbpart bench` captures its trajectories, study/capture.hpp), and every 10th of the last 100
// steps is kept with the warm start the live solve started from, so the problems timed are those a World
// solves once the pile has landed. The set-up takes about 1 min for rock_pile and 6 min for large_rock_pile
// (its landing) on one core. Every benchmark iteration solves every recorded problem once, from its warm
// start.
//
// Arguments: threads, then for the substructured solver the partitioner (MinDP, or MIX refined by
// FM) and n_max. Counters, per solve: ms (wall), parts, interface rows and bodies, loop iterations,
// fallbacks, the share of each phase in the work (summed over threads), work and critical path (ms),
// and the largest residual. Partitioning is done in the set-up, untimed (it is the partitioners'
// cost, reported by the stats of a World run).
#include "solve/solve.hpp"
#include "solve/substructured.hpp"

#include "core/timer.hpp"
#include "partition/partition.hpp"
#include "scenes/scenes.hpp"
#include "study/capture.hpp"

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <iterator>
#include <map>
#include <string>
#include <vector>

namespace rbpart {
namespace {

constexpr int kFormed = 300, kEvery = 10, kRecorded = 10;

enum Scene { kRockPile, kLargeRockPile };

const std::vector<StepProblem>& recorded(Scene scene) {
  static std::map<Scene, std::vector<StepProblem>> cache;
  auto [it, inserted] = cache.try_emplace(scene);
  if (!inserted) return it->second;
  Trajectory t = capture_trajectory(make_builtin_scene(scene == kRockPile ? "rock_pile" : "large_rock_pile"), kFormed,
                                    kEvery, StepParams{}, SolverParams{});
  it->second.assign(std::make_move_iterator(t.steps.end() - kRecorded), std::make_move_iterator(t.steps.end()));
  return it->second;
}

void BM_Direct(benchmark::State& state, Scene scene) {
  const std::vector<StepProblem>& problems = recorded(scene);
  const tbb::global_control threads(tbb::global_control::max_allowed_parallelism, state.range(0));
  double ms = 0, residual = 0, rows = 0;
  for (auto _ : state)
    for (const StepProblem& p : problems) {
      Rows r = p.rows;
      const Timer timer;
      const SolveReport report = solve_direct(r, p.bodies, p.islands, SolverParams{});
      ms += timer.ms();
      residual = std::max(residual, report.residual);
      rows += static_cast<double>(r.size());
    }
  const double solves = static_cast<double>(state.iterations()) * problems.size();
  state.counters["ms"] = ms / solves;
  state.counters["rows"] = rows / solves;
  state.counters["residual"] = residual;
}

void BM_Substructured(benchmark::State& state, Scene scene, PartitionerKind partitioner, RefinerKind refiner) {
  const std::vector<StepProblem>& problems = recorded(scene);
  const tbb::global_control threads(tbb::global_control::max_allowed_parallelism, state.range(0));
  PartitionParams pp;
  pp.partitioner = partitioner;
  pp.refiner = refiner;
  pp.nmax = static_cast<int>(state.range(1));
  std::vector<Partition> partitions(problems.size());
  for (std::size_t k = 0; k < problems.size(); ++k) {
    partition_graph(problems[k].graph, pp, partitions[k]);
    refine_partition(problems[k].graph, pp, partitions[k]);
  }
  SubstructuredReport sum;
  double ms = 0, residual = 0;
  for (auto _ : state)
    for (std::size_t k = 0; k < problems.size(); ++k) {
      const StepProblem& p = problems[k];
      Rows r = p.rows;
      const Timer timer;
      const SubstructuredReport report = solve_substructured(r, p.bodies, p.islands, p.graph, partitions[k], SolverParams{});
      ms += timer.ms();
      residual = std::max(residual, report.solve.residual);
      sum.parts += report.parts;
      sum.interface_rows += report.interface_rows;
      sum.interface_bodies += report.interface_bodies;
      sum.loop_iterations += report.loop_iterations;
      sum.fallbacks += report.fallbacks;
      sum.factor_ms += report.factor_ms;
      sum.schur_ms += report.schur_ms;
      sum.interface_ms += report.interface_ms;
      sum.subsystem_ms += report.subsystem_ms;
      sum.coupled_ms += report.coupled_ms;
      sum.monolithic_ms += report.monolithic_ms;
      sum.work_ms += report.work_ms;
      sum.critical_path_ms += report.critical_path_ms;
    }
  const double solves = static_cast<double>(state.iterations()) * problems.size();
  state.counters["ms"] = ms / solves;
  state.counters["parts"] = sum.parts / solves;
  state.counters["iface_rows"] = sum.interface_rows / solves;
  state.counters["iface_bodies"] = sum.interface_bodies / solves;
  state.counters["loops"] = sum.loop_iterations / solves;
  state.counters["fallbacks"] = sum.fallbacks / solves;
  state.counters["work_ms"] = sum.work_ms / solves;
  state.counters["critical_ms"] = sum.critical_path_ms / solves;
  const double work = std::max(sum.work_ms, 1e-300);
  state.counters["factor%"] = 100 * sum.factor_ms / work;
  state.counters["schur%"] = 100 * sum.schur_ms / work;
  state.counters["iface%"] = 100 * sum.interface_ms / work;
  state.counters["sub%"] = 100 * sum.subsystem_ms / work;
  state.counters["coupled%"] = 100 * sum.coupled_ms / work;
  state.counters["mono%"] = 100 * sum.monolithic_ms / work;
  state.counters["residual"] = residual;
}

void direct_args(benchmark::internal::Benchmark* b) {
  b->ArgNames({"threads"})->Args({1})->Args({2})->Unit(benchmark::kMillisecond)->Iterations(2);
}

void substructured_args(benchmark::internal::Benchmark* b) {
  b->ArgNames({"threads", "nmax"})->Unit(benchmark::kMillisecond)->Iterations(2);
  for (int threads : {1, 2})
    for (int nmax : {8, 16, 32, 64}) b->Args({threads, nmax});
}

BENCHMARK_CAPTURE(BM_Direct, rock_pile, kRockPile)->Apply(direct_args);
BENCHMARK_CAPTURE(BM_Substructured, rock_pile_mindp, kRockPile, PartitionerKind::MinDp, RefinerKind::None)
    ->Apply(substructured_args);
BENCHMARK_CAPTURE(BM_Substructured, rock_pile_mix_fm, kRockPile, PartitionerKind::Mix, RefinerKind::Fm)
    ->Apply(substructured_args);
BENCHMARK_CAPTURE(BM_Direct, large_rock_pile, kLargeRockPile)->Apply(direct_args);
BENCHMARK_CAPTURE(BM_Substructured, large_rock_pile_mindp, kLargeRockPile, PartitionerKind::MinDp, RefinerKind::None)
    ->Apply(substructured_args);
BENCHMARK_CAPTURE(BM_Substructured, large_rock_pile_mix_fm, kLargeRockPile, PartitionerKind::Mix, RefinerKind::Fm)
    ->Apply(substructured_args);

}  // namespace
}  // namespace rbpart

BENCHMARK_MAIN();
