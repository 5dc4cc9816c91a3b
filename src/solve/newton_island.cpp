#include "solve/newton_island.hpp"

#include "solve/blcp.hpp"
#include "solve/residual.hpp"

#include <algorithm>

namespace rbpart {

NewtonResult solve_island_newton(IslandSystem& s, LinearSystem& system, int max_factorizations, Rows& rows,
                                 NewtonWorkspace& ws) {
  Eigen::VectorXd& lambda = ws.island_lambda;
  std::vector<RowState>& state = ws.island_state;
  lambda.resize(s.rows);
  state.resize(s.rows);
  for (int r = 0; r < s.rows; ++r) {
    lambda[r] = rows.lambda[s.global_rows[r]];
    state[r] = rows.state[s.global_rows[r]];
  }
  const NewtonResult result = solve_newton(s, system, max_factorizations, lambda, state, ws);
  set_friction_bounds(s.coupling(), lambda, s.lo, s.hi);
  store_island_solution(s, lambda, state, rows);
  return result;
}

void add_island_result(const NewtonResult& result, SolveReport& report) {
  report.iterations += result.iterations;
  report.factorizations += result.factorizations;
  report.factor_ms += result.factor_ms;
  report.unsettled += !result.settled;
  report.residual = std::max(report.residual, result.residual);
}

}  // namespace rbpart
