// The fixed-bounds BLCP core (docs/design.md#contact-problem) on random contact-like islands: n rows on ~n/10
// bodies of a 3-D lattice (each row touches at most two neighbouring bodies; normal rows [0, inf), friction
// rows in fixed boxes, some bilateral and box rows; sigma a 1e-6 floor), for the three backends: dense
// Cholesky of A_FF, CHOLMOD on A, and CHOLMOD on the body-space matrix M + J_F^T S_F^-1 J_F. Timed: building
// the matrix (incl. symbolic analysis) and the pivoting solve, per BLCP.   cold: sets start at the lower
// bounds (first contact);   warm: sets start at those of a previous (untimed) solve, as in a settled step.
// Counters: rows, bodies, iterations (face solves), factorisations, whether projected Newton had to finish
// after pivoting stalled, and whether the solve converged (if not, the time is that of max_iterations = 500
// iterations).
#include "solve/blcp.hpp"
#include "solve/dense_matrix.hpp"
#include "solve/sparse_matrix.hpp"

#include "solve/random_blcp.hpp"

#include <benchmark/benchmark.h>

#include <map>
#include <memory>

namespace rbpart {
namespace {

enum Backend { kDense, kCholmodA, kBodySpace };

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

std::unique_ptr<BlcpMatrix> make(Backend backend, const IslandSystem& s) {
  switch (backend) {
    case kDense: {
      auto m = std::make_unique<DenseBlcpMatrix>();
      build_dense(s, m->matrix());
      m->finalize();
      return m;
    }
    case kCholmodA: {
      auto m = std::make_unique<SparseBlcpMatrix>();
      LowerCsc a;
      build_lower_csc(s, a);
      m->assign(std::move(a));
      return m;
    }
    case kBodySpace: {
      auto m = std::make_unique<BodySpaceBlcpMatrix>();
      m->assign(s);
      return m;
    }
  }
  return nullptr;
}

void BM_Blcp(benchmark::State& st, Backend backend, bool warm) {
  const IslandSystem& s = island(static_cast<int>(st.range(0))).system;
  std::vector<RowState> cold(s.rows);
  for (int j = 0; j < s.rows; ++j) cold[j] = std::isfinite(s.lo[j]) ? RowState::Lower : RowState::Free;
  std::vector<RowState> start = cold;
  if (warm) {  // the solution's sets, from an untimed solve
    Eigen::VectorXd lambda = Eigen::VectorXd::Zero(s.rows);
    BlcpWorkspace ws;
    solve_blcp(*make(backend, s), s.q, s.lo, s.hi, lambda, start, BlcpSettings{}, ws);
  }
  BlcpResult last;
  for (auto _ : st) {
    Eigen::VectorXd lambda = Eigen::VectorXd::Zero(s.rows);
    std::vector<RowState> state = start;
    BlcpWorkspace ws;
    const std::unique_ptr<BlcpMatrix> a = make(backend, s);
    last = solve_blcp(*a, s.q, s.lo, s.hi, lambda, state, BlcpSettings{}, ws);
    benchmark::DoNotOptimize(lambda.data());
  }
  st.counters["rows"] = s.rows;
  st.counters["bodies"] = s.bodies;
  st.counters["iterations"] = last.iterations;
  st.counters["factorizations"] = last.factorizations;
  st.counters["newton"] = last.newton;
  st.counters["converged"] = last.converged;
}

void sizes(benchmark::internal::Benchmark* b, int largest) {
  for (int n : {50, 100, 200, 500, 1000, 2000})
    if (n <= largest) b->Arg(n);
  b->Unit(benchmark::kMillisecond);
}

BENCHMARK_CAPTURE(BM_Blcp, dense_cold, kDense, false)->Apply([](auto* b) { sizes(b, 1000); });
BENCHMARK_CAPTURE(BM_Blcp, cholmod_a_cold, kCholmodA, false)->Apply([](auto* b) { sizes(b, 2000); });
BENCHMARK_CAPTURE(BM_Blcp, body_space_cold, kBodySpace, false)->Apply([](auto* b) { sizes(b, 2000); });
BENCHMARK_CAPTURE(BM_Blcp, dense_warm, kDense, true)->Apply([](auto* b) { sizes(b, 1000); });
BENCHMARK_CAPTURE(BM_Blcp, cholmod_a_warm, kCholmodA, true)->Apply([](auto* b) { sizes(b, 2000); });
BENCHMARK_CAPTURE(BM_Blcp, body_space_warm, kBodySpace, true)->Apply([](auto* b) { sizes(b, 2000); });

}  // namespace
}  // namespace rbpart

BENCHMARK_MAIN();
