#include "solve/blcp.hpp"

#include "solve/interior_point.hpp"

#include <limits>

namespace rbpart {

namespace {

// Lower bound for s = max |q| so that a BLCP with q = 0 still has an absolute scale.
constexpr double kMinScale = 1e-12;
// Iterative refinement of lambda_F (DESIGN.md §3 asks for exact answers): at most this many
// corrections per pivoting iteration, each a solve with the factor already computed. Backends that
// are backward stable (Cholesky of A_FF) rarely need one; the body-space backend, whose Woodbury
// solve cancels digits when sigma is tiny, needs one or two.
constexpr int kMaxRefinements = 3;
// Refine while max_F |w| exceeds this fraction of the feasibility tolerance.
constexpr double kRefineFraction = 1e-2;
// Round-off allowance of w = A lambda + q in units of eps * max_j A_jj |lambda_j| (a row sums a few
// tens of terms of that size).
constexpr double kRoundoffFactor = 64;
// Interior-point restarts per fixed-bounds solve; each costs a few tens of factorisations.
constexpr int kMaxRestarts = 3;

}  // namespace

BlcpResult solve_blcp(BlcpMatrix& A, const Eigen::VectorXd& q, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi,
                      Eigen::VectorXd& lambda, std::vector<RowState>& state, const BlcpSettings& settings,
                      BlcpWorkspace& ws) {
  const int n = A.size();
  BlcpResult result;
  ws.w.resize(n);
  ws.ax.resize(n);
  ws.delta.resize(n);
  ws.free.resize(n);
  if (n == 0) {
    result.converged = true;
    return result;
  }
  const Eigen::VectorXd& diag = A.diagonal();
  const double scale = std::max(max_abs(q), kMinScale);
  double tol_w = settings.tolerance * scale;
  auto is_fixed = [&](int j) { return !(lo[j] < hi[j]); };  // lo == hi: clamped whatever w is

  // Warm-start sets, made consistent with the bounds: no clamping at an infinite bound.
  for (int j = 0; j < n; ++j) {
    if (is_fixed(j)) state[j] = RowState::Lower;
    else if (state[j] == RowState::Lower && lo[j] == -std::numeric_limits<double>::infinity()) state[j] = RowState::Free;
    else if (state[j] == RowState::Upper && hi[j] == std::numeric_limits<double>::infinity()) state[j] = RowState::Free;
  }
  // The best iterate so far by the natural-map residual of its projection onto the bounds (what
  // is returned if pivoting does not converge); initially the warm start.
  ws.best_lambda.resize(n);
  for (int j = 0; j < n; ++j) ws.best_lambda[j] = std::isfinite(lambda[j]) ? lambda[j] : 0.0;
  double best_residual = std::numeric_limits<double>::infinity();
  auto keep_if_better = [&](const Eigen::VectorXd& candidate) {
    // candidate projected, then its residual with w = A candidate + q (uses ws.delta, ws.ax).
    for (int j = 0; j < n; ++j) ws.delta[j] = std::clamp(candidate[j], lo[j], std::max(lo[j], hi[j]));
    A.multiply(ws.delta, ws.ax);
    double r = 0;
    for (int j = 0; j < n; ++j) {
      const double wj = ws.ax[j] + q[j];
      const double projected = std::clamp(ws.delta[j] - wj / diag[j], lo[j], std::max(lo[j], hi[j]));
      r = std::max(r, std::abs(ws.delta[j] - projected) * diag[j]);
    }
    if (r < best_residual && std::isfinite(r)) {
      best_residual = r;
      ws.best_lambda = ws.delta;
    }
  };

  // Wrong-signed w of a clamped row, or distance outside the bounds of a free row (times A_jj, so
  // that both are in units of w). Positive means infeasible.
  auto violation = [&](int j) {
    switch (state[j]) {
      case RowState::Free: return std::max(lo[j] - lambda[j], lambda[j] - hi[j]) * diag[j];
      case RowState::Lower: return is_fixed(j) ? 0.0 : -ws.w[j];
      case RowState::Upper: return is_fixed(j) ? 0.0 : ws.w[j];
    }
    return 0.0;
  };
  auto swap = [&](int j) {
    if (state[j] != RowState::Free) state[j] = RowState::Free;
    else state[j] = lambda[j] < lo[j] ? RowState::Lower : RowState::Upper;
  };

  int fewest = n + 1;
  int patience = settings.murty_after;
  int restarts = 0;
  for (int it = 0; it < settings.max_iterations; ++it) {
    for (int j = 0; j < n; ++j) ws.free[j] = state[j] == RowState::Free;
    const int factored = A.prepare(ws.free);
    if (factored < 0) break;
    result.factorizations += factored;
    ++result.iterations;

    // lambda_F = -A_FF^-1 (q_F + A_FC lambda_C), lambda_C at its bounds.
    for (int j = 0; j < n; ++j) lambda[j] = ws.free[j] ? 0.0 : (state[j] == RowState::Upper ? hi[j] : lo[j]);
    A.multiply(lambda, ws.ax);
    for (int j = 0; j < n; ++j)
      if (ws.free[j]) lambda[j] = -(q[j] + ws.ax[j]);
    A.solve(lambda);
    A.multiply(lambda, ws.ax);
    ws.w = ws.ax + q;

    // Iterative refinement: w_F = 0 in exact arithmetic.
    auto free_residual = [&] {
      double r = 0;
      for (int j = 0; j < n; ++j)
        if (ws.free[j]) r = std::max(r, std::abs(ws.w[j]));
      return r;
    };
    double residual = free_residual();
    for (int k = 0; k < kMaxRefinements && residual > kRefineFraction * tol_w; ++k) {
      for (int j = 0; j < n; ++j) ws.delta[j] = ws.free[j] ? ws.w[j] : 0.0;
      A.solve(ws.delta);
      lambda -= ws.delta;
      A.multiply(lambda, ws.ax);
      ws.w = ws.ax + q;
      const double refined = free_residual();
      if (!(refined < 0.5 * residual)) {
        if (!(refined <= residual)) {  // round-off floor reached: keep the better iterate
          lambda += ws.delta;
          A.multiply(lambda, ws.ax);
          ws.w = ws.ax + q;
        }
        break;
      }
      residual = refined;
    }
    if (!lambda.allFinite() || !ws.w.allFinite()) break;
    // No test can be finer than the round-off of w = A lambda + q, about eps * A_jj |lambda_j|
    // summed over a row: with redundant rows and a tiny sigma, fighting constraints (q not in the
    // range of J) drive lambda to ~q / sigma, and a fixed tolerance would then swap rows on noise.
    double terms = 0;
    for (int j = 0; j < n; ++j) terms = std::max(terms, std::abs(lambda[j]) * diag[j]);
    tol_w = std::max(settings.tolerance * scale, kRoundoffFactor * std::numeric_limits<double>::epsilon() * terms);

    // Infeasible rows.
    int count = 0, highest = -1;
    for (int j = 0; j < n; ++j)
      if (violation(j) > tol_w) {
        ++count;
        highest = j;
      }
    if (count == 0) {
      result.converged = true;
      return result;
    }
    keep_if_better(lambda);

    // Judice & Pires with the restart: block swaps while the count reaches new lows (or within the
    // patience); a stall with many infeasible rows restarts from interior-point sets, which are
    // then finished by Murty's single swaps as long as few rows remain wrong; Murty's rule also
    // takes over once the restarts are used up.
    if (restarts > 0 && count <= settings.murty_max_infeasible) {
      result.murty = true;
      swap(highest);
      continue;
    }
    if (count < fewest) {
      fewest = count;
      patience = settings.murty_after;
    } else if (patience > 0) {
      --patience;
    } else if (restarts < kMaxRestarts && count > settings.murty_max_infeasible) {
      ++restarts;
      result.restarted = true;
      result.factorizations +=
          interior_point_sets(A, q, lo, hi, state, settings.interior_point_iterations, ws.interior);
      keep_if_better(ws.interior.x);
      fewest = n + 1;
      patience = settings.murty_after;
      continue;
    } else {
      result.murty = true;
      swap(highest);
      continue;
    }
    for (int j = 0; j < n; ++j)
      if (violation(j) > tol_w) swap(j);
  }

  // Not converged (iteration cap or a failed factorisation): the best iterate, inside the bounds,
  // with the sets it implies.
  lambda = ws.best_lambda;
  for (int j = 0; j < n; ++j) {
    lambda[j] = std::clamp(lambda[j], lo[j], std::max(lo[j], hi[j]));
    state[j] = is_fixed(j) || lambda[j] == lo[j] ? RowState::Lower
               : lambda[j] == hi[j]              ? RowState::Upper
                                                 : RowState::Free;
  }
  A.multiply(lambda, ws.ax);
  ws.w = ws.ax + q;
  return result;
}

}  // namespace rbpart
