#include "solve/newton.hpp"

#include "core/timer.hpp"
#include "solve/interior_point.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rbpart {

namespace {

constexpr int kRefinements = 3;  // refinement solves per Newton step, at most
// Full Newton steps without a better answer before the interior-point phase takes over.
constexpr int kPatience = 2;

// max_j |fw_j| / scale, NaN as infinite (the largest |fw_j| as the least -|fw_j|).
double residual_of(const Eigen::VectorXd& fw, double scale, IslandChunks& chunks) {
  const double least = chunks.min(static_cast<int>(fw.size()), [&](int j) {
    return std::isnan(fw[j]) ? -std::numeric_limits<double>::infinity() : -std::abs(fw[j]);
  });
  return std::max(0.0, -least) / scale;
}

void velocities(const IslandSystem& s, const Eigen::VectorXd& lambda, Eigen::VectorXd& du, Eigen::VectorXd& w,
                IslandChunks& chunks) {
  apply_a(s, lambda, du, w, chunks);
  chunks.each(s.rows, [&](int j) { w[j] += s.q[j]; });
}

bool all_finite(const Eigen::VectorXd& v, IslandChunks& chunks) {
  return chunks.min(static_cast<int>(v.size()), [&](int j) { return std::isfinite(v[j]) ? 1.0 : 0.0; }) > 0;
}

// to = from, in chunks.
void copy(const Eigen::VectorXd& from, Eigen::VectorXd& to, IslandChunks& chunks) {
  to.resize(from.size());
  chunks.each(static_cast<int>(from.size()), [&](int j) { to[j] = from[j]; });
}

// Normals and joint rows onto [lo, hi], then friction onto the box of its projected normal.
void project_onto_bounds(const IslandSystem& s, Eigen::VectorXd& lambda, IslandChunks& chunks) {
  chunks.each(s.rows, [&](int j) {
    if (s.normal_of[j] < 0) lambda[j] = std::clamp(lambda[j], s.lo[j], s.hi[j]);
  });
  chunks.each(s.rows, [&](int j) {
    if (s.normal_of[j] >= 0) {
      const double bound = s.mu[j] * std::max(0.0, lambda[s.normal_of[j]]);
      lambda[j] = std::clamp(lambda[j], -bound, bound);
    }
  });
}

// The kinetic energy an answer leaves: with q = J u* + b (u* the free motion, b assemble.cpp's
// position bias and friction's proximal term) and A = J M^-1 J^T + Sigma, the bodies' kinetic
// energy changes from the free motion's by E(lambda) - lambda^T Sigma lambda / 2 - lambda^T b,
// E(lambda) = lambda^T A lambda / 2 + lambda^T q. An exact answer does no positive work (lambda_j w_j <= 0 on every row: w = 0 on
// free rows, at a bound w pushes outward and every box holds 0), so E <= -lambda^T A lambda / 2 < 0.
// A point with E > 0 would add energy to the free motion: it is scaled back to t lambda, t = -b' / a
// (a = lambda^T A lambda, b' = lambda^T q; 0 if b' >= 0), the point of its ray that does no work and
// E(t lambda) = -b'^2 / 2a <= 0. t lambda is admissible: the boxes hold 0 and friction's scales with
// its normal. Returns t (1: left as it is). Only for boxes that hold 0 (see `scalable`).
double energy_scale(const IslandSystem& s, const Eigen::VectorXd& lambda, const Eigen::VectorXd& w,
                    IslandChunks& chunks) {
  const double work = chunks.sum(s.rows, [&](int j) { return lambda[j] * w[j]; });  // a + b'
  const double free_work = chunks.sum(s.rows, [&](int j) { return lambda[j] * s.q[j]; });  // b'
  if (!(work + free_work > 0)) return 1;                            // 2 E <= 0 (or not finite)
  // -b' / a without cancellation when t is small.
  return free_work < 0 ? -free_work / (work - free_work) : 0.0;
}

// The natural map's state at (lambda, w): each row Free, or at its Lower or Upper bound (a
// friction row: at -+mu lambda_n). With `warm`, rows free there stay free and friction rows keep
// their state while their normal pushes; clamped rows follow the natural map (a new contact, stored
// at 0, starts free when it approaches).
void natural_state(const IslandSystem& s, const Eigen::VectorXd& lambda, const Eigen::VectorXd& w,
                   const std::vector<RowState>* warm, std::vector<RowState>& state, IslandChunks& chunks) {
  state.resize(s.rows);
  chunks.each(s.rows, [&](int j) {
    const int normal = s.normal_of[j];
    const double x = lambda[j] - w[j] / s.diag[j];
    if (normal < 0) {
      state[j] = warm && (*warm)[j] == RowState::Free ? RowState::Free
                 : x <= s.lo[j]                      ? RowState::Lower
                 : x >= s.hi[j]                      ? RowState::Upper
                                                     : RowState::Free;
    } else if (warm && lambda[normal] > 0) {
      state[j] = (*warm)[j];
    } else {
      const double bound = s.mu[j] * std::max(0.0, lambda[normal]);
      state[j] = x >= bound && x > 0 ? RowState::Upper : x <= -bound && x < 0 ? RowState::Lower : RowState::Free;
    }
  });
}

// The piece of ws.piece_state at lambda: each row's equation and right-hand side. Normals and
// joints come first: a friction row ties only to a free normal, and its box is closed
// (lambda_t = 0; its state Free, the physical first guess if the box opens again) when the normal
// is not free or lambda_n < 0.
void set_piece(const IslandSystem& s, const Eigen::VectorXd& lambda, NewtonWorkspace& ws) {
  Piece& piece = ws.piece;
  std::vector<RowState>& state = ws.piece_state;
  const int n = s.rows;
  piece.equation.resize(n);
  piece.tie.resize(n);
  piece.shift.resize(n);
  ws.g.resize(n);
  const auto set_free = [&](int j) {  // w_j = 0
    piece.equation[j] = RowEquation::Free;
    ws.g[j] = -s.q[j];
  };
  ws.chunks.each(n, [&](int j) {
    piece.tie[j] = piece.shift[j] = 0;
    if (s.normal_of[j] >= 0) return;
    if (state[j] == RowState::Free) {
      set_free(j);
    } else {
      piece.equation[j] = RowEquation::Fixed;
      ws.g[j] = state[j] == RowState::Lower ? s.lo[j] : s.hi[j];
    }
  });
  ws.chunks.each(n, [&](int j) {
    const int normal = s.normal_of[j];
    if (normal < 0) return;
    ws.g[j] = 0;
    if (piece.equation[normal] != RowEquation::Free || lambda[normal] < 0) {
      piece.equation[j] = RowEquation::Fixed;
      state[j] = RowState::Free;
    } else if (state[j] == RowState::Free) {
      set_free(j);
    } else {
      piece.equation[j] = RowEquation::Tied;
      piece.tie[j] = state[j] == RowState::Upper ? s.mu[j] : -s.mu[j];
    }
  });
}

// e = g - E x for the piece's exact equations (E as in linear_system.hpp, A x matrix-free); returns
// max |e_j| over the rows.
double piece_residual(const IslandSystem& s, const Piece& piece, const Eigen::VectorXd& g, const Eigen::VectorXd& x,
                      Eigen::VectorXd& du, Eigen::VectorXd& ax, Eigen::VectorXd& e, IslandChunks& chunks) {
  apply_a(s, x, du, ax, chunks);
  e.resize(s.rows);
  // The largest |e_j| as the least -|e_j| (a NaN entry is passed over).
  const double least = chunks.min(s.rows, [&](int j) {
    switch (piece.equation[j]) {
      case RowEquation::Free: e[j] = g[j] - ax[j] - piece.shift[j] * x[j] + (piece.tie[j] != 0 ? piece.tie[j] * x[s.normal_of[j]] : 0.0); break;
      case RowEquation::Fixed: e[j] = g[j] - x[j]; break;
      case RowEquation::Tied: e[j] = g[j] - (x[j] - piece.tie[j] * x[s.normal_of[j]]); break;
    }
    return -std::abs(e[j]);
  });
  return std::max(0.0, -least);
}

}  // namespace

void scaled_natural_map(const IslandSystem& s, const Eigen::VectorXd& lambda, const Eigen::VectorXd& w,
                        Eigen::VectorXd& fw, IslandChunks& chunks) {
  fw.resize(s.rows);
  chunks.each(s.rows, [&](int j) {
    double lo = s.lo[j], hi = s.hi[j];
    if (s.normal_of[j] >= 0) {
      hi = s.mu[j] * std::max(0.0, lambda[s.normal_of[j]]);
      lo = -hi;
    }
    fw[j] = (lambda[j] - std::clamp(lambda[j] - w[j] / s.diag[j], lo, std::max(lo, hi))) * s.diag[j];
  });
}

void scaled_natural_map(const IslandSystem& s, const Eigen::VectorXd& lambda, const Eigen::VectorXd& w,
                        Eigen::VectorXd& fw) {
  IslandChunks serial;
  scaled_natural_map(s, lambda, w, fw, serial);
}

NewtonResult solve_newton(const IslandSystem& s, LinearSystem& system, int max_factorizations, Eigen::VectorXd& lambda,
                          std::vector<RowState>& state, NewtonWorkspace& ws) {
  NewtonResult result;
  const double scale = std::max(max_abs(s.q), 1e-12);
  // The iteration steers by the admissible point of least residual among the projected iterates
  // (ws.best). The answer is that point if it settles; if none does, the point of least residual
  // once each is scaled back where it would add kinetic energy to the free motion (ws.answer,
  // energy_scale): the budget may end far from the answer, and points that add energy threw the
  // boxes of a 1:100:10000 bin out at up to 1e9 J.
  double best = std::numeric_limits<double>::infinity(), answer = best;
  double last = 0;  // the residual of the last point considered
  bool have_best = false, have_answer = false;  // the first point is kept even if its residual is not finite
  // Scaling back needs every box to hold 0: the engine's rows do, a general box row may not.
  bool scalable = true;
  for (int j = 0; j < s.rows; ++j) scalable = scalable && (s.normal_of[j] >= 0 || (s.lo[j] <= 0 && s.hi[j] >= 0));
  const auto consider = [&](Eigen::VectorXd& candidate) {
    project_onto_bounds(s, candidate, ws.chunks);
    velocities(s, candidate, ws.du, ws.trial_w, ws.chunks);
    scaled_natural_map(s, candidate, ws.trial_w, ws.trial_fw, ws.chunks);
    last = residual_of(ws.trial_fw, scale, ws.chunks);
    if (last < best || !have_best) {
      have_best = true;
      best = last;
      copy(candidate, ws.best, ws.chunks);
    }
    if (last <= kSettledResidual) return;
    // Scaled back, projected again (t mu lambda_n may round below t lambda_t) and measured anew.
    const double t = scalable ? energy_scale(s, candidate, ws.trial_w, ws.chunks) : 1.0;
    double residual = last;
    if (t != 1) {
      ws.ex.resize(s.rows);
      ws.chunks.each(s.rows, [&](int j) { ws.ex[j] = t * candidate[j]; });
      project_onto_bounds(s, ws.ex, ws.chunks);
      velocities(s, ws.ex, ws.du, ws.trial_w, ws.chunks);
      scaled_natural_map(s, ws.ex, ws.trial_w, ws.trial_fw, ws.chunks);
      residual = residual_of(ws.trial_fw, scale, ws.chunks);
    }
    if (residual < answer || !have_answer) {
      have_answer = true;
      answer = residual;
      copy(t != 1 ? ws.ex : candidate, ws.answer, ws.chunks);
    }
  };
  const auto settled = [&] {
    return best <= kSettledResidual || result.factorizations >= max_factorizations;
  };
  // The solution of a piece (one factorisation), refined against its exact equations, in ws.x.
  const auto solve_piece = [&]() {
    ++result.factorizations;
    ++result.iterations;
    const Timer timer;
    const bool factored = system.factor(ws.piece);
    result.factor_ms += timer.ms();
    if (!factored) return false;
    system.solve(ws.g, ws.x);
    double error = piece_residual(s, ws.piece, ws.g, ws.x, ws.du, ws.ad, ws.e, ws.chunks);
    for (int r = 0; r < kRefinements && error > 1e-15 * scale; ++r) {
      system.solve(ws.e, ws.ex);
      ws.trial.resize(s.rows);
      ws.chunks.each(s.rows, [&](int j) { ws.trial[j] = ws.x[j] + ws.ex[j]; });
      const double next = piece_residual(s, ws.piece, ws.g, ws.trial, ws.du, ws.ad, ws.e, ws.chunks);
      if (!(next < error)) break;
      error = next;
      ws.x.swap(ws.trial);
    }
    return all_finite(ws.x, ws.chunks);
  };
  // Full Newton steps from ws.base (velocities ws.base_w), the first in the state ws.piece_state,
  // each next one in the state the natural map gives at the last step's solution, unprojected, so
  // that rows it pushed past a bound are fixed there and rows whose bound pushes them inward are
  // freed, many at a time (primal-dual active set). They stop on a repeated state or after
  // kPatience steps without a better answer.
  const auto newton_steps = [&]() {
    int idle = 0;
    ws.last_state.clear();
    while (!settled() && idle < kPatience) {
      if (!ws.last_state.empty()) natural_state(s, ws.base, ws.base_w, nullptr, ws.piece_state, ws.chunks);
      set_piece(s, ws.base, ws);
      if (ws.piece_state == ws.last_state) return;
      ws.last_state = ws.piece_state;
      if (!solve_piece()) return;
      copy(ws.x, ws.base, ws.chunks);
      velocities(s, ws.base, ws.du, ws.base_w, ws.chunks);
      const double before = best;
      consider(ws.x);
      idle = best < before ? 0 : idle + 1;
    }
  };

  ws.start = lambda;
  for (int j = 0; j < s.rows; ++j)
    if (!std::isfinite(ws.start[j])) ws.start[j] = 0;
  ws.base = ws.start;
  velocities(s, ws.base, ws.du, ws.base_w, ws.chunks);
  ws.trial = ws.start;
  consider(ws.trial);
  // The first step from the warm start takes its states (at rest: the answer).
  natural_state(s, ws.base, ws.base_w, &state, ws.piece_state, ws.chunks);
  newton_steps();
  // The interior-point phase, from a cold start: after each of its steps, the state its predictor
  // indicates (interior_point.hpp); when that state is the one of the step before (and not tried
  // yet), Newton steps from its iterate, the first in that state.
  if (!settled()) {
    ws.ipm.start(s);
    ws.ipm_state.clear();
    ws.tried_state.clear();
    while (!settled()) {
      ++result.factorizations;
      ++result.iterations;
      const Timer timer;
      const bool stepped = ws.ipm.step(system, ws.chunks) > 0;
      result.factor_ms += timer.ms();
      copy(ws.ipm.lambda(), ws.trial, ws.chunks);
      consider(ws.trial);
      // An interior-point iterate that settles is exact only to the criterion, and along redundant
      // contacts, held by sigma alone, its impulses may then lie 1e-9 / sigma ~ 1e-3 (relative) from
      // the answer's. One Newton step in the state its predictor indicates ends the solve on that
      // piece's solution, exact to round-off, where the budget allows (kept if better, as any
      // point). (The natural map's state at the iterate missed round-off on 1 of 68 replayed islands.)
      if (best <= kSettledResidual && best == last &&
          result.factorizations < max_factorizations) {
        copy(ws.trial, ws.base, ws.chunks);
        ws.piece_state = ws.ipm.indicated();
        set_piece(s, ws.base, ws);
        if (solve_piece()) consider(ws.x);
      }
      if (settled()) break;
      const std::vector<RowState>& indicated = ws.ipm.indicated();
      if ((indicated == ws.ipm_state && indicated != ws.tried_state) || !stepped) {
        ws.tried_state = indicated;
        copy(ws.trial, ws.base, ws.chunks);
        velocities(s, ws.base, ws.du, ws.base_w, ws.chunks);
        ws.piece_state = indicated;
        newton_steps();
        if (!stepped) break;
      }
      ws.ipm_state = indicated;
    }
  }
  result.settled = best <= kSettledResidual;
  result.residual = result.settled ? best : answer;
  lambda = result.settled ? ws.best : ws.answer;
  velocities(s, lambda, ws.du, ws.w, ws.chunks);
  natural_state(s, lambda, ws.w, nullptr, ws.piece_state, ws.chunks);
  set_piece(s, lambda, ws);
  state = ws.piece_state;
  return result;
}

}  // namespace rbpart
