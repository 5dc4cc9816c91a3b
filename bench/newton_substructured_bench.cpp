// One factorisation of the Newton solver's linear system (solve/linear_system.hpp) on a formed
// pile's largest island: the monolithic backend (solve/monolithic.hpp) against the substructured
// one (solve/substructured_system.hpp) on a MinDP and a MIX partition (n_max 32, no refiner). The
// piles: box_pile with masses from {10, 100, 1000} kg (largest island 44 bodies, 573 rows) and
// rock_pile (195 bodies, 4128 rows). Set-up, once per pile and untimed (about 15 s for both): the
// scene runs its 300 steps with the direct solver (study/capture.hpp), and the Newton solver, warm
// started as the World started the last step, solves the largest island on the monolithic backend,
// which records the pieces it factors.
//
// Every benchmark iteration factors each recorded piece once, in order. `all_parts`: each factor()
// sees a new state in every part (the free rows' shifts alternate by a relative 1e-12), the cost of
// a Newton step whose state changed everywhere; `newton`: the pieces as the solve met them, so parts
// whose rows did not change keep their factors (box_pile's solve runs to the budget, 40 pieces;
// rock_pile's, warm started at rest, two). Counters, per factor(): ms (wall), work and critical
// path (ms), parts refactored, and the partition's parts, interface rows and bodies.
#include "solve/island_parts.hpp"
#include "solve/island_system.hpp"
#include "solve/monolithic.hpp"
#include "solve/newton.hpp"
#include "solve/newton_island.hpp"
#include "solve/substructured_system.hpp"

#include "core/timer.hpp"
#include "partition/partition.hpp"
#include "scenes/scenes.hpp"
#include "study/capture.hpp"

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <map>
#include <memory>
#include <vector>

namespace rbpart {
namespace {

// Forwards to the monolithic backend and keeps every piece it is asked to factor.
class RecordingSystem final : public LinearSystem {
 public:
  MonolithicSystem system;
  std::vector<Piece> pieces;
  bool factor(const Piece& piece) override {
    pieces.push_back(piece);
    return system.factor(piece);
  }
  void solve(const Eigen::VectorXd& g, Eigen::VectorXd& x) override { system.solve(g, x); }
};

struct Pile {
  StepProblem step;
  IslandSystem island;        // the largest island (points into step)
  std::vector<Piece> pieces;  // the pieces Newton factored on it
  // The pieces with every free row's shift nudged: factored alternately with `pieces`, every
  // part's state changes at every call.
  std::vector<Piece> nudged;
};

enum Scene { kBoxPile, kRockPile };

const Pile& pile(Scene scene) {
  static std::map<Scene, std::unique_ptr<Pile>> cache;
  std::unique_ptr<Pile>& cached = cache[scene];
  if (!cached) {
    auto pile = std::make_unique<Pile>();
    const SceneDef def = scene == kBoxPile ? make_builtin_scene("box_pile", {{"mass_ratio_set", "1"}})
                                           : make_builtin_scene("rock_pile");
    Trajectory t = capture_trajectory(def, 300, 300, StepParams{}, SolverParams{});
    pile->step = std::move(t.steps.back());
    const StepProblem& step = pile->step;
    const std::vector<int> order = largest_islands_first(step.islands);
    pile->island.gather(step.rows, step.bodies, step.islands, order[0], local_row_index(step.rows, step.islands));
    const IslandSystem& s = pile->island;
    RecordingSystem recorder;
    recorder.system.assign(s);
    Eigen::VectorXd lambda;
    std::vector<RowState> state;
    island_warm_start(s, step.rows, lambda, state);
    NewtonWorkspace ws;
    solve_newton(s, recorder, SolverParams{}.max_factorizations, lambda, state, ws);
    pile->pieces = recorder.pieces;
    pile->nudged = recorder.pieces;
    for (Piece& piece : pile->nudged)
      for (int j = 0; j < s.rows; ++j)
        if (piece.equation[j] == RowEquation::Free) piece.shift[j] += 1e-12 * s.sigma[j];
    cached = std::move(pile);
  }
  return *cached;
}

// The pieces one iteration factors, in order.
std::vector<const Piece*> sequence(const Pile& p, bool all_parts) {
  std::vector<const Piece*> out;
  for (std::size_t k = 0; k < p.pieces.size(); ++k) {
    out.push_back(&p.pieces[k]);
    if (all_parts) out.push_back(&p.nudged[k]);
  }
  return out;
}

void BM_Monolithic(benchmark::State& state, Scene scene) {
  const Pile& p = pile(scene);
  MonolithicSystem system;
  system.assign(p.island);
  const std::vector<const Piece*> pieces = sequence(p, true);
  system.factor(*pieces.front());  // the symbolic analysis, once per island, untimed
  double ms = 0;
  for (auto _ : state)
    for (const Piece* piece : pieces) {
      const Timer timer;
      benchmark::DoNotOptimize(system.factor(*piece));
      ms += timer.ms();
    }
  const double calls = static_cast<double>(state.iterations()) * pieces.size();
  state.counters["ms"] = ms / calls;
  state.counters["bodies"] = p.island.bodies;
  state.counters["rows"] = p.island.rows;
  state.counters["pieces"] = static_cast<double>(p.pieces.size());
}

void BM_Substructured(benchmark::State& state, Scene scene, PartitionerKind partitioner, bool all_parts) {
  const Pile& p = pile(scene);
  const tbb::global_control threads(tbb::global_control::max_allowed_parallelism, state.range(0));
  PartitionParams pp;
  pp.partitioner = partitioner;
  pp.nmax = 32;
  Partition partition;
  partition_graph(p.step.graph, pp, partition);
  std::vector<int> part_of_body, distinct;
  island_parts(p.island, p.step.graph, partition, part_of_body, distinct);
  SubstructuredSystem system;
  system.assign(p.island, part_of_body);
  const std::vector<const Piece*> pieces = sequence(p, all_parts);
  system.factor(p.nudged.back());  // the symbolic analyses, untimed, and a state unlike the first
  SubstructuredCost sum;
  for (auto _ : state)
    for (const Piece* piece : pieces) {
      benchmark::DoNotOptimize(system.factor(*piece));
      const SubstructuredCost& c = system.last();
      sum.wall_ms += c.wall_ms;
      sum.work_ms += c.work_ms;
      sum.critical_path_ms += c.critical_path_ms;
      sum.parts_refactored += c.parts_refactored;
    }
  const double calls = static_cast<double>(state.iterations()) * pieces.size();
  state.counters["ms"] = sum.wall_ms / calls;
  state.counters["work_ms"] = sum.work_ms / calls;
  state.counters["critical_ms"] = sum.critical_path_ms / calls;
  state.counters["refactored"] = sum.parts_refactored / calls;
  state.counters["parts"] = system.parts();
  state.counters["iface_rows"] = system.interface_rows();
  state.counters["iface_bodies"] = system.interface_bodies();
}

void thread_args(benchmark::internal::Benchmark* b) {
  b->ArgNames({"threads"})->Args({1})->Args({2})->Unit(benchmark::kMillisecond);
}

BENCHMARK_CAPTURE(BM_Monolithic, box_pile, kBoxPile)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Substructured, box_pile_mindp_all_parts, kBoxPile, PartitionerKind::MinDp, true)->Apply(thread_args);
BENCHMARK_CAPTURE(BM_Substructured, box_pile_mix_all_parts, kBoxPile, PartitionerKind::Mix, true)->Apply(thread_args);
BENCHMARK_CAPTURE(BM_Substructured, box_pile_mindp_newton, kBoxPile, PartitionerKind::MinDp, false)->Apply(thread_args);
BENCHMARK_CAPTURE(BM_Substructured, box_pile_mix_newton, kBoxPile, PartitionerKind::Mix, false)->Apply(thread_args);
BENCHMARK_CAPTURE(BM_Monolithic, rock_pile, kRockPile)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Substructured, rock_pile_mindp_all_parts, kRockPile, PartitionerKind::MinDp, true)->Apply(thread_args);
BENCHMARK_CAPTURE(BM_Substructured, rock_pile_mix_all_parts, kRockPile, PartitionerKind::Mix, true)->Apply(thread_args);
BENCHMARK_CAPTURE(BM_Substructured, rock_pile_mindp_newton, kRockPile, PartitionerKind::MinDp, false)->Apply(thread_args);
BENCHMARK_CAPTURE(BM_Substructured, rock_pile_mix_newton, kRockPile, PartitionerKind::Mix, false)->Apply(thread_args);

}  // namespace
}  // namespace rbpart

BENCHMARK_MAIN();
