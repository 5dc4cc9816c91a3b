// The substructured solver (docs/design.md#substructured: the Newton solver on the substructured
// backend) against the direct solver (the same solver on the monolithic backend) on recorded step
// problems of formed piles: rock_pile (200 rocks) and large_rock_pile (600 rocks, masses from {10,
// 100, 1000} kg). Set-up, once per scene and untimed: the scene runs `kFormed` steps with the direct
// solver (as `rbpart bench` captures its trajectories, study/capture.hpp), and every 10th of the last
// 100 steps is kept with the warm start the live solve started from, so the problems timed are those
// a World solves once the pile has landed. Every benchmark iteration solves every recorded problem
// once, from its warm start, with no analyses carried over from another solve (as the study replays).
//
// Arguments: threads, and n_max for the substructured solver (MinDP, MIX refined by FM, or METIS).
// Counters, per solve: ms (wall), factorisations, unsettled islands, the largest residual; for the
// substructured solver also parts, interface rows and bodies, part factorisations, and the work and
// critical path (ms). Partitioning is done in the set-up, untimed (it is the partitioners' cost,
// reported by the stats of a World run).
#include "solve/newton_substructured.hpp"
#include "solve/solve.hpp"

#include "core/timer.hpp"
#include "partition/partition.hpp"
#include "scenes/scenes.hpp"
#include "study/capture.hpp"

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <algorithm>
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

// What both solvers report, summed over the solves.
struct Sums {
  double ms = 0, factorizations = 0, unsettled = 0, residual = 0;
  void add(double wall_ms, const SolveStats& r) {
    ms += wall_ms;
    factorizations += r.factorizations;
    unsettled += r.unsettled;
    residual = std::max(residual, r.residual);
  }
  void report(benchmark::State& state, double solves) const {
    state.counters["ms"] = ms / solves;
    state.counters["factorizations"] = factorizations / solves;
    state.counters["unsettled"] = unsettled / solves;
    state.counters["residual"] = residual;
  }
};

void BM_Direct(benchmark::State& state, Scene scene) {
  const std::vector<StepProblem>& problems = recorded(scene);
  const tbb::global_control threads(tbb::global_control::max_allowed_parallelism, state.range(0));
  Sums sums;
  for (auto _ : state)
    for (const StepProblem& p : problems) {
      Rows r = p.rows;
      const Timer timer;
      const SolveStats report = solve_newton_direct(r, p.bodies, p.islands, SolverParams{});
      sums.add(timer.ms(), report);
    }
  sums.report(state, static_cast<double>(state.iterations()) * problems.size());
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
  Sums sums;
  NewtonSubstructuredReport sum;
  for (auto _ : state)
    for (std::size_t k = 0; k < problems.size(); ++k) {
      const StepProblem& p = problems[k];
      Rows r = p.rows;
      const Timer timer;
      const NewtonSubstructuredReport report =
          solve_newton_substructured(r, p.bodies, p.islands, p.graph, partitions[k], SolverParams{});
      sums.add(timer.ms(), report.solve);
      sum.parts += report.parts;
      sum.interface_rows += report.interface_rows;
      sum.interface_bodies += report.interface_bodies;
      sum.parts_refactored += report.parts_refactored;
      sum.solve.work_ms += report.solve.work_ms;
      sum.solve.critical_path_ms += report.solve.critical_path_ms;
    }
  const double solves = static_cast<double>(state.iterations()) * problems.size();
  sums.report(state, solves);
  state.counters["parts"] = sum.parts / solves;
  state.counters["iface_rows"] = sum.interface_rows / solves;
  state.counters["iface_bodies"] = sum.interface_bodies / solves;
  state.counters["part_factors"] = sum.parts_refactored / solves;
  state.counters["work_ms"] = sum.solve.work_ms / solves;
  state.counters["critical_ms"] = sum.solve.critical_path_ms / solves;
}

void direct_args(benchmark::internal::Benchmark* b) {
  b->ArgNames({"threads"})->Args({1})->Args({2})->Unit(benchmark::kMillisecond)->Iterations(2);
}

void substructured_args(benchmark::internal::Benchmark* b) {
  b->ArgNames({"threads", "nmax"})->Unit(benchmark::kMillisecond)->Iterations(2);
  for (int threads : {1, 2})
    for (int nmax : {8, 16, 32, 64}) b->Args({threads, nmax});
}

// METIS as the min-cut reference, up to parts as large as a pile's main island's half (two parts
// for two threads).
void metis_args(benchmark::internal::Benchmark* b) {
  b->ArgNames({"threads", "nmax"})->Unit(benchmark::kMillisecond)->Iterations(2);
  for (int threads : {1, 2})
    for (int nmax : {32, 128, 300}) b->Args({threads, nmax});
}

BENCHMARK_CAPTURE(BM_Direct, rock_pile, kRockPile)->Apply(direct_args);
BENCHMARK_CAPTURE(BM_Substructured, rock_pile_mindp, kRockPile, PartitionerKind::MinDp, RefinerKind::None)
    ->Apply(substructured_args);
BENCHMARK_CAPTURE(BM_Substructured, rock_pile_mix_fm, kRockPile, PartitionerKind::Mix, RefinerKind::Fm)
    ->Apply(substructured_args);
BENCHMARK_CAPTURE(BM_Substructured, rock_pile_metis, kRockPile, PartitionerKind::Metis, RefinerKind::None)
    ->Apply(metis_args);
BENCHMARK_CAPTURE(BM_Direct, large_rock_pile, kLargeRockPile)->Apply(direct_args);
BENCHMARK_CAPTURE(BM_Substructured, large_rock_pile_mindp, kLargeRockPile, PartitionerKind::MinDp, RefinerKind::None)
    ->Apply(substructured_args);
BENCHMARK_CAPTURE(BM_Substructured, large_rock_pile_mix_fm, kLargeRockPile, PartitionerKind::Mix, RefinerKind::Fm)
    ->Apply(substructured_args);
BENCHMARK_CAPTURE(BM_Substructured, large_rock_pile_metis, kLargeRockPile, PartitionerKind::Metis, RefinerKind::None)
    ->Apply(metis_args);

}  // namespace
}  // namespace rbpart

BENCHMARK_MAIN();
