// The monolithic direct solver (DESIGN.md §3): per island, the friction outer loop around the exact
// fixed-bounds BLCP core, on a dense or sparse factorisation of A_FF.
#include "solve/solve.hpp"

#include "core/parallel.hpp"
#include "solve/blcp.hpp"
#include "solve/dense_matrix.hpp"
#include "solve/direct_island.hpp"
#include "solve/island_system.hpp"
#include "solve/residual.hpp"
#include "solve/sparse_matrix.hpp"

#include <algorithm>
#include <memory>
#include <numeric>

namespace rbpart {

// The backend for an island: dense Cholesky up to dense_max_rows rows; above, the body-space
// factorisation, which is exact through the core's refinement and much cheaper than CHOLMOD on A
// (bench/blcp_bench.cpp, warm solves: 1.9 ms vs 4.7 ms at 1000 rows, and A's factor grows with the
// square of the contacts per body), or CHOLMOD on A itself when a row has no regularisation (the
// Woodbury form divides by sigma).
std::unique_ptr<BlcpMatrix> make_direct_matrix(const IslandSystem& s, const SolverParams& params) {
  if (s.rows <= params.dense_max_rows) {
    auto dense = std::make_unique<DenseBlcpMatrix>();
    build_dense(s, dense->matrix());
    dense->finalize();
    return dense;
  }
  if ((s.sigma.array() > 0).all()) {
    auto body_space = std::make_unique<BodySpaceBlcpMatrix>();
    body_space->assign(s);
    return body_space;
  }
  auto sparse = std::make_unique<SparseBlcpMatrix>();
  LowerCsc a;
  build_lower_csc(s, a);
  sparse->assign(std::move(a));
  return sparse;
}

BlcpSettings blcp_settings(const SolverParams& params) {
  BlcpSettings settings;
  settings.max_iterations = params.max_pivot_iterations;
  settings.pivot_patience = params.murty_after;
  settings.coupled_paths = params.coupled_paths;
  return settings;
}

IslandOutcome solve_island(Rows& rows, const Bodies& bodies, const Islands& islands, int island,
                           const std::vector<int>& local_row, const SolverParams& params) {
  IslandSystem s;
  s.gather(rows, bodies, islands, island, local_row);
  Eigen::VectorXd lambda(s.rows), previous;
  std::vector<RowState> state(s.rows);
  for (int r = 0; r < s.rows; ++r) {
    lambda[r] = rows.lambda[s.global_rows[r]];
    state[r] = rows.state[s.global_rows[r]];
  }
  const std::unique_ptr<BlcpMatrix> a = make_direct_matrix(s, params);

  const BlcpSettings settings = blcp_settings(params);
  BlcpWorkspace ws;
  CoupledWorkspace coupled;
  IslandOutcome out;
  const FrictionPassResult passes = friction_passes(
      s.coupling(), s.diag, lambda, state, s.lo, s.hi, params.friction_passes, params.friction_tolerance, previous,
      [&] { return out.count(solve_blcp(*a, s.q, s.lo, s.hi, lambda, state, settings, ws)); },
      [&]() -> const Eigen::VectorXd& { return ws.w; },
      [&] { return coupled_friction_step(*a, s.q, s.lo, s.hi, s.coupling(), lambda, state, settings, coupled); });
  out.passes = passes.passes;
  out.count(coupled);
  out.failed = !passes.solved;
  out.unsettled = !passes.settled;

  store_island_solution(s, lambda, state, rows);
  // w afresh, as the coupled step may have replaced the last fixed-bounds solve's lambda.
  Eigen::VectorXd du;
  out.residual = island_residual(s, lambda, du, ws.w);
  return out;
}

SolveReport solve_direct(Rows& rows, const Bodies& bodies, const Islands& islands, const SolverParams& params) {
  const std::vector<int> local_row = local_row_index(rows, islands);
  const std::size_t count = islands.count();
  const std::vector<int> order = largest_islands_first(islands);
  std::vector<IslandOutcome> outcome(count);
  parallel_for_each(count, [&](std::size_t t) {
    const int i = order[t];
    outcome[i] = solve_island(rows, bodies, islands, i, local_row, params);
  });

  SolveReport report;
  for (const IslandOutcome& o : outcome) {
    report.iterations += o.iterations;
    report.friction_passes = std::max(report.friction_passes, o.passes);
    report.factorizations += o.factorizations;
    report.newton_islands += o.newton;
    report.failures += o.failed;
    report.unsettled += o.unsettled;
    report.residual = std::max(report.residual, o.residual);
  }
  return report;
}

}  // namespace rbpart
