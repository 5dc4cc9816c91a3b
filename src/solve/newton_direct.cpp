// The Newton solver (newton.hpp, DESIGN.md §3) on the monolithic backend (monolithic.hpp), per
// island, islands in parallel: `--solver newton`.
#include "solve/solve.hpp"

#include "core/parallel.hpp"
#include "solve/island_system.hpp"
#include "solve/monolithic.hpp"
#include "solve/newton.hpp"
#include "solve/residual.hpp"

#include <algorithm>
#include <numeric>

namespace rbpart {

SolveReport solve_newton_direct(Rows& rows, const Bodies& bodies, const Islands& islands, const SolverParams& params) {
  const std::vector<int> local_row = local_row_index(rows, islands);
  const std::size_t count = islands.count();
  const std::vector<int> order = largest_islands_first(islands);
  std::vector<NewtonResult> outcome(count);
  parallel_for_each(count, [&](std::size_t t) {
    const int i = order[t];
    IslandSystem s;
    s.gather(rows, bodies, islands, i, local_row);
    Eigen::VectorXd lambda(s.rows);
    std::vector<RowState> state(s.rows);
    for (int r = 0; r < s.rows; ++r) {
      lambda[r] = rows.lambda[s.global_rows[r]];
      state[r] = rows.state[s.global_rows[r]];
    }
    MonolithicSystem system;
    system.assign(s, params.dense_max_bodies);
    NewtonWorkspace ws;
    outcome[i] = solve_newton(s, system, params.max_factorizations, lambda, state, ws);
    set_friction_bounds(s.coupling(), lambda, s.lo, s.hi);
    store_island_solution(s, lambda, state, rows);
  });

  SolveReport report;
  for (const NewtonResult& o : outcome) {
    report.iterations += o.iterations;
    report.factorizations += o.factorizations;
    report.factor_ms += o.factor_ms;
    report.unsettled += !o.settled;
    report.residual = std::max(report.residual, o.residual);
  }
  return report;
}

}  // namespace rbpart
