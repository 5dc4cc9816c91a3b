#pragma once
// The one contact solver (DESIGN.md §3) on the coupled natural map
//   F_j(lambda) = lambda_j - mid(lo_j(lambda), lambda_j - w_j / A_jj, hi_j(lambda)),  w = A lambda + q,
// joints, normals and friction in one solve, friction bounds +-mu_j max(0, lambda_n) of the same
// iterate. F is piecewise linear; each piece is a Newton state (linear_system.hpp: every row Free,
// Fixed at a bound, or Tied to its normal), and a Newton step solves the piece's linear system
// (one factorisation, the unit of cost), refined against its exact equations.
//
//   1. Newton steps from the warm start: the first on the previous step's states (at rest it is
//      the answer: one factorisation), each next one on the state F gives at the last step's
//      solution (primal-dual active set: every row the step pushed past a bound is fixed there,
//      every fixed row whose bound pushes it inward is freed). They stop when the state repeats or
//      two steps bring no better answer.
//   2. Otherwise an interior-point phase (interior_point.hpp: Mehrotra's predictor-corrector on
//      the same complementarity problem, friction coupled to its normal) from a cold start. It
//      has no state to get wrong, so the kinks of F do not stall it: it finds the answer's state.
//      When two consecutive predictors indicate the same state (Tapia's indicators, not the
//      natural map at the iterate: interior_point.hpp), and that state was not tried, step 1's
//      Newton steps run from the iterate, the first in that state; they end the solve exactly. An
//      iterate that settles by itself is finished by one Newton step in the state its predictor
//      indicates (exact to round-off rather than to the criterion).
//
// Why not one globalised Newton method (a line search on 1/2 ||D F||^2, a proximal safeguard):
// measured on the box piles, its Newton directions stop being descent directions a step of 1e-3
// into them wherever friction sits between sticking and sliding (its eight friction rows on a box's
// three planar freedoms are fixed only by sigma, so the kinks of F lie ~sigma apart), and 5-37 % of
// islands of 1-500 rows ended unsettled; bench/results/amd-epyc-2core/newton/experiments/.
//
// The answer is always admissible: every point considered is projected onto its bounds (normals
// and joint limits, then friction onto the box of its projected normal), and the projected point of
// least residual, max_j A_jj |F_j| / max_j |q_j|, is kept. It stops when that residual is at most
// kSettledResidual, or after max_factorizations factorisations (the budget; interior-point steps
// count one each). An answer that ends unsettled never leaves the bodies more kinetic energy than
// their free motion (beyond the work of assemble.cpp's b: penetration pushed out, joints' drift
// corrected, friction's proximal term), as an exact one never does: each unsettled point that
// would is scaled back towards 0 to the point of its ray that does no work, and the least
// residual among the points so treated is kept (newton.cpp, energy_scale).
#include "solve/interior_point.hpp"
#include "solve/island_system.hpp"
#include "solve/linear_system.hpp"

#include <Eigen/Core>

#include <vector>

namespace rbpart {

// The one criterion (DESIGN.md §3): a step is settled iff its residual is at most this.
constexpr double kSettledResidual = 1e-9;

struct NewtonResult {
  int iterations = 0;      // Newton steps taken or attempted
  int factorizations = 0;  // factorisations (the cost)
  double residual = 0;     // of the returned iterate
  bool settled = false;    // residual <= kSettledResidual
  double factor_ms = 0;    // time in factorisations
};

// Buffers of solve_newton, kept across calls so that the iterations do not allocate.
struct NewtonWorkspace {
  Piece piece;
  std::vector<RowState> piece_state;
  Eigen::VectorXd w, fw, g, x, e, ex, d, ad, trial, trial_w, trial_fw, best, answer, du, start, base, base_w;
  InteriorPoint ipm;
  // The loops over the island's rows and bodies (one chunk, serial, unless the caller sets more).
  IslandChunks chunks;
  // The state of the last Newton step; the one the interior point's last predictor indicated; the
  // last one Newton steps were tried from.
  std::vector<RowState> last_state, ipm_state, tried_state;
  // The island's warm start in, answer out (solve_island_newton).
  Eigen::VectorXd island_lambda;
  std::vector<RowState> island_state;
};

// Solves the island's coupled problem in place: `lambda` and `state` carry the warm start in
// (non-finite values count as 0) and the answer out (the states of the answer's piece).
NewtonResult solve_newton(const IslandSystem& s, LinearSystem& system, int max_factorizations, Eigen::VectorXd& lambda,
                          std::vector<RowState>& state, NewtonWorkspace& ws);

// D F(lambda) for w = A lambda + q: fw_j = A_jj F_j (friction bounds from lambda's own normals).
void scaled_natural_map(const IslandSystem& s, const Eigen::VectorXd& lambda, const Eigen::VectorXd& w,
                        Eigen::VectorXd& fw, IslandChunks& chunks);
void scaled_natural_map(const IslandSystem& s, const Eigen::VectorXd& lambda, const Eigen::VectorXd& w,
                        Eigen::VectorXd& fw);

}  // namespace rbpart
