// Projected Gauss-Seidel (the iterative baseline) on the rows of each island, in velocity form:
// du = M^-1 J^T lambda is kept per body, so a row visit costs O(1) instead of a row of A:
//   w_j = q_j + J_j du + sigma_j lambda_j,  lambda_j <- clamp(lambda_j - w_j / A_jj, lo_j, hi_j).
#include "solve/solve.hpp"

#include "core/parallel.hpp"
#include "solve/island_system.hpp"
#include "solve/residual.hpp"

#include <algorithm>
#include <cmath>

namespace rbpart {

namespace {

struct PgsOutcome {
  int sweeps = 0;
  double residual = 0;
};

PgsOutcome solve_island(Rows& rows, const Bodies& bodies, const Islands& islands, int island,
                        const std::vector<int>& local_row, const SolverParams& params) {
  IslandSystem s;
  s.gather(rows, bodies, islands, island, local_row);
  Eigen::VectorXd lambda(s.rows), du, w;
  std::vector<RowState> state(s.rows, RowState::Free);
  for (int r = 0; r < s.rows; ++r) {
    const double warm = rows.lambda[s.global_rows[r]];
    lambda[r] = std::isfinite(warm) ? warm : 0.0;
  }
  apply_mjt(s, lambda, du);
  const double scale = std::max(max_abs(s.q), 1e-12);

  PgsOutcome out;
  for (int sweep = 0; sweep < params.pgs_iterations; ++sweep) {
    ++out.sweeps;
    double largest_change = 0;
    for (int j = 0; j < s.rows; ++j) {
      // The friction outer rule of DESIGN.md §3 at sweep granularity: a friction row takes its
      // bounds from its normal row's current impulse at each visit (updated earlier in this sweep
      // when the normal row comes first), so the bounds and the impulses converge together.
      if (s.normal_of[j] >= 0) {
        const double bound = s.mu[j] * std::max(0.0, lambda[s.normal_of[j]]);
        s.lo[j] = -bound;
        s.hi[j] = bound;
      }
      const double wj = s.q[j] + row_velocity(s, j, du) + s.sigma[j] * lambda[j];
      const double trial = lambda[j] - wj / s.diag[j];
      double next = trial;
      state[j] = RowState::Free;
      if (!(trial > s.lo[j])) {
        next = s.lo[j];
        state[j] = RowState::Lower;
      } else if (!(trial < s.hi[j])) {
        next = s.hi[j];
        state[j] = RowState::Upper;
      }
      const double change = next - lambda[j];
      if (change == 0.0) continue;
      lambda[j] = next;
      for (int slot = 0; slot < 2; ++slot)
        if (s.body[j][slot] >= 0) du.segment<6>(6 * s.body[j][slot]) += s.mjac[j][slot] * change;
      largest_change = std::max(largest_change, std::abs(change) * s.diag[j]);
    }
    if (largest_change < params.pgs_tolerance * scale) break;
  }

  store_island_solution(s, lambda, state, rows);
  // Residual from a fresh du (the incremental one carries round-off), bounds from the final lambda_n.
  out.residual = island_residual(s, lambda, du, w);
  return out;
}

}  // namespace

SolveStats solve_pgs(Rows& rows, const Bodies& bodies, const Islands& islands, const SolverParams& params) {
  const std::vector<int> local_row = local_row_index(rows, islands);
  std::vector<PgsOutcome> outcome(islands.count());
  parallel_for_each(islands.count(), [&](std::size_t i) {
    outcome[i] = solve_island(rows, bodies, islands, static_cast<int>(i), local_row, params);
  });
  // PGS has no factorisations and no separate friction passes (bounds follow every visit).
  SolveStats stats;
  for (const PgsOutcome& o : outcome) {
    stats.iterations += o.sweeps;
    stats.residual = std::max(stats.residual, o.residual);
  }
  return stats;
}

}  // namespace rbpart
