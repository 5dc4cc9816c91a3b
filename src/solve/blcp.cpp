#include "solve/blcp.hpp"

#include <Eigen/LU>

#include <limits>

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
// Pivoting iterations of the coupled friction problem, and the rounds (one solve, then refinement)
// of each of its linear solves.
constexpr int kMaxCoupledPivots = 30;
constexpr int kCoupledRefinements = 3;


double clamp_row(double v, double lo, double hi) { return std::clamp(v, lo, std::max(lo, hi)); }

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

}  // namespace rbpart

namespace rbpart {

bool coupled_friction_step(BlcpMatrix& A, const Eigen::VectorXd& q, Eigen::VectorXd& lo, Eigen::VectorXd& hi,
                           const FrictionCoupling& f, Eigen::VectorXd& lambda, std::vector<RowState>& state,
                           const BlcpSettings& settings, CoupledWorkspace& cw) {
  const int n = A.size();
  if (n == 0) return true;
  const std::vector<int>& normal_of = *f.normal_of;
  const std::vector<double>& mu = *f.mu;
  const Eigen::VectorXd& diag = A.diagonal();
  const double scale = std::max(max_abs(q), kMinScale);
  auto is_friction = [&](int j) { return normal_of[j] >= 0; };
  // Working sets of the coupled problem. A friction row whose box was closed starts sticking (its
  // normal may open it); its state only matters while its normal row is free.
  cw.sets = state;
  for (int j = 0; j < n; ++j)
    if (is_friction(j) && !(lo[j] < hi[j])) cw.sets[j] = RowState::Free;
  cw.free.assign(n, 0);
  cw.slope.setZero(n);
  cw.fixed.setZero(n);
  cw.t.resize(n);
  cw.u.resize(n);
  cw.x.resize(n);
  cw.w.resize(n);
  cw.b.resize(n);
  cw.lambda.resize(n);
  auto assemble = [&](Eigen::VectorXd& out) {  // lambda from the free values in cw.x
    for (int j = 0; j < n; ++j)
      out[j] = cw.free[j] ? cw.x[j] : cw.slope[j] != 0 ? cw.slope[j] * cw.x[normal_of[j]] : cw.fixed[j];
  };
  double tol = settings.tolerance * scale;
  // > 0: row j violates the coupled BLCP for the current sets, in units of w. A sliding row is on
  // its bound by construction and needs the sign of w that pushes it there; a sticking row must
  // stay inside +-mu lambda_n of its own normal; a friction row of a clamped normal is 0.
  auto violation = [&](int j) {
    const double l = cw.lambda[j], w = cw.w[j];
    double low = lo[j], high = hi[j];
    if (is_friction(j)) {
      if (cw.sets[normal_of[j]] != RowState::Free) return 0.0;
      high = mu[j] * std::max(0.0, cw.lambda[normal_of[j]]);
      low = -high;
    } else if (!(low < high)) {
      return 0.0;
    }
    switch (cw.sets[j]) {
      case RowState::Free: return std::max(low - l, l - high) * diag[j];
      case RowState::Lower: return -w;
      case RowState::Upper: return w;
    }
    return 0.0;
  };

  auto swap = [&](int j) {
    if (cw.sets[j] != RowState::Free) cw.sets[j] = RowState::Free;
    else if (is_friction(j)) cw.sets[j] = cw.lambda[j] > 0 ? RowState::Upper : RowState::Lower;
    else cw.sets[j] = cw.lambda[j] < lo[j] ? RowState::Lower : RowState::Upper;
  };
  // Block principal pivoting on the coupled problem (DESIGN.md §3): every row that violates its
  // conditions swaps, while the count of violating rows keeps reaching new lows.
  int fewest = n + 1, patience = settings.pivot_patience;
  bool solved = false;
  for (int iteration = 0; iteration < kMaxCoupledPivots; ++iteration) {
    for (int j = 0; j < n; ++j) {
      cw.free[j] = 0;
      cw.slope[j] = 0;
      cw.fixed[j] = 0;
      if (is_friction(j)) {
        if (cw.sets[normal_of[j]] != RowState::Free) continue;  // its normal impulse is 0: held at 0
        if (cw.sets[j] == RowState::Free) cw.free[j] = 1;
        else cw.slope[j] = cw.sets[j] == RowState::Upper ? mu[j] : -mu[j];
      } else if (cw.sets[j] == RowState::Free) {
        cw.free[j] = 1;
      } else {
        cw.fixed[j] = cw.sets[j] == RowState::Upper ? hi[j] : lo[j];
      }
    }
    const int factored = A.prepare(cw.free);
    if (factored < 0) return false;
    cw.factorizations += factored;
    // The free rows' equations with the sliding rows substituted: (I + Z E) x_F = A_FF^-1 b_F,
    // where E picks the k normal rows that carry sliding friction and column c of Z is
    // A_FF^-1 (A g_c)_F, g_c = sum of slope_s e_s over the sliding rows s of normal c. Woodbury
    // with the k x k capacitance I + E Z solves it exactly with k + 1 solves on the factor.
    cw.normals.clear();
    for (int j = 0; j < n; ++j)
      if (cw.slope[j] != 0 && (cw.normals.empty() || cw.normals.back() != normal_of[j]))
        cw.normals.push_back(normal_of[j]);
    std::sort(cw.normals.begin(), cw.normals.end());
    cw.normals.erase(std::unique(cw.normals.begin(), cw.normals.end()), cw.normals.end());
    const int k = static_cast<int>(cw.normals.size());
    cw.z.resize(n, k);
    for (int c = 0; c < k; ++c) {
      for (int j = 0; j < n; ++j) cw.t[j] = cw.slope[j] != 0 && normal_of[j] == cw.normals[c] ? cw.slope[j] : 0.0;
      A.multiply(cw.t, cw.u);
      for (int j = 0; j < n; ++j) cw.u[j] = cw.free[j] ? cw.u[j] : 0.0;
      A.solve(cw.u);
      cw.z.col(c) = cw.u;
    }
    cw.capacitance.setIdentity(k, k);
    for (int r = 0; r < k; ++r) cw.capacitance.row(r) += cw.z.row(cw.normals[r]);
    cw.lu.compute(cw.capacitance);
    // Refined against A: the first round solves from lambda_F = 0, later ones correct round-off.
    cw.x.setZero();
    for (int round = 0; round < kCoupledRefinements; ++round) {
      assemble(cw.lambda);
      A.multiply(cw.lambda, cw.w);
      cw.w += q;
      for (int j = 0; j < n; ++j) cw.b[j] = cw.free[j] ? -cw.w[j] : 0.0;
      A.solve(cw.b);
      if (k > 0) {
        cw.y.resize(k);
        for (int c = 0; c < k; ++c) cw.y[c] = cw.b[cw.normals[c]];
        cw.b -= cw.z * cw.lu.solve(cw.y);
      }
      for (int j = 0; j < n; ++j)
        if (cw.free[j]) cw.x[j] += cw.b[j];
    }
    assemble(cw.lambda);
    A.multiply(cw.lambda, cw.w);
    cw.w += q;
    if (!cw.lambda.allFinite() || !cw.w.allFinite()) return false;
    double terms = 0;
    for (int j = 0; j < n; ++j) terms = std::max(terms, std::abs(cw.lambda[j]) * diag[j]);
    tol = std::max(settings.tolerance * scale, kRoundoffFactor * std::numeric_limits<double>::epsilon() * terms);
    int count = 0;
    for (int j = 0; j < n; ++j) count += violation(j) > tol;
    if (count == 0) {
      solved = true;
      break;
    }
    if (count < fewest) {
      fewest = count;
      patience = settings.pivot_patience;
    } else if (patience > 0) {
      --patience;
    }
    // Block swaps while they make progress. Once they stall (block pivoting can cycle), one row
    // swaps per iteration, the first violating friction row if any, else the first violating
    // row: a normal row that opens under a sticking guess goes negative, and closing it again
    // would undo the swap, whereas letting its friction slide resolves it.
    if (patience > 0) {
      for (int j = 0; j < n; ++j)
        if (violation(j) > tol) swap(j);
      continue;
    }
    int first = -1;
    for (int j = 0; j < n; ++j) {
      if (violation(j) <= tol) continue;
      if (is_friction(j)) {
        first = j;
        break;
      }
      if (first < 0) first = j;
    }
    swap(first);
  }
  if (!solved) return false;
  // Accept only an exact solution of the coupled BLCP: bounds from its own normal impulses.
  cw.lo = lo;
  cw.hi = hi;
  set_friction_bounds(f, cw.lambda, cw.lo, cw.hi);
  for (int j = 0; j < n; ++j) {
    const double l = cw.lambda[j], w = cw.w[j];
    if (cw.free[j]) {
      if (std::abs(w) > tol || (cw.lo[j] - l) * diag[j] > tol || (l - cw.hi[j]) * diag[j] > tol) return false;
    } else if (cw.lo[j] < cw.hi[j]) {
      if (l <= cw.lo[j] ? w < -tol : l >= cw.hi[j] ? w > tol : std::abs(w) > tol) return false;
    }
  }
  for (int j = 0; j < n; ++j) {
    lambda[j] = std::clamp(cw.lambda[j], cw.lo[j], std::max(cw.lo[j], cw.hi[j]));
    state[j] = cw.free[j] && cw.lo[j] < cw.hi[j] ? RowState::Free
               : lambda[j] == cw.hi[j] && cw.lo[j] < cw.hi[j] ? RowState::Upper
                                                              : RowState::Lower;
  }
  lo = cw.lo;
  hi = cw.hi;
  return true;
}

}  // namespace rbpart
