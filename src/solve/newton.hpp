#pragma once
// The one contact solver (DESIGN.md §3): a semismooth Newton method on the coupled natural map
//   F_j(lambda) = lambda_j - mid(lo_j(lambda), lambda_j - w_j / A_jj, hi_j(lambda)),  w = A lambda + q,
// joints, normals and friction in one solve, friction bounds +-mu_j max(0, lambda_n) of the same
// iterate. F is piecewise linear; each piece is a Newton state (linear_system.hpp: every row Free,
// Fixed at a bound, or Tied to its normal), and a Newton step solves the piece's linear system:
//
//   1. state: the piece of F at the iterate (the first iteration takes the warm start's states, so
//      that at rest the first step is the answer);
//   2. step: factor that piece's system (one factorisation, the unit of cost) and solve it, refined
//      against the exact equations (the body-space form loses digits to the small regularisation);
//   3. line search: Armijo backtracking on the merit 1/2 ||D F||^2, D = diag(A_jj) (the residual's
//      scaling: velocities), along the step to the piece's solution;
//   4. safeguard: when no step length decreases the merit (the iterate sits on a kink that the
//      piece's Newton step cannot leave, or a piece is nearly singular), the next system gets a
//      proximal shift rho A_jj (lambda_j - lambda_k,j) on its free rows: shorter steps on a better
//      conditioned system that still converge to the same solution (proximal point). rho grows
//      tenfold on every failure and falls tenfold on every full step.
//
// The answer is always admissible: every iterate is projected onto its bounds (normals and joint
// limits, then friction onto the box of its projected normal), and the projected point of least
// residual is kept (an iterate's free normals can be negative; applying one would pull bodies
// together, and projecting only the last iterate can launch bodies). It stops when that residual,
// max_j A_jj |F_j| / max_j |q_j|, is at most kSettledResidual, or after max_factorizations
// factorisations (the budget).
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
  Eigen::VectorXd w, fw, g, x, e, ex, d, ad, trial, trial_w, trial_fw, best, du;
};

// Solves the island's coupled problem in place: `lambda` and `state` carry the warm start in
// (non-finite values count as 0) and the answer out (the states of the answer's piece).
NewtonResult solve_newton(const IslandSystem& s, LinearSystem& system, int max_factorizations, Eigen::VectorXd& lambda,
                          std::vector<RowState>& state, NewtonWorkspace& ws);

// D F(lambda) for w = A lambda + q: fw_j = A_jj F_j (friction bounds from lambda's own normals).
void scaled_natural_map(const IslandSystem& s, const Eigen::VectorXd& lambda, const Eigen::VectorXd& w,
                        Eigen::VectorXd& fw);

}  // namespace rbpart
