// The Newton solver (solve/newton.hpp) on one random contact-like island (solve/random_blcp.hpp: n
// rows on ~n/10 bodies of a 3-D lattice, each row touching at most two neighbouring bodies; contacts
// with friction coupled to their normal, some bilateral and box rows; sigma a 1e-6 floor), on the
// monolithic backend (the body-space system factored by the block LU of block_lu.hpp). Timed per solve: assigning the backend (the pattern and
// its symbolic analysis) and the solve. cold: from zero impulses, every row free; warm: from the
// answer of a previous (untimed) solve and its states, as in a resting step. Counters: rows,
// bodies, factorisations, the time of one factorisation (ms), and whether the solve settled
// (residual at most 1e-9; if not, the time is that of the budget of 40 factorisations, as on the
// 500-row island).
#include <rbpart/params.hpp>

#include "solve/island_system.hpp"
#include "solve/monolithic.hpp"
#include "solve/newton.hpp"

#include "solve/random_blcp.hpp"

#include <benchmark/benchmark.h>

#include <map>

namespace rbpart {
namespace {

const testing::RandomIsland& island(int rows) {
  static std::map<int, testing::RandomIsland> cache;
  auto [it, inserted] = cache.try_emplace(rows);
  if (inserted) {
    std::mt19937 rng(1000 + rows);
    testing::IslandOptions opt;
    opt.rows = rows;
    opt.neighbour_radius = 1.2;
    testing::random_contact_island(rng, opt, it->second);
  }
  return it->second;
}

void BM_Newton(benchmark::State& st, bool warm) {
  const IslandSystem& s = island(static_cast<int>(st.range(0))).system;
  const int budget = SolverParams{}.max_factorizations;
  Eigen::VectorXd start = Eigen::VectorXd::Zero(s.rows);
  std::vector<RowState> start_state(s.rows, RowState::Free);
  NewtonWorkspace ws;
  if (warm) {  // the answer and its states, from an untimed solve
    MonolithicSystem system;
    system.assign(s);
    solve_newton(s, system, budget, start, start_state, ws);
  }
  NewtonResult last;
  for (auto _ : st) {
    Eigen::VectorXd lambda = start;
    std::vector<RowState> state = start_state;
    MonolithicSystem system;
    system.assign(s);
    last = solve_newton(s, system, budget, lambda, state, ws);
    benchmark::DoNotOptimize(lambda.data());
  }
  st.counters["rows"] = s.rows;
  st.counters["bodies"] = s.bodies;
  st.counters["factorizations"] = last.factorizations;
  st.counters["factor_ms"] = last.factorizations > 0 ? last.factor_ms / last.factorizations : 0.0;
  st.counters["settled"] = last.settled;
}

void sizes(benchmark::internal::Benchmark* b, int largest) {
  for (int n : {50, 100, 200, 500, 1000, 2000})
    if (n <= largest) b->Arg(n);
  b->Unit(benchmark::kMillisecond);
}

BENCHMARK_CAPTURE(BM_Newton, cold, false)->Apply([](auto* b) { sizes(b, 2000); });
BENCHMARK_CAPTURE(BM_Newton, warm, true)->Apply([](auto* b) { sizes(b, 2000); });

}  // namespace
}  // namespace rbpart

BENCHMARK_MAIN();
