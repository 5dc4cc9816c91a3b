// Whole-step benchmarks on formed piles: the pile is first simulated until it has settled, then
// each benchmark iteration is one more step. Counters report the problem size and quality.
#include <benchmark/benchmark.h>
#include <rbpart/world.hpp>

#include <algorithm>
#include <cstdio>

#include "scenes/scenes.hpp"

namespace rbpart {
namespace {

void run_formed_pile(benchmark::State& state, const std::string& scene, const std::string& mass_set,
                     SolverKind kind, int pgs_iterations) {
  SolverParams solver;
  solver.kind = kind;
  solver.pgs_iterations = pgs_iterations;
  solver.pgs_tolerance = 0;
  solver.threads = static_cast<int>(state.range(1));
  World world(make_builtin_scene(scene, {{"mass_ratio_set", mass_set}}), StepParams{}, solver);
  const int settle = static_cast<int>(state.range(0));
  for (int i = 0; i < settle; ++i) world.step();
  double penetration = 0, rows = 0, contacts = 0, collide_ms = 0, solve_ms = 0, iterations = 0, residual = 0;
  for (auto _ : state) {
    const StepStats& s = world.step();
    penetration = std::max(penetration, s.max_penetration);
    residual = std::max(residual, s.solve.residual);
    rows += s.rows;
    contacts += s.contacts;
    collide_ms += s.profile.collide_ms;
    solve_ms += s.profile.solve_ms;
    iterations += s.solve.iterations;
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["rows"] = rows / n;
  state.counters["contacts"] = contacts / n;
  state.counters["collide_ms"] = collide_ms / n;
  state.counters["solve_ms"] = solve_ms / n;
  state.counters["iterations"] = iterations / n;
  state.counters["max_penetration_mm"] = 1e3 * penetration;
  state.counters["max_residual"] = residual;
}

void BM_BoxPile200_Direct(benchmark::State& s) { run_formed_pile(s, "box_pile", "0", SolverKind::Direct, 0); }
void BM_BoxPile200_MassRatio_Direct(benchmark::State& s) {
  run_formed_pile(s, "box_pile", "1", SolverKind::Direct, 0);
}
void BM_BoxPile200_Pgs100(benchmark::State& s) { run_formed_pile(s, "box_pile", "0", SolverKind::Pgs, 100); }
void BM_BoxPile200_MassRatio_Pgs100(benchmark::State& s) {
  run_formed_pile(s, "box_pile", "1", SolverKind::Pgs, 100);
}

// Arguments: steps simulated before timing (the pile forms within 300 steps at 60 Hz), and the
// World's threads (the narrow phase's pairs and the islands run in parallel).
BENCHMARK(BM_BoxPile200_Direct)->Args({300, 1})->Args({300, 2})->Unit(benchmark::kMillisecond)->Iterations(60);
BENCHMARK(BM_BoxPile200_MassRatio_Direct)->Args({300, 1})->Args({300, 2})->Unit(benchmark::kMillisecond)->Iterations(60);
BENCHMARK(BM_BoxPile200_Pgs100)->Args({300, 1})->Unit(benchmark::kMillisecond)->Iterations(60);
BENCHMARK(BM_BoxPile200_MassRatio_Pgs100)->Args({300, 1})->Unit(benchmark::kMillisecond)->Iterations(60);

}  // namespace
}  // namespace rbpart

BENCHMARK_MAIN();
