#include "solve/blcp.hpp"

#include <Eigen/LU>

#include <limits>
#include <optional>

namespace rbpart {

namespace {

// Lower bound for s = max |q| so that a BLCP with q = 0 still has an absolute scale.
constexpr double kMinScale = 1e-12;
// Iterative refinement of a face solve (DESIGN.md §3 asks for exact answers): at most this many
// corrections, each a solve with the factor already computed. Backends that are backward stable
// (Cholesky of A_FF) rarely need one; the body-space backend, whose Woodbury solve cancels digits
// when sigma is tiny, needs one or two.
constexpr int kMaxRefinements = 3;
// Refine while max_F |w| exceeds this fraction of the feasibility tolerance.
constexpr double kRefineFraction = 1e-2;
// Round-off allowance of w = A lambda + q in units of eps * max_j A_jj |lambda_j| (a row sums a few
// tens of terms of that size).
constexpr double kRoundoffFactor = 64;
// Armijo's sufficient-decrease fraction and the step halvings tried along the projected path.
constexpr double kArmijo = 1e-4;
constexpr int kMaxHalvings = 60;

double clamp_row(double v, double lo, double hi) { return std::clamp(v, lo, std::max(lo, hi)); }

// The interior-point phase (interior_point): started kInteriorStart inside the bounds (a fraction
// of the box, or of |q| / A_jj); stopped when the mean complementarity and the dual residual fell
// by kInteriorGap (at 1e-8 the landing 600-rock pile's projected Newton then needed 30-46 face
// solves, at 1e-12 6-12), or after kInteriorMaxIterations; steps go kInteriorFraction of the way
// to the nearest bound; kInteriorRefinements corrections of the corrector's solve (the predictor
// only sets the centring and the second-order term, and goes unrefined).
constexpr double kInteriorStart = 1e-2;
constexpr double kInteriorGap = 1e-12;
constexpr int kInteriorMaxIterations = 60;
constexpr double kInteriorFraction = 0.99;
constexpr int kInteriorRefinements = 1;

// Mehrotra's primal-dual interior-point method on the box QP min 1/2 x^T A x + q^T x, lo <= x <= hi
// (Nocedal & Wright, ch. 16.6), from `x` moved strictly inside its bounds. Rows with lo == hi stay
// at their bound. With slacks s_l = x - lo, s_u = hi - x and multipliers z_l, z_u >= 0 of the finite
// bounds, each iteration solves (A + Theta) dx = -g + c_l / s_l - c_u / s_u, g = A x + q,
// Theta = z_l / s_l + z_u / s_u, twice (predictor, corrector) with one factorisation: the shifted
// factor of the BlcpMatrix. Stops when the mean complementarity and the dual residual are below
// kInteriorGap of their start, or after kInteriorMaxIterations. On return x is the last iterate,
// strictly feasible, and state the sets it points to: a row is clamped where its multiplier
// exceeds its slack (both in units of w). False if the backend has no shifted factorisation.
bool interior_point(BlcpMatrix& A, const Eigen::VectorXd& q, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi,
                    Eigen::VectorXd& x, std::vector<RowState>& state, int budget, BlcpWorkspace& ws,
                    BlcpResult& result) {
  const int n = A.size();
  const Eigen::VectorXd& diag = A.diagonal();
  const double scale = std::max(max_abs(q), kMinScale);
  for (Eigen::VectorXd* v : {&ws.sl, &ws.su, &ws.zl, &ws.zu, &ws.theta, &ws.dx, &ws.dzl, &ws.dzu, &ws.rhs})
    v->setZero(n);
  std::vector<char>& active = ws.free;  // the rows that are variables (not fixed)
  int bounds = 0;
  for (int j = 0; j < n; ++j) {
    active[j] = lo[j] < hi[j];
    if (!active[j]) {
      x[j] = lo[j];
      continue;
    }
    // Start a little inside: kInteriorStart of the box, or of the row's natural impulse scale.
    const double inset =
        std::isfinite(hi[j] - lo[j]) ? kInteriorStart * (hi[j] - lo[j]) : kInteriorStart * scale / diag[j];
    if (std::isfinite(lo[j])) x[j] = std::max(x[j], lo[j] + inset);
    if (std::isfinite(hi[j])) x[j] = std::min(x[j], hi[j] - inset);
  }
  A.multiply(x, ws.ax);
  for (int j = 0; j < n; ++j) {
    if (!active[j]) continue;
    const double g = ws.ax[j] + q[j], floor = kInteriorStart * scale;
    if (std::isfinite(lo[j])) {
      ws.sl[j] = x[j] - lo[j];
      ws.zl[j] = std::max(g, 0.0) + floor;
      ++bounds;
    }
    if (std::isfinite(hi[j])) {
      ws.su[j] = hi[j] - x[j];
      ws.zu[j] = std::max(-g, 0.0) + floor;
      ++bounds;
    }
  }
  auto complementarity = [&](double a) {  // mean of (s + a ds)(z + a dz) over the finite bounds
    double sum = 0;
    for (int j = 0; j < n; ++j) {
      if (!active[j]) continue;
      if (std::isfinite(lo[j])) sum += (ws.sl[j] + a * ws.dx[j]) * (ws.zl[j] + a * ws.dzl[j]);
      if (std::isfinite(hi[j])) sum += (ws.su[j] - a * ws.dx[j]) * (ws.zu[j] + a * ws.dzu[j]);
    }
    return bounds > 0 ? sum / bounds : 0.0;
  };
  auto max_step = [&]() {  // the largest a <= 1 keeping every slack and multiplier non-negative
    double a = 1;
    for (int j = 0; j < n; ++j) {
      if (!active[j]) continue;
      if (std::isfinite(lo[j])) {
        if (ws.dx[j] < 0) a = std::min(a, -ws.sl[j] / ws.dx[j]);
        if (ws.dzl[j] < 0) a = std::min(a, -ws.zl[j] / ws.dzl[j]);
      }
      if (std::isfinite(hi[j])) {
        if (ws.dx[j] > 0) a = std::min(a, ws.su[j] / ws.dx[j]);
        if (ws.dzu[j] < 0) a = std::min(a, -ws.zu[j] / ws.dzu[j]);
      }
    }
    return a;
  };
  // dx from ws.rhs on the shifted factor, refined against A + Theta (the body-space backend's
  // Woodbury solve cancels digits), then the multipliers' steps for the complementarity targets
  // c_l, c_u (target(j) gives them).
  auto direction = [&](auto&& target, int refinements) {
    ws.dx = ws.rhs;
    A.solve(ws.dx);
    for (int k = 0; k < refinements; ++k) {
      A.multiply(ws.dx, ws.ax);
      for (int j = 0; j < n; ++j) ws.delta[j] = active[j] ? ws.rhs[j] - ws.ax[j] - ws.theta[j] * ws.dx[j] : 0.0;
      A.solve(ws.delta);
      ws.dx += ws.delta;
    }
    for (int j = 0; j < n; ++j) {
      if (!active[j]) continue;
      const auto [cl, cu] = target(j);
      if (std::isfinite(lo[j])) ws.dzl[j] = (cl - ws.zl[j] * ws.dx[j]) / ws.sl[j] - ws.zl[j];
      if (std::isfinite(hi[j])) ws.dzu[j] = (cu + ws.zu[j] * ws.dx[j]) / ws.su[j] - ws.zu[j];
    }
  };
  double mu0 = -1, residual0 = -1;
  for (int it = 0; it < std::min(budget, kInteriorMaxIterations); ++it) {
    A.multiply(x, ws.ig);
    ws.ig += q;  // g = A x + q
    double residual = 0;  // dual residual g - z_l + z_u, in units of w
    for (int j = 0; j < n; ++j) {
      if (!active[j]) continue;
      ws.theta[j] = (std::isfinite(lo[j]) ? ws.zl[j] / ws.sl[j] : 0.0) +
                    (std::isfinite(hi[j]) ? ws.zu[j] / ws.su[j] : 0.0);
      residual = std::max(residual, std::abs(ws.ig[j] - ws.zl[j] + ws.zu[j]));
    }
    const double mu = complementarity(0);
    if (mu0 < 0) {
      mu0 = std::max(mu, std::numeric_limits<double>::min());
      residual0 = std::max(residual, kMinScale);
    }
    if (mu <= kInteriorGap * mu0 && residual <= kInteriorGap * residual0) break;
    if (!A.prepare_shifted(active, ws.theta)) return false;
    ++result.iterations;
    ++result.factorizations;
    // Predictor (affine scaling): c = 0.
    for (int j = 0; j < n; ++j) ws.rhs[j] = active[j] ? -ws.ig[j] : 0.0;
    direction([](int) { return std::pair<double, double>(0.0, 0.0); }, 0);
    const double sigma = std::pow(complementarity(max_step()) / std::max(mu, std::numeric_limits<double>::min()), 3);
    // Corrector: c = sigma mu - ds_aff dz_aff (ds_l = dx, ds_u = -dx).
    ws.dx_aff = ws.dx;
    ws.dzl_aff = ws.dzl;
    ws.dzu_aff = ws.dzu;
    auto target = [&](int j) {
      return std::pair<double, double>(sigma * mu - ws.dx_aff[j] * ws.dzl_aff[j],
                                       sigma * mu + ws.dx_aff[j] * ws.dzu_aff[j]);
    };
    for (int j = 0; j < n; ++j) {
      if (!active[j]) continue;
      const auto [cl, cu] = target(j);
      ws.rhs[j] = -ws.ig[j] + (std::isfinite(lo[j]) ? cl / ws.sl[j] : 0.0) -
                  (std::isfinite(hi[j]) ? cu / ws.su[j] : 0.0);
    }
    direction(target, kInteriorRefinements);
    const double a = std::min(1.0, kInteriorFraction * max_step());
    for (int j = 0; j < n; ++j) {
      if (!active[j]) continue;
      x[j] += a * ws.dx[j];
      if (std::isfinite(lo[j])) {
        ws.sl[j] += a * ws.dx[j];
        ws.zl[j] += a * ws.dzl[j];
      }
      if (std::isfinite(hi[j])) {
        ws.su[j] -= a * ws.dx[j];
        ws.zu[j] += a * ws.dzu[j];
      }
    }
  }
  for (int j = 0; j < n; ++j)
    state[j] = !active[j]                                               ? RowState::Lower
               : std::isfinite(lo[j]) && ws.zl[j] > ws.sl[j] * diag[j] ? RowState::Lower
               : std::isfinite(hi[j]) && ws.zu[j] > ws.su[j] * diag[j] ? RowState::Upper
                                                                       : RowState::Free;
  return true;
}

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
  // No test can be finer than the round-off of w = A lambda + q, about eps * A_jj |lambda_j| summed
  // over a row: with redundant rows and a tiny sigma, fighting constraints (q not in the range of J)
  // drive lambda to ~q / sigma, and a fixed tolerance would then swap rows on noise.
  auto update_tolerance = [&](const Eigen::VectorXd& v) {
    double terms = 0;
    for (int j = 0; j < n; ++j) terms = std::max(terms, std::abs(v[j]) * diag[j]);
    tol_w = std::max(settings.tolerance * scale, kRoundoffFactor * std::numeric_limits<double>::epsilon() * terms);
  };

  // Face solve: lambda_F = -A_FF^-1 (q_F + A_FC lambda_C) with lambda_C given on entry, refined
  // until w_F = 0 to round-off; leaves w = A lambda + q. False if A_FF could not be factored.
  auto face_solve = [&]() {
    const int factored = A.prepare(ws.free);
    if (factored < 0) return false;
    result.factorizations += factored;
    ++result.iterations;
    for (int j = 0; j < n; ++j)
      if (ws.free[j]) lambda[j] = 0.0;
    A.multiply(lambda, ws.ax);
    for (int j = 0; j < n; ++j)
      if (ws.free[j]) lambda[j] = -(q[j] + ws.ax[j]);
    A.solve(lambda);
    A.multiply(lambda, ws.ax);
    ws.w = ws.ax + q;
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
    return lambda.allFinite() && ws.w.allFinite();
  };

  // The start of projected Newton: the feasible point of least f = 1/2 l^T A l + q^T l among the
  // projection of 0, of the warm-start values and of every pivoting iterate. f(x) = 1/2 x.(g + q)
  // with g = A x + q.
  double best_f = std::numeric_limits<double>::infinity();
  ws.x.resize(n);
  ws.gx.resize(n);
  auto offer = [&](const Eigen::VectorXd& candidate) {
    for (int j = 0; j < n; ++j) ws.delta[j] = clamp_row(std::isfinite(candidate[j]) ? candidate[j] : 0.0, lo[j], hi[j]);
    A.multiply(ws.delta, ws.ax);
    ws.ax += q;
    const double f = 0.5 * ws.delta.dot(ws.ax + q);
    if (f < best_f) {
      best_f = f;
      ws.x = ws.delta;
      ws.gx = ws.ax;
    }
  };
  offer(Eigen::VectorXd::Zero(n));
  offer(lambda);

  // Warm-start sets, made consistent with the bounds: no clamping at an infinite bound.
  for (int j = 0; j < n; ++j) {
    if (is_fixed(j)) state[j] = RowState::Lower;
    else if (state[j] == RowState::Lower && lo[j] == -std::numeric_limits<double>::infinity()) state[j] = RowState::Free;
    else if (state[j] == RowState::Upper && hi[j] == std::numeric_limits<double>::infinity()) state[j] = RowState::Free;
  }

  // Phase 1, block principal pivoting (Judice & Pires): swap every infeasible row while the count of
  // infeasible rows keeps reaching new lows (within the patience).
  auto violation = [&](int j) {  // > 0: infeasible, in units of w
    switch (state[j]) {
      case RowState::Free: return std::max(lo[j] - lambda[j], lambda[j] - hi[j]) * diag[j];
      case RowState::Lower: return is_fixed(j) ? 0.0 : -ws.w[j];
      case RowState::Upper: return is_fixed(j) ? 0.0 : ws.w[j];
    }
    return 0.0;
  };
  int fewest = n + 1;
  int patience = settings.pivot_patience;
  while (result.iterations < settings.max_iterations) {
    for (int j = 0; j < n; ++j) {
      ws.free[j] = state[j] == RowState::Free;
      if (!ws.free[j]) lambda[j] = state[j] == RowState::Upper ? hi[j] : lo[j];
    }
    if (!face_solve()) break;
    update_tolerance(lambda);
    int count = 0;
    for (int j = 0; j < n; ++j) count += violation(j) > tol_w;
    if (count == 0) {
      result.converged = true;
      return result;
    }
    offer(lambda);
    if (count < fewest) {
      fewest = count;
      patience = settings.pivot_patience;
    } else if (patience-- <= 0) {
      break;
    }
    for (int j = 0; j < n; ++j) {
      if (violation(j) <= tol_w) continue;
      if (state[j] != RowState::Free) state[j] = RowState::Free;
      else state[j] = lambda[j] < lo[j] ? RowState::Lower : RowState::Upper;
    }
  }

  // Phase 1b, on large BLCPs whose pivoting stalled (redundant contacts make A nearly singular, and
  // the sets it swaps between differ in thousands of rows): an interior-point method, whose
  // iteration count hardly depends on how far the start's sets are from the answer's, nearly solves
  // the QP; its point, with the rows it finds clamped put on their bounds, starts phase 2, which
  // then has the few degenerate rows left to settle (6-12 face solves on a landing 600-rock pile,
  // against 50-90 from pivoting's best point). Offered like any candidate, so phase 2 still
  // starts from the feasible point of least f.
  if (n >= settings.interior_min_rows && result.iterations < settings.max_iterations) {
    ws.ix = ws.x;
    if (interior_point(A, q, lo, hi, ws.ix, state, settings.max_iterations - result.iterations, ws, result)) {
      result.interior = true;
      for (int j = 0; j < n; ++j)
        if (state[j] != RowState::Free) ws.ix[j] = state[j] == RowState::Upper ? hi[j] : lo[j];
      offer(ws.ix);
    }
  }

  // Phase 2, a primal active-set method on the box QP from the best feasible point x (gradient
  // g = A x + q), which decreases f monotonically and so cannot cycle. Working set W: rows held on a
  // bound; the face solve z minimises f with W held. If z is feasible, x = z is the face's minimiser;
  // if no row of W has a wrong-signed g it is the solution, else every such row is released (one
  // row, the worst, if the last release gained nothing: a single release always gains, as its row
  // then moves inwards). If z is infeasible, x moves towards it along the projected path
  // P(x + a (z - x)) with the largest a = 1, 1/2, ... meeting Armijo's condition, and at least to
  // the first bound on the segment (the exact ratio test, where f still decreases); the rows
  // that end on a bound join W. W only grows between releases, and f strictly decreases from one
  // face minimiser to the next, so no face repeats. The projected path clamps many rows per step
  // where the ratio test clamps one.
  result.newton = result.iterations < settings.max_iterations;
  Eigen::VectorXd& x = ws.x;
  Eigen::VectorXd& g = ws.gx;
  for (int j = 0; j < n; ++j) ws.free[j] = !(is_fixed(j) || x[j] == lo[j] || x[j] == hi[j]);
  double last_minimum = std::numeric_limits<double>::infinity();
  while (result.iterations < settings.max_iterations) {
    lambda = x;
    if (!face_solve()) break;
    ws.step = lambda - x;  // zero on W
    double block = 1;      // ratio test: the largest a <= 1 with x + a d feasible
    for (int j = 0; j < n; ++j) {
      if (!ws.free[j]) continue;
      if (lambda[j] < lo[j]) block = std::min(block, (lo[j] - x[j]) / (lambda[j] - x[j]));
      else if (lambda[j] > hi[j]) block = std::min(block, (hi[j] - x[j]) / (lambda[j] - x[j]));
    }
    if (block >= 1) {  // the face's minimiser is feasible
      x = lambda;
      g = ws.w;
      update_tolerance(x);
      const double f = 0.5 * x.dot(g + q);
      const bool single = !(f < last_minimum);
      last_minimum = std::min(last_minimum, f);
      int worst = -1;
      double worst_violation = tol_w;
      for (int j = 0; j < n; ++j) {
        if (ws.free[j] || is_fixed(j)) continue;
        const double v = x[j] == lo[j] ? -g[j] : g[j];
        if (v <= tol_w) continue;
        if (!single) ws.free[j] = 1;
        if (v > worst_violation) {
          worst_violation = v;
          worst = j;
        }
      }
      if (worst < 0) {
        result.converged = true;
        break;
      }
      ws.free[worst] = 1;
      continue;
    }
    // Projected search, the decrease computed from the step s itself (g.s + 1/2 s^T A s), not as
    // a difference of two large values of f.
    double a = 1;
    for (; a > block; a *= 0.5) {
      for (int j = 0; j < n; ++j) ws.delta[j] = clamp_row(x[j] + a * ws.step[j], lo[j], hi[j]) - x[j];
      const double slope = g.dot(ws.delta);
      if (!(slope < 0)) continue;
      A.multiply(ws.delta, ws.ax);
      if (slope + 0.5 * ws.delta.dot(ws.ax) <= kArmijo * slope) break;
    }
    if (a > block) {
      for (int j = 0; j < n; ++j) x[j] = clamp_row(x[j] + a * ws.step[j], lo[j], hi[j]);
    } else {
      // The segment's first bound: rows reaching it are put exactly on it.
      for (int j = 0; j < n; ++j) {
        if (!ws.free[j]) continue;
        const double v = x[j] + block * ws.step[j];
        if (lambda[j] < lo[j] && (v <= lo[j] || (lo[j] - x[j]) == block * (lambda[j] - x[j]))) x[j] = lo[j];
        else if (lambda[j] > hi[j] && (v >= hi[j] || (hi[j] - x[j]) == block * (lambda[j] - x[j]))) x[j] = hi[j];
        else x[j] = clamp_row(v, lo[j], hi[j]);
      }
    }
    int added = 0;
    for (int j = 0; j < n; ++j)
      if (ws.free[j] && (x[j] == lo[j] || x[j] == hi[j])) {
        ws.free[j] = 0;
        ++added;
      }
    if (added == 0) {  // the ratio row missed its bound by round-off: clamp it
      int arg = -1;
      double best = std::numeric_limits<double>::infinity();
      for (int j = 0; j < n; ++j) {
        if (!ws.free[j] || (lambda[j] >= lo[j] && lambda[j] <= hi[j])) continue;
        const double t = lambda[j] < lo[j] ? (lo[j] - x[j]) : (x[j] - hi[j]);
        if (std::abs(t) < best) {
          best = std::abs(t);
          arg = j;
        }
      }
      x[arg] = lambda[arg] < lo[arg] ? lo[arg] : hi[arg];
      ws.free[arg] = 0;
    }
    A.multiply(x, g);
    g += q;
  }

  if (!result.converged) {
    // The feasible iterate of least f (pivoting's projected iterates were offered; x is the
    // Newton iterate, which only decreases f from the best of them).
    lambda = ws.x;
    A.multiply(lambda, ws.ax);
    ws.w = ws.ax + q;
  }
  for (int j = 0; j < n; ++j)
    state[j] = is_fixed(j) || lambda[j] == lo[j] ? RowState::Lower
               : lambda[j] == hi[j]              ? RowState::Upper
                                                 : RowState::Free;
  return result;
}

namespace {

// The coupled friction path (blcp.hpp). A row of the warm start's first piece that would sit exactly
// on a bound or at w = 0 is moved this fraction of its scale inside (a degenerate first piece would
// make the first pivot's direction undefined).
constexpr double kStartMargin = 1e-3;
// Woodbury columns allowed before the base is refactored for the current free set (also at least
// twice the columns the base started with: its sliding rows, unless the backend ties them).
constexpr int kMinColumns = 64;
// Pivots of one coupled step (all its paths) before it gives up: kMinEvents plus one per
// kRowsPerEvent rows. The steps it solved on forming rock piles (100 and 200 rocks, up to 5600
// rows) took at most 0.5 pivots per row (1063 of ~2400, 2357 of ~5400); those it could not solve
// ran to any budget (4.5 per row before there was one, 20-100 s a step at 200 rocks with one per
// row), and the lagged passes that follow a failure cost far less.
constexpr int kMinEvents = 100;
constexpr int kRowsPerEvent = 2;
// Two events closer than this (relative) are a tie; a normal row wins over its friction rows.
constexpr double kTie = 1e-9;
// Updates of the capacitance's explicit inverse between recomputations (at least kRefresh, and one
// per kColumnsPerRefresh columns: a recomputation costs O(k^3), an update O(k^2)), and the
// smallest pivot an update may divide by (C is I plus terms of order 1 on well-scaled pieces).
constexpr int kRefresh = 32;
constexpr int kColumnsPerRefresh = 4;
constexpr double kSmallPivot = 1e-8;
// Block pivots of the coupled problem tried before its paths (coupled_friction_step), and the
// GMRES iterations and relative residual of their solves (CoupledPath::krylov).
constexpr int kJumpRounds = 4;
constexpr int kKrylovIterations = 80;
constexpr double kKrylovTolerance = 1e-12;
// Warm paths restarted from an end point that missed by round-off.
constexpr int kWarmRestarts = 3;
// Warm paths tried before the cold path (each from the end or the nearest point of the last).
constexpr int kWarmPaths = 8;
// Islands from this many rows on try BlcpSettings::coupled_paths warm paths instead, and no cold
// path: on the 200-rock pile's islands of 4000-5600 rows it solved none of the 10 steps it was
// tried on, at 2.3 s each. On the 100-rock pile's (2000-2400 rows) failures are cheap: the limit
// at 1000 rows saved nothing there (8.2 against 8.5 s of solve) and left 24 instead of 14 steps
// on the lagged bounds.
constexpr int kLargeCoupledRows = 3000;
// Pivots without getting nearer to s = 0 after which a path is abandoned: at least kMinPatience,
// one per kRowsPerPatience rows on large islands.
constexpr int kMinPatience = 50;
constexpr int kRowsPerPatience = 16;

// The equation a row contributes to a piece of the path, E lambda = ra + s rd:
//   Free    (A lambda)_j = -q_j - s d_j
//   Bound   lambda_j = lo_j or hi_j                          (rows other than friction)
//   Slide   lambda_t -+ mu lambda_n = +-s e_t                (friction on a bound of its box)
//   Closed  lambda_t = 0                                     (friction, e_t = 0, normal at 0)
enum class Eq : std::int8_t { Free, Bound, Slide, Closed };

// Kinds of the slacks a piece keeps non-negative: 0 the upper bound (hi - lambda), 1 the lower
// bound (lambda - lo), 2 the sign of w of a clamped row.
constexpr int kUpperSlack = 0, kLowerSlack = 1, kWSlack = 2;

class CoupledPath {
 public:
  CoupledPath(BlcpMatrix& a, const Eigen::VectorXd& q, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi,
              const FrictionCoupling& f, CoupledWorkspace& ws)
      : a_(a), q_(q), lo_(lo), hi_(hi), normal_of_(*f.normal_of), mu_(*f.mu), diag_(a.diagonal()), ws_(ws),
        n_(a.size()), scale_(std::max(max_abs(q), kMinScale)) {
    // Friction rows of every normal row (CSR), for the pivots that open or close a contact.
    ws.friction_start.assign(n_ + 1, 0);
    for (int j = 0; j < n_; ++j)
      if (normal_of_[j] >= 0) ++ws.friction_start[normal_of_[j] + 1];
    for (int j = 0; j < n_; ++j) ws.friction_start[j + 1] += ws.friction_start[j];
    ws.friction_rows.resize(ws.friction_start[n_]);
    ws.column_of.assign(ws.friction_start.begin(), ws.friction_start.end() - 1);  // fill cursor
    for (int j = 0; j < n_; ++j)
      if (normal_of_[j] >= 0) ws.friction_rows[ws.column_of[normal_of_[j]]++] = j;
    for (Eigen::VectorXd* v : {&ws.d, &ws.e, &ws.lambda, &ws.w, &ws.dl, &ws.dw, &ws.ga, &ws.aga, &ws.gd, &ws.agd,
                               &ws.g, &ws.ag, &ws.r, &ws.t, &ws.at})
      v->resize(n_);
    ws.sets.resize(n_);
    ws.base_free.resize(n_);
    ws.mixed_free.resize(n_);
  }

  // Start from a solution of the fixed-bounds BLCP (bounds lo/hi of the constructor): d and e are
  // chosen so that it solves H(1) (blcp.hpp). False if A_FF cannot be factored.
  bool start_warm(const Eigen::VectorXd& lambda, const std::vector<RowState>& state) {
    ws_.sets = state;
    ws_.lambda = lambda;
    ws_.d.setZero();
    ws_.e.setZero();
    for (int t = 0; t < n_; ++t) {
      if (!is_friction(t)) continue;
      const int n = normal_of_[t];
      if (ws_.sets[n] != RowState::Free) {  // closed until its normal opens
        ws_.lambda[t] = 0;
        ws_.sets[t] = RowState::Free;
        continue;
      }
      // A row on a lagged bound beyond its own box keeps sliding on a box widened by e_t; a row
      // inside its box is free (d_t below absorbs its w); a free row outside it is put inside.
      const double box = mu_[t] * ws_.lambda[n], size = std::abs(ws_.lambda[t]);
      if (ws_.sets[t] != RowState::Free && size > box) {
        ws_.e[t] = size - box;
      } else {
        ws_.sets[t] = RowState::Free;
        if (size >= box) ws_.e[t] = size - box + kStartMargin * (size + box);
      }
    }
    a_.multiply(ws_.lambda, ws_.w);
    ws_.w += q_;
    const double margin = kStartMargin * scale_;
    for (int j = 0; j < n_; ++j) {
      const Eq type = eq(j);
      if (type == Eq::Closed || fixed(j)) continue;
      if (type == Eq::Free) ws_.d[j] = -ws_.w[j];
      else if (ws_.sets[j] == RowState::Lower && ws_.w[j] < margin) ws_.d[j] = margin - ws_.w[j];
      else if (ws_.sets[j] == RowState::Upper && ws_.w[j] > -margin) ws_.d[j] = -margin - ws_.w[j];
    }
    ws_.w += ws_.d;  // w of H(s) is A lambda + q + s d; s = 1
    s_ = 1;
    last_ = -1;
    // The base: the first piece's own equations (tied, no columns) if the backend factors tied
    // systems; else the last pass's free set, whose factor the matrix still holds.
    for (int j = 0; j < n_; ++j) ws_.base_free[j] = eq(j) == Eq::Free;
    return set_base(&state);
  }

  // The coupled problem itself (s = 0, d = e = 0) on the sets of a fixed-bounds solution: its rows
  // on a friction bound slide with their normal, the others keep their sets. When the lagged bounds
  // moved without changing the sets (the load shares of a resting pile's redundant contacts), the
  // point of this one piece is the answer (finish()), with no path. False if A_FF cannot be factored.
  bool start_jump(const Eigen::VectorXd& lambda, const std::vector<RowState>& state) {
    ws_.sets = state;
    ws_.lambda = lambda;
    ws_.d.setZero();
    ws_.e.setZero();
    for (int t = 0; t < n_; ++t)
      if (is_friction(t) && ws_.sets[normal_of_[t]] != RowState::Free) ws_.lambda[t] = 0;  // closed
    s_ = 0;
    last_ = -1;
    return set_jump_base();
  }

  // A block pivot of the coupled problem (Judice & Pires on its tied equations): every row that
  // finish() found outside its bounds or with w of the wrong sign changes sides, and the base is
  // refactored for the new free set. The friction rows of a contact that opens start free (sticking).
  // False if A_FF cannot be factored.
  bool swap_violated() {
    for (const int j : ws_.violated) {
      if (ws_.sets[j] != RowState::Free) {
        ws_.sets[j] = RowState::Free;
        for (int c = ws_.friction_start[j]; c < ws_.friction_start[j + 1]; ++c)
          ws_.sets[ws_.friction_rows[c]] = RowState::Free;
      } else {
        ws_.sets[j] = ws_.lambda[j] > ws_.hi[j] ? RowState::Upper : RowState::Lower;
      }
    }
    return set_jump_base();
  }

  // Rows finish() found violated (outside their bounds, or clamped with w of the wrong sign).
  int violated() const { return static_cast<int>(ws_.violated.size()); }

  // The cold start: the piece for large s, where every bounded row other than friction is clamped
  // (d = +-A_jj pushes its w the right way) and friction rows are free in boxes +-s mu_t; the path
  // enters at the largest s where that piece ends. False if A_FF cannot be factored.
  bool start_cold() {
    ws_.d.setZero();
    for (int j = 0; j < n_; ++j) {
      ws_.lambda[j] = 0;
      ws_.e[j] = is_friction(j) ? mu_[j] : 0.0;
      ws_.sets[j] = RowState::Free;
      if (is_friction(j)) continue;
      if (fixed(j) || std::isfinite(lo_[j])) {
        ws_.sets[j] = RowState::Lower;
        ws_.lambda[j] = lo_[j];
        if (!fixed(j)) ws_.d[j] = diag_[j];
      } else if (std::isfinite(hi_[j])) {
        ws_.sets[j] = RowState::Upper;
        ws_.lambda[j] = hi_[j];
        ws_.d[j] = -diag_[j];
      }
    }
    for (int j = 0; j < n_; ++j) ws_.base_free[j] = eq(j) == Eq::Free;
    if (!set_base()) return false;
    // On this piece lambda does not depend on s (rd = 0).
    solve_point(ws_.lambda, ws_.w);
    ws_.w += q_;
    double start = 0;
    int row = -1, kind = 0;
    for (int j = 0; j < n_; ++j) {
      double at = 0;
      int k = kWSlack;
      if (is_friction(j)) {
        if (ws_.e[j] > 0) at = std::abs(ws_.lambda[j]) / ws_.e[j];
        k = ws_.lambda[j] > 0 ? kUpperSlack : kLowerSlack;
      } else if (ws_.d[j] != 0) {
        at = -ws_.w[j] / ws_.d[j];
      }
      if (at > start) {
        start = at;
        row = j;
        kind = k;
      }
    }
    s_ = start;
    ws_.w += s_ * ws_.d;
    last_ = -1;
    return row < 0 || pivot(row, kind);
  }

  // Follows the path from the current point to s = 0. False if it closes on itself, ends on an
  // unbounded piece, exhausts the step's pivot budget, or a piece's system is singular.
  bool follow() {
    ws_.visited.clear();
    lowest_ = std::numeric_limits<double>::infinity();
    for (int events = 0;; ++events) {
      direction();
      int dir = -1;
      if (last_ >= 0) {  // the pivoted row must move into its new feasible side
        const double rate = entering_rate();
        if (!(rate != 0) || !std::isfinite(rate)) return false;
        dir = rate > 0 ? 1 : -1;
      }
      if (!ws_.visited.insert(hash(dir)).second) return false;
      // Ratio test: the first slack to reach zero; ties go to rows other than friction (a normal
      // reaching 0 takes its friction rows' boxes with it), then to the lowest index.
      double best = std::numeric_limits<double>::infinity();
      for_each_slack([&](int, int, double value, double rate) {
        rate *= dir;
        if (rate < 0) best = std::min(best, std::max(0.0, value) / -rate);
      });
      if (dir < 0 && !(best < s_)) {
        advance(-s_);
        s_ = 0;
        return true;
      }
      if (!std::isfinite(best) || ws_.events >= budget_) return false;
      int row = -1, kind = 0;
      for_each_slack([&](int j, int k, double value, double rate) {
        rate *= dir;
        if (!(rate < 0) || std::max(0.0, value) / -rate > best * (1 + kTie)) return;
        if (row < 0 || (is_friction(row) && !is_friction(j))) {
          row = j;
          kind = k;
        }
      });
      advance(dir * best);
      s_ += dir * best;
      ++ws_.events;
      if (s_ < lowest_) {  // the point of the path nearest the problem itself, for a restart
        lowest_ = s_;
        lowest_event_ = events;
        end_point(ws_.start, ws_.start_state);
      } else if (events - lowest_event_ > patience_) {
        return false;
      }
      if (!pivot(row, kind)) return false;
    }
  }

  // The end of the path: the last piece solved at s = 0 and refined against A. Accepted if it
  // satisfies the BLCP with friction bounds from its own normal impulses, within the tolerance;
  // Inexact if only the tolerance fails (the pivots were decided on values carried along the path,
  // whose round-off can misplace a row that ends within ~1e-8 of its switch): the end point is
  // then a warm start one short path away (end_point()).
  enum class End { Accepted, Inexact, Failed };
  End finish(const BlcpSettings& settings, Eigen::VectorXd& lambda, std::vector<RowState>& state,
             Eigen::VectorXd& lo, Eigen::VectorXd& hi) {
    if (!solve_point(ws_.lambda, ws_.w)) return End::Failed;  // w holds A lambda here
    auto terms = [&] {
      double m = 0;
      for (int j = 0; j < n_; ++j) m = std::max(m, std::abs(ws_.lambda[j]) * diag_[j]);
      return m;
    };
    double tol = std::max(settings.tolerance * scale_, kRoundoffFactor * std::numeric_limits<double>::epsilon() * terms());
    double previous = std::numeric_limits<double>::infinity();
    for (int round = 0; round <= 3 * kMaxRefinements; ++round) {
      // Residual of the piece's equations at s = 0, in units of w.
      double residual = 0;
      for (int j = 0; j < n_; ++j) {
        double r = 0;
        switch (eq(j)) {
          case Eq::Free: r = -q_[j] - ws_.w[j]; break;
          case Eq::Bound: r = bound(j) - ws_.lambda[j]; break;
          case Eq::Slide: r = sign(j) * mu_[j] * ws_.lambda[normal_of_[j]] - ws_.lambda[j]; break;
          case Eq::Closed: r = -ws_.lambda[j]; break;
        }
        ws_.r[j] = r;
        residual = std::max(residual, std::abs(r) * (eq(j) == Eq::Free ? 1.0 : diag_[j]));
      }
      if (!(residual > 0) || !(residual < 0.5 * previous) || round == 3 * kMaxRefinements) break;
      previous = residual;
      if (!piece_solve(ws_.r, ws_.t, ws_.at)) return End::Failed;
      ws_.lambda += ws_.t;
      ws_.w += ws_.at;
    }
    ws_.w += q_;
    if (!ws_.lambda.allFinite() || !ws_.w.allFinite()) return End::Failed;
    tol = std::max(settings.tolerance * scale_, kRoundoffFactor * std::numeric_limits<double>::epsilon() * terms());
    ws_.lo = lo_;
    ws_.hi = hi_;
    set_friction_bounds({&normal_of_, &mu_}, ws_.lambda, ws_.lo, ws_.hi);
    ws_.violated.clear();
    bool inexact = false;
    for (int j = 0; j < n_; ++j) {
      const double l = ws_.lambda[j], w = ws_.w[j];
      switch (eq(j)) {
        case Eq::Free:
          if ((ws_.lo[j] - l) * diag_[j] > tol || (l - ws_.hi[j]) * diag_[j] > tol) ws_.violated.push_back(j);
          else inexact = inexact || std::abs(w) > tol;
          break;
        case Eq::Bound:
        case Eq::Slide:
          if (!fixed(j) && (ws_.sets[j] == RowState::Lower ? w < -tol : w > tol)) ws_.violated.push_back(j);
          break;
        case Eq::Closed: break;
      }
    }
    if (inexact || !ws_.violated.empty()) return End::Inexact;
    // Clamped rows exactly on their bounds, free rows clamped against round-off.
    for (int j = 0; j < n_; ++j) {
      const bool open = ws_.lo[j] < ws_.hi[j];
      switch (eq(j)) {
        case Eq::Free:
          lambda[j] = std::clamp(ws_.lambda[j], ws_.lo[j], std::max(ws_.lo[j], ws_.hi[j]));
          state[j] = open ? RowState::Free : RowState::Lower;
          break;
        case Eq::Bound:
        case Eq::Slide: {
          const bool upper = ws_.sets[j] == RowState::Upper && open;
          lambda[j] = upper ? ws_.hi[j] : ws_.lo[j];
          state[j] = upper ? RowState::Upper : RowState::Lower;
          break;
        }
        case Eq::Closed:
          lambda[j] = 0;
          state[j] = RowState::Lower;
          break;
      }
    }
    lo = ws_.lo;
    hi = ws_.hi;
    return End::Accepted;
  }

  // Whether the cold path can still reach s = 0 within the pivot budget: it starts with every
  // bounded row other than friction clamped, so each one the fixed-bounds solution `state` has free
  // must pivot at least once. (On forming 100- and 200-rock piles the cold path, entering at
  // s ~ 10-200, ran out of budget all 9 times it was tried.)
  bool cold_path_fits(const std::vector<RowState>& state) const {
    int pivots = 0;
    for (int j = 0; j < n_; ++j)
      pivots += !is_friction(j) && !fixed(j) && state[j] == RowState::Free &&
                (std::isfinite(lo_[j]) || std::isfinite(hi_[j]));
    return ws_.events + pivots <= budget_;
  }

  // Whether the last follow() pivoted at all (and so left its point nearest s = 0 in ws.start).
  bool moved() const { return lowest_ < std::numeric_limits<double>::infinity(); }

  // The current point as a warm start (clamped rows on their bounds, closed friction rows at 0,
  // sets as on the current piece).
  void end_point(Eigen::VectorXd& lambda, std::vector<RowState>& state) const {
    lambda = ws_.lambda;
    state = ws_.sets;
    for (int j = 0; j < n_; ++j) {
      switch (eq(j)) {
        case Eq::Free: break;
        case Eq::Bound: lambda[j] = bound(j); break;
        case Eq::Slide: lambda[j] = sign(j) * std::max(0.0, mu_[j] * lambda[normal_of_[j]]); break;
        case Eq::Closed: lambda[j] = 0; state[j] = RowState::Lower; break;
      }
    }
  }

 private:
  bool is_friction(int j) const { return normal_of_[j] >= 0; }
  bool fixed(int j) const { return !is_friction(j) && !(lo_[j] < hi_[j]); }
  double sign(int j) const { return ws_.sets[j] == RowState::Upper ? 1.0 : -1.0; }
  double bound(int j) const { return ws_.sets[j] == RowState::Upper ? hi_[j] : lo_[j]; }

  Eq eq(int j) const {
    if (is_friction(j)) {
      if (ws_.e[j] == 0 && ws_.sets[normal_of_[j]] != RowState::Free) return Eq::Closed;
      return ws_.sets[j] == RowState::Free ? Eq::Free : Eq::Slide;
    }
    return ws_.sets[j] == RowState::Free ? Eq::Free : Eq::Bound;
  }
  // Right-hand sides of row j's equation (ra, and rd per unit s), and of its base equation: A_j
  // with -q_j, -d_j on the base's free rows, lambda_j = 0 elsewhere.
  double rhs(int j, bool per_s) const {
    switch (eq(j)) {
      case Eq::Free: return per_s ? -ws_.d[j] : -q_[j];
      case Eq::Bound: return per_s ? 0.0 : bound(j);
      case Eq::Slide: return per_s ? sign(j) * ws_.e[j] : 0.0;
      case Eq::Closed: return 0.0;
    }
    return 0.0;
  }
  double base_rhs(int j, bool per_s) const {
    if (ws_.base_free[j]) return per_s ? -ws_.d[j] : -q_[j];
    return per_s ? ws_.base_sign[j] * ws_.e[j] : 0.0;
  }
  // Whether row j's equation or right-hand side differs from the base's (it then needs a column).
  bool differs(int j) const {
    const Eq type = eq(j);
    if (ws_.base_free[j]) return type != Eq::Free;
    if (ws_.base_sign[j] != 0) return !(type == Eq::Slide && sign(j) == ws_.base_sign[j]);
    return !(type == Eq::Closed || (type == Eq::Bound && bound(j) == 0));
  }
  // Row j of E applied to x (ax = A x), and of the base matrix.
  template <class X, class AX>
  double row_product(int j, const X& x, const AX& ax) const {
    switch (eq(j)) {
      case Eq::Free: return ax[j];
      case Eq::Slide: return x[j] - sign(j) * mu_[j] * x[normal_of_[j]];
      default: return x[j];
    }
  }
  template <class X, class AX>
  double base_product(int j, const X& x, const AX& ax) const {
    if (ws_.base_free[j]) return ax[j];
    return ws_.base_sign[j] == 0 ? x[j] : x[j] - ws_.base_sign[j] * mu_[j] * x[normal_of_[j]];
  }

  // g = M_b^-1 r for the base matrix M_b (rows A_j on the base's free set F, the tied rows of a
  // tied base, identity rows elsewhere), refined against A; ag = A g. Untied: g_C = r_C,
  // g_F = A_FF^-1 (r_F - A_FC r_C).
  bool base_solve(const Eigen::VectorXd& r, Eigen::VectorXd& g, Eigen::VectorXd& ag) {
    if (tied_) return tied_base_solve(r, g, ag);
    bool clamped = false;
    for (int j = 0; j < n_; ++j) {
      g[j] = ws_.base_free[j] ? 0.0 : r[j];
      clamped = clamped || g[j] != 0;
    }
    if (clamped) a_.multiply(g, ag);
    for (int j = 0; j < n_; ++j)
      if (ws_.base_free[j]) g[j] = r[j] - (clamped ? ag[j] : 0.0);
    a_.solve(g);
    a_.multiply(g, ag);
    double previous = std::numeric_limits<double>::infinity();
    for (int round = 0; round < kMaxRefinements; ++round) {
      double residual = 0, size = 0;
      for (int j = 0; j < n_; ++j) {
        size = std::max(size, std::abs(g[j]) * diag_[j]);
        if (!ws_.base_free[j]) continue;
        ws_.t[j] = r[j] - ag[j];
        residual = std::max(residual, std::abs(ws_.t[j]));
        size = std::max(size, std::abs(r[j]));
      }
      if (!(residual > kRoundoffFactor * std::numeric_limits<double>::epsilon() * size) || !(residual < 0.5 * previous))
        break;
      previous = residual;
      for (int j = 0; j < n_; ++j)
        if (!ws_.base_free[j]) ws_.t[j] = 0;
      a_.solve(ws_.t);
      g += ws_.t;
      a_.multiply(g, ag);
    }
    return g.allFinite() && ag.allFinite();
  }

  // g = M_b^-1 r on a tied base (BlcpMatrix::factor_tied), refined against A while that halves the
  // residual of M_b's equations.
  bool tied_base_solve(const Eigen::VectorXd& r, Eigen::VectorXd& g, Eigen::VectorXd& ag) {
    g = r;
    a_.solve_tied(g);
    a_.multiply(g, ag);
    double previous = std::numeric_limits<double>::infinity();
    for (int round = 0; round < kMaxRefinements; ++round) {
      double residual = 0, size = 0;
      for (int j = 0; j < n_; ++j) {
        ws_.t[j] = r[j] - base_product(j, g, ag);
        residual = std::max(residual, std::abs(ws_.t[j]) * (ws_.base_free[j] ? 1.0 : diag_[j]));
        size = std::max({size, std::abs(r[j]), std::abs(g[j]) * diag_[j]});
      }
      if (!(residual > kRoundoffFactor * std::numeric_limits<double>::epsilon() * size) || !(residual < 0.5 * previous))
        break;
      previous = residual;
      a_.solve_tied(ws_.t);
      g += ws_.t;
      a_.multiply(g, ag);
    }
    return g.allFinite() && ag.allFinite();
  }

  // Factors the base, solves its right-hand sides and adds a column for every row whose equation
  // differs from the base's. The base is the free set ws.base_free and, if the backend factors tied
  // systems, the sliding rows of the current piece tied to their normals: every sliding row would
  // otherwise need a column from the first piece on (hundreds on a landing pile), each one solve.
  // `untied`: sets whose free set is factored instead if the base cannot be tied.
  bool set_base(const std::vector<RowState>* untied = nullptr) {
    if (!tie_base()) {
      if (untied)
        for (int j = 0; j < n_; ++j) ws_.base_free[j] = (*untied)[j] == RowState::Free;
      const int factored = a_.prepare(ws_.base_free);
      if (factored < 0) return false;
      ws_.factorizations += factored;
    }
    jump_ = false;
    for (const bool per_s : {false, true}) {
      for (int j = 0; j < n_; ++j) ws_.r[j] = base_rhs(j, per_s);
      if (!base_solve(ws_.r, per_s ? ws_.gd : ws_.ga, per_s ? ws_.agd : ws_.aga)) return false;
    }
    columns_ = 0;
    ws_.column_of.assign(n_, -1);
    ws_.column_row.clear();
    for (int j = 0; j < n_; ++j) ws_.mixed_free[j] = eq(j) == Eq::Free;
    for (int j = 0; j < n_; ++j)
      if (differs(j) && !add_column(j)) return false;
    base_columns_ = columns_;
    return build_capacitance();
  }

  bool add_column(int j) {
    if (ws_.column_of[j] >= 0) return true;
    if (ws_.y.cols() <= columns_) {
      const int cols = std::max(2 * columns_, 16);
      ws_.y.conservativeResize(n_, cols);
      ws_.ay.conservativeResize(n_, cols);
      ws_.mixed.conservativeResize(n_, cols);
    }
    ws_.r.setZero();
    ws_.r[j] = 1;
    if (!base_solve(ws_.r, ws_.g, ws_.ag)) return false;
    ws_.y.col(columns_) = ws_.g;
    ws_.ay.col(columns_) = ws_.ag;
    for (int i = 0; i < n_; ++i) ws_.mixed(i, columns_) = ws_.mixed_free[i] ? ws_.g[i] : ws_.ag[i];
    ws_.column_of[j] = columns_++;
    ws_.column_row.push_back(j);
    return true;
  }

  // Collects the current piece's sliding rows (whose normals are in the base's free set) into
  // ws.sliding and has the backend factor the base with them tied to their normals. False, with an
  // untied base, if there are none or the backend has no tied factorisation.
  bool tie_base() {
    ws_.base_sign.assign(n_, 0);
    ws_.sliding.clear();
    ws_.tie.clear();
    for (int j = 0; j < n_; ++j)
      if (eq(j) == Eq::Slide && ws_.base_free[normal_of_[j]]) {
        ws_.sliding.push_back(j);
        ws_.tie.push_back(sign(j) * mu_[j]);
      }
    tied_ = !ws_.sliding.empty() && a_.factor_tied(ws_.base_free, ws_.sliding, ws_.tie);
    if (!tied_) return false;
    ++ws_.factorizations;
    ++ws_.tied_factorizations;
    for (const int j : ws_.sliding) ws_.base_sign[j] = static_cast<signed char>(sign(j));
    return true;
  }

  // The base of a jump (start_jump, swap_violated): the current free set with its sliding rows
  // tied, and no columns. On a backend without tied factorisation, A_FF is factored and krylov()
  // solves for the sliding rows.
  bool set_jump_base() {
    for (int j = 0; j < n_; ++j) ws_.base_free[j] = eq(j) == Eq::Free;
    jump_ = true;
    columns_ = 0;
    if (tie_base()) return true;
    const int factored = a_.prepare(ws_.base_free);
    if (factored < 0) return false;
    ws_.factorizations += factored;
    return true;
  }

  // x = E^-1 r (ax = A x) from g = M_b^-1 r and ag = A g, on a jump's base. E differs from M_b only
  // on the k sliding rows (lambda_t - sign mu lambda_n = r_t instead of lambda_t = r_t), so
  // x = g + M_b^-1 P z with z on the sliding rows (P embeds them) solving
  //   z_t - sign_t mu_t (M_b^-1 P z)_n(t) = sign_t mu_t g_n(t),
  // the capacitance system, here by GMRES: one base solve per iteration, where the columns of
  // set_base() take k solves and an O(k^3) factorisation. False if it does not converge within
  // kKrylovIterations or a solve fails.
  bool krylov(const Eigen::VectorXd& g, const Eigen::VectorXd& ag, Eigen::VectorXd& x, Eigen::VectorXd& ax) {
    const std::vector<int>& rows = ws_.sliding;
    const int k = static_cast<int>(rows.size());
    const int most = std::min(k, kKrylovIterations);
    x = g;
    ax = ag;
    if (k == 0) return true;
    Eigen::VectorXd& b = ws_.kb;
    b.resize(k);
    for (int i = 0; i < k; ++i) b[i] = sign(rows[i]) * mu_[rows[i]] * g[normal_of_[rows[i]]];
    const double beta = b.norm();
    if (!(beta > 0)) return beta == 0;
    ws_.kx.resize(n_);
    ws_.kax.resize(n_);
    ws_.kv.resize(k, most + 1);
    ws_.ku.resize(n_, most);
    ws_.kau.resize(n_, most);
    ws_.kh.setZero(most + 1, most);
    ws_.kcs.resize(most);
    ws_.ksn.resize(most);
    ws_.kgamma.setZero(most + 1);
    ws_.kv.col(0) = b / beta;
    ws_.kgamma[0] = beta;
    ws_.kr.setZero(n_);  // nonzero on the sliding rows only, rewritten every iteration
    for (int m = 0; m < most; ++m) {
      for (int i = 0; i < k; ++i) ws_.kr[rows[i]] = ws_.kv(i, m);
      if (!base_solve(ws_.kr, ws_.kx, ws_.kax)) return false;
      ws_.ku.col(m) = ws_.kx;
      ws_.kau.col(m) = ws_.kax;
      for (int i = 0; i < k; ++i) b[i] = ws_.kv(i, m) - sign(rows[i]) * mu_[rows[i]] * ws_.kx[normal_of_[rows[i]]];
      for (int j = 0; j <= m; ++j) {  // Arnoldi, modified Gram-Schmidt
        ws_.kh(j, m) = ws_.kv.col(j).dot(b);
        b -= ws_.kh(j, m) * ws_.kv.col(j);
      }
      ws_.kh(m + 1, m) = b.norm();
      for (int j = 0; j < m; ++j) {  // the earlier Givens rotations, then the one for this column
        const double h = ws_.kcs[j] * ws_.kh(j, m) + ws_.ksn[j] * ws_.kh(j + 1, m);
        ws_.kh(j + 1, m) = -ws_.ksn[j] * ws_.kh(j, m) + ws_.kcs[j] * ws_.kh(j + 1, m);
        ws_.kh(j, m) = h;
      }
      const double r = std::hypot(ws_.kh(m, m), ws_.kh(m + 1, m));
      if (!(r > 0)) return false;
      const double below = ws_.kh(m + 1, m);
      ws_.kcs[m] = ws_.kh(m, m) / r;
      ws_.ksn[m] = below / r;
      ws_.kh(m, m) = r;
      ws_.kh(m + 1, m) = 0;
      ws_.kgamma[m + 1] = -ws_.ksn[m] * ws_.kgamma[m];
      ws_.kgamma[m] *= ws_.kcs[m];
      if (std::abs(ws_.kgamma[m + 1]) <= kKrylovTolerance * beta || below == 0) {
        const Eigen::VectorXd c = ws_.kh.topLeftCorner(m + 1, m + 1).triangularView<Eigen::Upper>().solve(
            ws_.kgamma.head(m + 1));
        x.noalias() += ws_.ku.leftCols(m + 1) * c;
        ax.noalias() += ws_.kau.leftCols(m + 1) * c;
        return x.allFinite() && ax.allFinite();
      }
      ws_.kv.col(m + 1) = b / below;
    }
    return false;
  }

  // x = E^-1 r (ax = A x): the backend's tied factorisation on a jump's base if it has one, else
  // from g = M_b^-1 r by Woodbury on the columns, or by krylov() on a jump's base. Clobbers g, ag.
  bool piece_solve(const Eigen::VectorXd& r, Eigen::VectorXd& x, Eigen::VectorXd& ax) {
    if (jump_ && tied_) {
      x = r;
      a_.solve_tied(x);
      a_.multiply(x, ax);
      return x.allFinite() && ax.allFinite();
    }
    if (!base_solve(r, ws_.g, ws_.ag)) return false;
    if (jump_) return krylov(ws_.g, ws_.ag, x, ax);
    woodbury(ws_.g, ws_.ag, x, ax);
    return true;
  }

  // E = M_b + sum_c e_{j_c} u_c^T over the columns; the capacitance is C = I + U^T Y, and the
  // Woodbury solves apply its inverse, kept explicitly: a pivot changes a row of C (a row whose
  // equation changed) or borders it (a new column), both O(k^2) updates (Sherman-Morrison, the
  // bordered inverse), where refactoring C would be O(k^3) per pivot. The inverse is recomputed
  // from C by LU every so many updates (kRefresh) and whenever an update divides by a small pivot.
  double capacitance_entry(int r, int c) const {
    const int j = ws_.column_row[r];
    return (r == c) + row_product(j, ws_.y.col(c), ws_.ay.col(c)) - base_product(j, ws_.y.col(c), ws_.ay.col(c));
  }
  void reserve_capacitance(int k) {
    if (ws_.capacitance.rows() >= k) return;
    const int cap = std::max(2 * k, 32);
    ws_.capacitance.conservativeResize(cap, cap);
    ws_.inverse.conservativeResize(cap, cap);
  }
  bool build_capacitance() {
    const int k = columns_;
    reserve_capacitance(k);
    for (int r = 0; r < k; ++r)
      for (int c = 0; c < k; ++c) ws_.capacitance(r, c) = capacitance_entry(r, c);
    return refresh();
  }
  bool refresh() {
    const int k = columns_;
    updates_ = 0;
    stale_ = false;
    if (k == 0) return true;
    ws_.lu.compute(ws_.capacitance.topLeftCorner(k, k));
    // A singular piece is a degenerate point of the path.
    if (!(ws_.lu.rcond() > std::numeric_limits<double>::epsilon())) return false;
    ws_.inverse.topLeftCorner(k, k) = ws_.lu.inverse();
    return true;
  }
  // Row r of C after its row's equation changed.
  void update_row(int r) {
    const int k = columns_;
    ws_.v.resize(k);
    for (int c = 0; c < k; ++c) ws_.v[c] = capacitance_entry(r, c) - ws_.capacitance(r, c);
    if (ws_.v.isZero(0)) return;
    ws_.capacitance.row(r).head(k) += ws_.v.transpose();
    auto inverse = ws_.inverse.topLeftCorner(k, k);
    ws_.vb.noalias() = inverse.transpose() * ws_.v;  // (v^T B)^T
    const double pivot = 1 + ws_.vb[r];
    ++updates_;
    if (!(std::abs(pivot) > kSmallPivot)) {
      stale_ = true;
      return;
    }
    ws_.bc = inverse.col(r);
    inverse.noalias() -= (ws_.bc / pivot) * ws_.vb.transpose();
  }
  // C bordered by the new last column and row.
  void border() {
    const int k = columns_ - 1;  // size before
    reserve_capacitance(k + 1);
    for (int r = 0; r <= k; ++r) ws_.capacitance(r, k) = capacitance_entry(r, k);
    for (int c = 0; c < k; ++c) ws_.capacitance(k, c) = capacitance_entry(k, c);
    ++updates_;
    if (stale_ || k == 0) {
      stale_ = stale_ || k > 0;
      if (k == 0) ws_.inverse(0, 0) = 1 / ws_.capacitance(0, 0);
      return;
    }
    auto inverse = ws_.inverse.topLeftCorner(k, k);
    ws_.bc.noalias() = inverse * ws_.capacitance.col(k).head(k);            // B b
    ws_.vb.noalias() = inverse.transpose() * ws_.capacitance.row(k).head(k).transpose();  // (c^T B)^T
    const double schur = ws_.capacitance(k, k) - ws_.capacitance.row(k).head(k).dot(ws_.bc);
    if (!(std::abs(schur) > kSmallPivot)) {
      stale_ = true;
      return;
    }
    inverse.noalias() += (ws_.bc / schur) * ws_.vb.transpose();
    ws_.inverse.col(k).head(k) = -ws_.bc / schur;
    ws_.inverse.row(k).head(k) = -ws_.vb.transpose() / schur;
    ws_.inverse(k, k) = 1 / schur;
  }

  // zb = C^-1 (delta - U^T g) for the right-hand side r + sum_c delta_c e_{j_c}, where g = M_b^-1 r
  // and ag = A g, and delta is the piece's change of the base's right-hand side for ra (per_s
  // false) or rd (true), or 0 (none). With U^T the rows by which E differs from M_b and
  // C = I + U^T Y, Woodbury gives x = E^-1 (...) = g + Y delta - Y C^-1 U^T (g + Y delta), and
  // U^T Y delta = (C - I) delta, so x = g + Y zb: two n-by-k products (x and A x), not four.
  void weights(const Eigen::VectorXd& g, const Eigen::VectorXd& ag, std::optional<bool> per_s) {
    const int k = columns_;
    ws_.z.resize(k);
    for (int c = 0; c < k; ++c) {
      const int j = ws_.column_row[c];
      const double delta = per_s ? rhs(j, *per_s) - base_rhs(j, *per_s) : 0.0;
      ws_.z[c] = delta - (row_product(j, g, ag) - base_product(j, g, ag));
    }
    ws_.zb.noalias() = ws_.inverse.topLeftCorner(k, k) * ws_.z;
  }

  // x = g + Y zb, ax = ag + AY zb.
  void combine(const Eigen::VectorXd& g, const Eigen::VectorXd& ag, Eigen::VectorXd& x, Eigen::VectorXd& ax) const {
    const int k = columns_;
    x = g;
    ax = ag;
    if (k == 0) return;
    x.noalias() += ws_.y.leftCols(k) * ws_.zb;
    ax.noalias() += ws_.ay.leftCols(k) * ws_.zb;
  }

  // x = E^-1 r from g = M_b^-1 r and ag = A g; ax = A x.
  void woodbury(const Eigen::VectorXd& g, const Eigen::VectorXd& ag, Eigen::VectorXd& x, Eigen::VectorXd& ax) {
    weights(g, ag, std::nullopt);
    combine(g, ag, x, ax);
  }

  // The piece's point for ra (lambda at s = 0 of the piece's equations); ax = A x. False if a
  // jump's solve fails.
  bool solve_point(Eigen::VectorXd& x, Eigen::VectorXd& ax) {
    if (jump_) {
      for (int j = 0; j < n_; ++j) ws_.r[j] = rhs(j, false);
      return piece_solve(ws_.r, x, ax);
    }
    weights(ws_.ga, ws_.aga, false);
    combine(ws_.ga, ws_.aga, x, ax);
    return true;
  }

  // The piece's direction, dl = d lambda / ds and dw = d w / ds, from one product: the solution
  // for rd is needed on free rows only and its A-image on clamped rows only (ws.mixed). The rest
  // follows from the piece's equations: dw = 0 on free rows (A dl = -d there), dl = 0 on bound and
  // closed rows, dl_t = +-(mu dl_n + e_t) on sliding ones.
  void direction() {
    const int k = columns_;
    for (int j = 0; j < n_; ++j) {
      const bool free = eq(j) == Eq::Free;
      if (ws_.mixed_free[j] == free) continue;
      ws_.mixed_free[j] = free;
      ws_.mixed.row(j).head(k) = free ? ws_.y.row(j).head(k) : ws_.ay.row(j).head(k);
    }
    weights(ws_.gd, ws_.agd, true);
    Eigen::VectorXd& m = ws_.t;
    for (int j = 0; j < n_; ++j) m[j] = ws_.mixed_free[j] ? ws_.gd[j] : ws_.agd[j];
    if (k > 0) m.noalias() += ws_.mixed.leftCols(k) * ws_.zb;
    for (int j = 0; j < n_; ++j) {
      const bool free = eq(j) == Eq::Free;
      ws_.dl[j] = free ? m[j] : 0.0;
      ws_.dw[j] = free ? 0.0 : m[j] + ws_.d[j];
    }
    for (int j = 0; j < n_; ++j)
      if (eq(j) == Eq::Slide) ws_.dl[j] = sign(j) * (mu_[j] * ws_.dl[normal_of_[j]] + ws_.e[j]);
  }

  void advance(double ds) {
    ws_.lambda += ds * ws_.dl;
    ws_.w += ds * ws_.dw;
  }

  // Calls f(row, kind, value, d value / ds) for every slack of the current piece.
  template <class F>
  void for_each_slack(F&& f) const {
    const Eigen::VectorXd &l = ws_.lambda, &dl = ws_.dl;
    for (int j = 0; j < n_; ++j) {
      switch (eq(j)) {
        case Eq::Closed: break;
        case Eq::Free:
          if (is_friction(j)) {
            const int n = normal_of_[j];
            const double box = mu_[j] * l[n] + s_ * ws_.e[j], rate = mu_[j] * dl[n] + ws_.e[j];
            f(j, kUpperSlack, box - l[j], rate - dl[j]);
            f(j, kLowerSlack, box + l[j], rate + dl[j]);
          } else {
            if (std::isfinite(hi_[j])) f(j, kUpperSlack, hi_[j] - l[j], -dl[j]);
            if (std::isfinite(lo_[j])) f(j, kLowerSlack, l[j] - lo_[j], dl[j]);
          }
          break;
        case Eq::Bound:
        case Eq::Slide:
          if (fixed(j)) break;
          if (ws_.sets[j] == RowState::Lower) f(j, kWSlack, ws_.w[j], ws_.dw[j]);
          else f(j, kWSlack, -ws_.w[j], -ws_.dw[j]);
          break;
      }
    }
  }

  // d/ds of the slack the last pivot made active (the one that must grow along the new piece).
  double entering_rate() const {
    const int j = last_;
    if (ws_.sets[j] != RowState::Free) return ws_.sets[j] == RowState::Lower ? ws_.dw[j] : -ws_.dw[j];
    double rate = 0;
    for_each_slack([&](int row, int kind, double, double r) {
      if (row == j && kind == last_kind_) rate = r;
    });
    return rate;
  }

  // Row j's slack `kind` reached zero: it changes sides, its equation changes, and so may those of
  // its friction rows (a normal row that opens or closes its contact).
  bool pivot(int j, int kind) {
    if (ws_.sets[j] == RowState::Free) {
      ws_.sets[j] = kind == kUpperSlack ? RowState::Upper : RowState::Lower;
      if (is_friction(j))
        ws_.lambda[j] = sign(j) * (mu_[j] * ws_.lambda[normal_of_[j]] + s_ * ws_.e[j]);
      else
        ws_.lambda[j] = bound(j);
      last_kind_ = kWSlack;
    } else {
      last_kind_ = ws_.sets[j] == RowState::Upper ? kUpperSlack : kLowerSlack;
      ws_.sets[j] = RowState::Free;
      ws_.w[j] = 0;
    }
    last_ = j;
    if (!changed(j)) return false;
    // Friction rows closed with their normal open sliding against their w (their box grows from
    // zero, so they start on it); they close again, at 0, when it does.
    for (int c = ws_.friction_start[j]; c < ws_.friction_start[j + 1]; ++c) {
      const int t = ws_.friction_rows[c];
      if (ws_.e[t] != 0) continue;
      if (ws_.sets[j] == RowState::Free) {
        ws_.sets[t] = ws_.w[t] > 0 ? RowState::Lower : ws_.w[t] < 0 ? RowState::Upper : RowState::Free;
      } else {
        ws_.lambda[t] = 0;
      }
      if (!changed(t)) return false;
    }
    if (columns_ > std::max(kMinColumns, 2 * base_columns_)) {
      for (int r = 0; r < n_; ++r) ws_.base_free[r] = eq(r) == Eq::Free;
      return set_base();
    }
    return (stale_ || updates_ >= std::max(kRefresh, columns_ / kColumnsPerRefresh)) ? refresh() : true;
  }
  // Row j's equation changed: its row of C changes, or it needs a column.
  bool changed(int j) {
    if (ws_.column_of[j] >= 0) {
      update_row(ws_.column_of[j]);
      return true;
    }
    if (!differs(j)) return true;
    if (!add_column(j)) return false;
    border();
    return true;
  }

  std::uint64_t hash(int dir) const {
    std::uint64_t h = 1469598103934665603ull ^ static_cast<std::uint64_t>(dir + 1);
    for (int j = 0; j < n_; ++j) {
      const int set = eq(j) == Eq::Closed ? 3 : static_cast<int>(ws_.sets[j]);
      h = (h ^ static_cast<std::uint64_t>(set)) * 1099511628211ull;  // FNV-1a
    }
    return h;
  }

  BlcpMatrix& a_;
  const Eigen::VectorXd &q_, &lo_, &hi_;
  const std::vector<int>& normal_of_;
  const std::vector<double>& mu_;
  const Eigen::VectorXd& diag_;
  CoupledWorkspace& ws_;
  const int n_;
  const double scale_;
  double s_ = 1;
  int last_ = -1, last_kind_ = 0;
  int columns_ = 0, base_columns_ = 0;
  bool jump_ = false;  // the base is a jump's (set_jump_base): no columns, krylov() solves
  bool tied_ = false;  // the base is a tied system the backend factored (factor_tied)
  int updates_ = 0;     // updates of the capacitance's inverse since it was computed
  bool stale_ = false;  // an update hit a small pivot: recompute the inverse
  double lowest_ = std::numeric_limits<double>::infinity();
  int lowest_event_ = 0;
  int patience_ = std::max(kMinPatience, n_ / kRowsPerPatience);
  int budget_ = ws_.events + kMinEvents + n_ / kRowsPerEvent;  // ws.events at which every path gives up
};

}  // namespace

bool coupled_friction_step(BlcpMatrix& A, const Eigen::VectorXd& q, Eigen::VectorXd& lo, Eigen::VectorXd& hi,
                           const FrictionCoupling& f, Eigen::VectorXd& lambda, std::vector<RowState>& state,
                           const BlcpSettings& settings, CoupledWorkspace& ws) {
  if (A.size() == 0) return true;
  CoupledPath path(A, q, lo, hi, f, ws);
  using End = CoupledPath::End;
  // Block pivots on the coupled problem from the fixed-bounds solution's sets, while they cut the
  // violated rows: exact when they end, but with no guarantee that they do, so the paths follow.
  int violated = std::numeric_limits<int>::max();
  for (int round = 0; round < kJumpRounds; ++round) {
    if (!(round == 0 ? path.start_jump(lambda, state) : path.swap_violated())) break;
    const End end = path.finish(settings, lambda, state, lo, hi);
    if (end == End::Accepted) {
      ++ws.jumps;
      return true;
    }
    if (end == End::Failed || path.violated() == 0 || path.violated() >= violated) break;
    violated = path.violated();
  }
  const std::vector<int>& normal_of = *f.normal_of;
  int sliding = 0;
  for (std::size_t t = 0; t < normal_of.size(); ++t)
    sliding += normal_of[t] >= 0 && state[t] != RowState::Free && state[normal_of[t]] == RowState::Free;
  if (sliding > kCoupledMaxSliding) return false;
  // Warm paths: from the fixed-bounds solution; from an end point that missed by round-off; after a
  // path that closed on itself, from the fixed-bounds solution for the normal impulses of its point
  // nearest s = 0 (a path through another start). follow() leaves that point in ws.start.
  ws.start = lambda;
  ws.start_state = state;
  const bool large = A.size() >= kLargeCoupledRows;
  for (int attempt = 0; attempt < (large ? settings.coupled_paths : kWarmPaths); ++attempt) {
    if (!path.start_warm(ws.start, ws.start_state)) break;
    if (!path.follow()) {
      if (!path.moved()) break;
      ws.lo = lo;
      ws.hi = hi;
      update_friction_bounds(f, ws.start, ws.lo, ws.hi, ws.start_state);
      const BlcpResult pass = solve_blcp(A, q, ws.lo, ws.hi, ws.start, ws.start_state, settings, ws.blcp);
      ws.factorizations += pass.factorizations;
      if (!pass.converged) break;
      continue;
    }
    const End end = path.finish(settings, lambda, state, lo, hi);
    if (end == End::Accepted) return true;
    if (end == End::Failed) break;
    path.end_point(ws.start, ws.start_state);
  }
  // The cold path, which cannot close on itself, and warm paths from its end if needed.
  if (large || !path.cold_path_fits(state)) return false;
  ++ws.cold_starts;
  if (!path.start_cold() || !path.follow()) return false;
  for (int attempt = 0;; ++attempt) {
    const End end = path.finish(settings, lambda, state, lo, hi);
    if (end == End::Accepted) return true;
    if (end == End::Failed || attempt == kWarmRestarts) return false;
    path.end_point(ws.start, ws.start_state);
    if (!path.start_warm(ws.start, ws.start_state) || !path.follow()) return false;
  }
}

}  // namespace rbpart
