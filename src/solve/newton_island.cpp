#include "solve/newton_island.hpp"

#include "solve/bounds.hpp"
#include "solve/residual.hpp"

#include <algorithm>

namespace rbpart {

void island_warm_start(const IslandSystem& s, const Rows& rows, Eigen::VectorXd& lambda, std::vector<RowState>& state) {
  lambda.resize(s.rows);
  state.resize(s.rows);
  for (int r = 0; r < s.rows; ++r) {
    lambda[r] = rows.lambda[s.global_rows[r]];
    state[r] = rows.state[s.global_rows[r]];
  }
}

NewtonResult solve_island_newton(IslandSystem& s, LinearSystem& system, int max_factorizations, Rows& rows,
                                 NewtonWorkspace& ws) {
  Eigen::VectorXd& lambda = ws.island_lambda;
  std::vector<RowState>& state = ws.island_state;
  island_warm_start(s, rows, lambda, state);
  const NewtonResult result = solve_newton(s, system, max_factorizations, lambda, state, ws);
  set_friction_bounds(s.coupling(), lambda, s.lo, s.hi);
  store_island_solution(s, lambda, state, rows);
  return result;
}

void add_island_result(const NewtonResult& result, SolveStats& stats) {
  stats.iterations += result.iterations;
  stats.factorizations += result.factorizations;
  stats.island_factorizations = std::max(stats.island_factorizations, result.factorizations);
  stats.factor_ms += result.factor_ms;
  stats.unsettled += !result.settled;
  stats.residual = std::max(stats.residual, result.residual);
}

}  // namespace rbpart
