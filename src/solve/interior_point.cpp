#include "solve/interior_point.hpp"

#include <algorithm>
#include <cmath>

namespace rbpart {

namespace {

// Stop when the scaled dual residual and complementarity fall below this: far from exact, but the
// sets are then settled; pivoting supplies the exact answer.
constexpr double kTolerance = 1e-9;
// Fraction of the step to the boundary of the positive orthant.
constexpr double kStepBack = 0.99;

// Largest a in (0, 1] with v + a dv >= 0.
double max_step(double v, double dv) { return dv < 0 ? std::min(1.0, -v / dv) : 1.0; }

}  // namespace

int interior_point_sets(BlcpMatrix& A, const Eigen::VectorXd& q, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi,
                        std::vector<RowState>& state, int max_iterations, InteriorPointWorkspace& ws) {
  const int n = A.size();
  const Eigen::VectorXd& diag = A.diagonal();
  const double scale = std::max(max_abs(q), 1e-12);
  for (Eigen::VectorXd* v : {&ws.x, &ws.sl, &ws.su, &ws.zl, &ws.zu, &ws.g, &ws.dx, &ws.dzl, &ws.dzu, &ws.shift, &ws.rhs})
    v->setZero(n);
  ws.free.assign(n, 0);

  // Start inside the box, one impulse scale (s / A_jj) from finite bounds, with duals of size s.
  int bounds = 0;
  for (int j = 0; j < n; ++j) {
    const bool has_lo = std::isfinite(lo[j]), has_hi = std::isfinite(hi[j]);
    const double t = scale / diag[j];
    ws.free[j] = lo[j] < hi[j];
    if (!ws.free[j]) ws.x[j] = lo[j];
    else if (has_lo && has_hi) ws.x[j] = 0.5 * (lo[j] + hi[j]);
    else if (has_lo) ws.x[j] = lo[j] + t;
    else if (has_hi) ws.x[j] = hi[j] - t;
    if (ws.free[j] && has_lo) {
      ws.zl[j] = scale;
      ++bounds;
    }
    if (ws.free[j] && has_hi) {
      ws.zu[j] = scale;
      ++bounds;
    }
  }

  int factorizations = 0;
  for (int it = 0; it < max_iterations && bounds > 0; ++it) {
    // Residuals: r_d = A x + q - zl + zu (zero at the solution), slacks, complementarity.
    A.multiply(ws.x, ws.g);
    ws.g += q;
    double dual = 0, complementarity = 0, mu = 0;
    for (int j = 0; j < n; ++j) {
      if (!ws.free[j]) continue;
      ws.sl[j] = ws.zl[j] > 0 ? ws.x[j] - lo[j] : 1.0;
      ws.su[j] = ws.zu[j] > 0 ? hi[j] - ws.x[j] : 1.0;
      dual = std::max(dual, std::abs(ws.g[j] - ws.zl[j] + ws.zu[j]));
      const double c = ws.sl[j] * ws.zl[j] + ws.su[j] * ws.zu[j];
      complementarity = std::max(complementarity, c * diag[j]);
      mu += c;
      ws.shift[j] = ws.zl[j] / ws.sl[j] + ws.zu[j] / ws.su[j];
    }
    mu /= bounds;
    if (dual <= kTolerance * scale && complementarity <= kTolerance * scale * scale) break;
    if (!A.prepare_shifted(ws.free, ws.shift)) break;
    ++factorizations;

    // Newton step for target complementarity `target` (corrections dx_c dz_c from the predictor):
    // (A + Z/S) dx = -r_d + rc_l / s_l - rc_u / s_u, dz_l = (rc_l - z_l dx) / s_l, dz_u = (rc_u + z_u dx) / s_u.
    auto newton = [&](double target, bool corrected) {
      for (int j = 0; j < n; ++j) {
        if (!ws.free[j]) continue;
        double rc_l = -ws.sl[j] * ws.zl[j] + (ws.zl[j] > 0 ? target : 0.0);
        double rc_u = -ws.su[j] * ws.zu[j] + (ws.zu[j] > 0 ? target : 0.0);
        if (corrected) {
          rc_l -= ws.dx[j] * ws.dzl[j];
          rc_u += ws.dx[j] * ws.dzu[j];
        }
        ws.rhs[j] = -(ws.g[j] - ws.zl[j] + ws.zu[j]) + rc_l / ws.sl[j] - rc_u / ws.su[j];
        ws.dzl[j] = rc_l;  // kept until dx is known
        ws.dzu[j] = rc_u;
      }
      A.solve(ws.rhs);
      double step = 1;
      for (int j = 0; j < n; ++j) {
        if (!ws.free[j]) continue;
        ws.dx[j] = ws.rhs[j];
        ws.dzl[j] = ws.zl[j] > 0 ? (ws.dzl[j] - ws.zl[j] * ws.dx[j]) / ws.sl[j] : 0.0;
        ws.dzu[j] = ws.zu[j] > 0 ? (ws.dzu[j] + ws.zu[j] * ws.dx[j]) / ws.su[j] : 0.0;
        if (ws.zl[j] > 0) step = std::min({step, max_step(ws.sl[j], ws.dx[j]), max_step(ws.zl[j], ws.dzl[j])});
        if (ws.zu[j] > 0) step = std::min({step, max_step(ws.su[j], -ws.dx[j]), max_step(ws.zu[j], ws.dzu[j])});
      }
      return step;
    };
    // Predictor (affine scaling), Mehrotra's centring, corrector.
    const double affine = newton(0.0, false);
    double mu_affine = 0;
    for (int j = 0; j < n; ++j) {
      if (!ws.free[j]) continue;
      if (ws.zl[j] > 0) mu_affine += (ws.sl[j] + affine * ws.dx[j]) * (ws.zl[j] + affine * ws.dzl[j]);
      if (ws.zu[j] > 0) mu_affine += (ws.su[j] - affine * ws.dx[j]) * (ws.zu[j] + affine * ws.dzu[j]);
    }
    mu_affine /= bounds;
    const double centring = std::pow(mu_affine / mu, 3);
    const double step = std::min(1.0, kStepBack * newton(centring * mu, true));
    for (int j = 0; j < n; ++j) {
      if (!ws.free[j]) continue;
      ws.x[j] += step * ws.dx[j];
      ws.zl[j] += step * ws.dzl[j];
      ws.zu[j] += step * ws.dzu[j];
    }
  }

  // Sets: a row is clamped where its bound's multiplier outweighs its distance to the bound.
  for (int j = 0; j < n; ++j) {
    if (!ws.free[j]) state[j] = RowState::Lower;
    else if (ws.zl[j] > 0 && ws.zl[j] > (ws.x[j] - lo[j]) * diag[j]) state[j] = RowState::Lower;
    else if (ws.zu[j] > 0 && ws.zu[j] > (hi[j] - ws.x[j]) * diag[j]) state[j] = RowState::Upper;
    else state[j] = RowState::Free;
  }
  return factorizations;
}

}  // namespace rbpart
