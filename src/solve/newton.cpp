#include "solve/newton.hpp"

#include "core/timer.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rbpart {

namespace {

constexpr double kArmijo = 1e-4;     // sufficient decrease: merit falls by 2 kArmijo alpha of itself
constexpr int kHalvings = 10;        // step lengths 1, 1/2, ..., 1/1024 (no factorisation: products only)
constexpr double kFirstShift = 1e-3; // proximal shift after the first failed line search, times A_jj
constexpr double kLargestShift = 1e4;
constexpr int kRefinements = 3;      // refinement solves per step, at most

// Merit 1/2 ||D F||^2; NaN counts as infinite.
double merit(const Eigen::VectorXd& fw) {
  const double m = 0.5 * fw.squaredNorm();
  return std::isnan(m) ? std::numeric_limits<double>::infinity() : m;
}

// max_j |fw_j| / scale, NaN as infinite.
double residual_of(const Eigen::VectorXd& fw, double scale) {
  double r = 0;
  for (Eigen::Index j = 0; j < fw.size(); ++j) {
    const double v = std::abs(fw[j]);
    if (!(v <= r)) r = std::isnan(v) ? std::numeric_limits<double>::infinity() : v;
  }
  return r / scale;
}

void velocities(const IslandSystem& s, const Eigen::VectorXd& lambda, Eigen::VectorXd& du, Eigen::VectorXd& w) {
  apply_a(s, lambda, du, w);
  w += s.q;
}

// Normals and joint rows onto [lo, hi], then friction onto the box of its projected normal.
void project_onto_bounds(const IslandSystem& s, Eigen::VectorXd& lambda) {
  for (int j = 0; j < s.rows; ++j)
    if (s.normal_of[j] < 0) lambda[j] = std::clamp(lambda[j], s.lo[j], s.hi[j]);
  for (int j = 0; j < s.rows; ++j)
    if (s.normal_of[j] >= 0) {
      const double bound = s.mu[j] * std::max(0.0, lambda[s.normal_of[j]]);
      lambda[j] = std::clamp(lambda[j], -bound, bound);
    }
}

// The Newton state at (lambda, w): each row's equation and right-hand side, and its RowState (the
// warm start the step leaves for the next one). With `warm`, rows free there stay free and the
// friction rows keep their tie; clamped rows follow the natural map (a new contact, stored at 0,
// starts free when it approaches). Normals and joints come first: a friction row ties only to a
// free normal, and its box is closed (lambda_t = 0) when the normal is at 0.
void choose_piece(const IslandSystem& s, const Eigen::VectorXd& lambda, const Eigen::VectorXd& w,
                  const std::vector<RowState>* warm, double rho, NewtonWorkspace& ws) {
  Piece& piece = ws.piece;
  std::vector<RowState>& state = ws.piece_state;
  const int n = s.rows;
  piece.equation.resize(n);
  piece.tie.setZero(n);
  piece.shift.setZero(n);
  state.resize(n);
  ws.g.resize(n);
  // A free row: w_j + shift_j (lambda_j - lambda_k,j) = 0 at the proximal centre lambda_k.
  const auto set_free = [&](int j) {
    piece.equation[j] = RowEquation::Free;
    piece.shift[j] = rho * s.diag[j];
    ws.g[j] = -s.q[j] + piece.shift[j] * lambda[j];
  };
  for (int j = 0; j < n; ++j) {
    if (s.normal_of[j] >= 0) continue;
    const double x = lambda[j] - w[j] / s.diag[j];
    RowState st = x <= s.lo[j] ? RowState::Lower : x >= s.hi[j] ? RowState::Upper : RowState::Free;
    if (warm && (*warm)[j] == RowState::Free) st = RowState::Free;
    state[j] = st;
    if (st == RowState::Free) {
      set_free(j);
    } else {
      piece.equation[j] = RowEquation::Fixed;
      ws.g[j] = st == RowState::Lower ? s.lo[j] : s.hi[j];
    }
  }
  for (int j = 0; j < n; ++j) {
    const int normal = s.normal_of[j];
    if (normal < 0) continue;
    ws.g[j] = 0;
    if (piece.equation[normal] != RowEquation::Free || lambda[normal] < 0) {
      piece.equation[j] = RowEquation::Fixed;
      state[j] = RowState::Free;  // sticking: the physical first guess if the box opens again
      continue;
    }
    RowState st;
    if (warm && lambda[normal] > 0) {
      st = (*warm)[j];
    } else {
      const double bound = s.mu[j] * std::max(0.0, lambda[normal]);
      const double x = lambda[j] - w[j] / s.diag[j];
      st = x >= bound && x > 0 ? RowState::Upper : x <= -bound && x < 0 ? RowState::Lower : RowState::Free;
    }
    state[j] = st;
    if (st == RowState::Free) {
      set_free(j);
    } else {
      piece.equation[j] = RowEquation::Tied;
      piece.tie[j] = st == RowState::Upper ? s.mu[j] : -s.mu[j];
    }
  }
}

// e = g - E x for the piece's exact equations (E as in linear_system.hpp, A x matrix-free); returns
// max |e_j| over the rows.
double piece_residual(const IslandSystem& s, const Piece& piece, const Eigen::VectorXd& g, const Eigen::VectorXd& x,
                      Eigen::VectorXd& du, Eigen::VectorXd& ax, Eigen::VectorXd& e) {
  apply_a(s, x, du, ax);
  e.resize(s.rows);
  double worst = 0;
  for (int j = 0; j < s.rows; ++j) {
    switch (piece.equation[j]) {
      case RowEquation::Free: e[j] = g[j] - ax[j] - piece.shift[j] * x[j]; break;
      case RowEquation::Fixed: e[j] = g[j] - x[j]; break;
      case RowEquation::Tied: e[j] = g[j] - (x[j] - piece.tie[j] * x[s.normal_of[j]]); break;
    }
    worst = std::max(worst, std::abs(e[j]));
  }
  return worst;
}

}  // namespace

void scaled_natural_map(const IslandSystem& s, const Eigen::VectorXd& lambda, const Eigen::VectorXd& w,
                        Eigen::VectorXd& fw) {
  fw.resize(s.rows);
  for (int j = 0; j < s.rows; ++j) {
    double lo = s.lo[j], hi = s.hi[j];
    if (s.normal_of[j] >= 0) {
      hi = s.mu[j] * std::max(0.0, lambda[s.normal_of[j]]);
      lo = -hi;
    }
    fw[j] = (lambda[j] - std::clamp(lambda[j] - w[j] / s.diag[j], lo, std::max(lo, hi))) * s.diag[j];
  }
}

NewtonResult solve_newton(const IslandSystem& s, LinearSystem& system, int max_factorizations, Eigen::VectorXd& lambda,
                          std::vector<RowState>& state, NewtonWorkspace& ws) {
  NewtonResult result;
  for (int j = 0; j < s.rows; ++j)
    if (!std::isfinite(lambda[j])) lambda[j] = 0;
  const double scale = std::max(max_abs(s.q), 1e-12);
  // The answer is the admissible point of least residual: each iterate projected onto its bounds.
  result.residual = std::numeric_limits<double>::infinity();
  const auto keep_if_better = [&] {
    ws.trial = lambda;
    project_onto_bounds(s, ws.trial);
    velocities(s, ws.trial, ws.du, ws.trial_w);
    scaled_natural_map(s, ws.trial, ws.trial_w, ws.trial_fw);
    const double r = residual_of(ws.trial_fw, scale);
    if (ws.best.size() == 0 || r < result.residual) {
      result.residual = r;
      ws.best = ws.trial;
    }
  };
  ws.best.resize(0);
  keep_if_better();
  velocities(s, lambda, ws.du, ws.w);
  scaled_natural_map(s, lambda, ws.w, ws.fw);
  double rho = 0;
  bool warm = true;
  while (result.residual > kSettledResidual && result.factorizations < max_factorizations) {
    choose_piece(s, lambda, ws.w, warm ? &state : nullptr, rho, ws);
    warm = false;
    ++result.iterations;
    ++result.factorizations;
    const Timer timer;
    const bool factored = system.factor(ws.piece);
    result.factor_ms += timer.ms();
    if (!factored) {
      rho = rho == 0 ? kFirstShift : 10 * rho;
      continue;
    }
    // The piece's solution, refined against its exact equations.
    system.solve(ws.g, ws.x);
    double error = piece_residual(s, ws.piece, ws.g, ws.x, ws.du, ws.ad, ws.e);
    for (int r = 0; r < kRefinements && error > 1e-15 * scale; ++r) {
      system.solve(ws.e, ws.ex);
      ws.trial = ws.x + ws.ex;
      const double next = piece_residual(s, ws.piece, ws.g, ws.trial, ws.du, ws.ad, ws.e);
      if (!(next < error)) break;
      error = next;
      ws.x = ws.trial;
    }
    // Line search along d = x - lambda on the merit; w is affine in the step.
    ws.d = ws.x - lambda;
    apply_a(s, ws.d, ws.du, ws.ad);
    const double merit0 = merit(ws.fw);
    double alpha = 1;
    bool accepted = false;
    for (int h = 0; h <= kHalvings; ++h, alpha *= 0.5) {
      ws.trial = lambda + alpha * ws.d;
      ws.trial_w = ws.w + alpha * ws.ad;
      scaled_natural_map(s, ws.trial, ws.trial_w, ws.trial_fw);
      if (merit(ws.trial_fw) <= (1 - 2 * kArmijo * alpha) * merit0) {
        accepted = true;
        break;
      }
    }
    if (!accepted) {
      rho = rho == 0 ? kFirstShift : std::min(10 * rho, kLargestShift);
      continue;
    }
    lambda = ws.trial;
    velocities(s, lambda, ws.du, ws.w);
    scaled_natural_map(s, lambda, ws.w, ws.fw);
    keep_if_better();
    if (alpha == 1) rho = rho < 1e-9 ? 0 : 0.1 * rho;
  }
  lambda = ws.best;
  velocities(s, lambda, ws.du, ws.w);
  choose_piece(s, lambda, ws.w, nullptr, 0, ws);
  state = ws.piece_state;
  result.settled = result.residual <= kSettledResidual;
  return result;
}

}  // namespace rbpart
