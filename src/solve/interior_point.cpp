#include "solve/interior_point.hpp"

#include "solve/bounds.hpp"

#include <algorithm>
#include <cmath>

namespace rbpart {

namespace {

constexpr double kToBoundary = 0.99;  // fraction of the step to the nearest bound taken

// A row with an empty interior (frictionless friction, lo = hi) is held at its bound.
bool closed(const IslandSystem& s, int j) {
  return s.normal_of[j] >= 0 ? !(s.mu[j] > 0) : !(s.lo[j] < s.hi[j]);
}

// Slacks of lambda's bounds (friction: the box of lambda's own normal); 0 where there is no bound.
void slacks(const IslandSystem& s, const Eigen::VectorXd& lambda, Eigen::VectorXd& slo, Eigen::VectorXd& shi,
            IslandChunks& chunks) {
  slo.resize(s.rows);
  shi.resize(s.rows);
  chunks.each(s.rows, [&](int j) {
    const int n = s.normal_of[j];
    if (n >= 0) {
      slo[j] = lambda[j] + s.mu[j] * lambda[n];
      shi[j] = s.mu[j] * lambda[n] - lambda[j];
      return;
    }
    slo[j] = std::isfinite(s.lo[j]) ? lambda[j] - s.lo[j] : 0.0;
    shi[j] = std::isfinite(s.hi[j]) ? s.hi[j] - lambda[j] : 0.0;
  });
}

// Changes of the slacks for a change d of the impulses (friction: with its normal's change).
void slack_steps(const IslandSystem& s, const InteriorPoint::Sides& has, const Eigen::VectorXd& d,
                 Eigen::VectorXd& dslo, Eigen::VectorXd& dshi, IslandChunks& chunks) {
  dslo.resize(s.rows);
  dshi.resize(s.rows);
  chunks.each(s.rows, [&](int j) {
    const int n = s.normal_of[j];
    const double coupled = n >= 0 ? s.mu[j] * d[n] : 0.0;
    dslo[j] = has.lo[j] ? d[j] + coupled : 0.0;
    dshi[j] = has.hi[j] ? coupled - d[j] : 0.0;
  });
}

// The largest alpha in (0, 1] that keeps every slack and multiplier that exists non-negative
// (s + alpha ds >= 0, z + alpha dz >= 0), in one pass over the rows.
double step_to_boundary(const InteriorPoint::Sides& has, const Eigen::VectorXd& slo, const Eigen::VectorXd& dslo,
                        const Eigen::VectorXd& shi, const Eigen::VectorXd& dshi, const Eigen::VectorXd& zlo,
                        const Eigen::VectorXd& dzlo, const Eigen::VectorXd& zhi, const Eigen::VectorXd& dzhi,
                        IslandChunks& chunks) {
  const auto ratio = [](double x, double dx) { return dx < 0 ? -x / dx : 1.0; };
  const double alpha = chunks.min(static_cast<int>(has.lo.size()), [&](int j) {
    double a = 1.0;
    if (has.lo[j]) a = std::min({a, ratio(slo[j], dslo[j]), ratio(zlo[j], dzlo[j])});
    if (has.hi[j]) a = std::min({a, ratio(shi[j], dshi[j]), ratio(zhi[j], dzhi[j])});
    return a;
  });
  return std::min(1.0, alpha);
}

}  // namespace

void InteriorPoint::start(const IslandSystem& s) {
  s_ = &s;
  const int n = s.rows;
  has_.closed.resize(n);
  has_.lo.resize(n);
  has_.hi.resize(n);
  bounds_ = 0;
  for (int j = 0; j < n; ++j) {
    has_.closed[j] = closed(s, j);
    has_.lo[j] = !has_.closed[j] && (s.normal_of[j] >= 0 || std::isfinite(s.lo[j]));
    has_.hi[j] = !has_.closed[j] && (s.normal_of[j] >= 0 || std::isfinite(s.hi[j]));
    bounds_ += has_.lo[j] + has_.hi[j];
  }
  const double scale = std::max(max_abs(s.q), 1e-12);
  lambda_.setZero(n);
  for (int j = 0; j < n; ++j) {
    if (has_.closed[j]) lambda_[j] = s.normal_of[j] >= 0 ? 0.0 : s.lo[j];
    if (s.normal_of[j] >= 0 || has_.closed[j]) continue;
    const double margin = 0.1 * scale / s.diag[j];
    const bool lo = std::isfinite(s.lo[j]), hi = std::isfinite(s.hi[j]);
    const double inset = lo && hi ? std::min(margin, 0.25 * (s.hi[j] - s.lo[j])) : margin;
    if (lo) lambda_[j] = std::max(lambda_[j], s.lo[j] + inset);
    if (hi) lambda_[j] = std::min(lambda_[j], s.hi[j] - inset);
  }
  for (int j = 0; j < n; ++j)
    if (s.normal_of[j] >= 0 && !has_.closed[j]) {
      const double bound = 0.5 * s.mu[j] * lambda_[s.normal_of[j]];
      lambda_[j] = std::clamp(lambda_[j], -bound, bound);
    }
  apply_a(s, lambda_, du_, w_);
  w_ += s.q;
  zlo_.setZero(n);
  zhi_.setZero(n);
  for (int j = 0; j < n; ++j) {
    if (has_.lo[j]) zlo_[j] = std::max(w_[j], 0.0) + 0.1 * scale;
    if (has_.hi[j]) zhi_[j] = std::max(-w_[j], 0.0) + 0.1 * scale;
  }
  piece_.equation.resize(n);
  indicated_.resize(n);
  for (int j = 0; j < n; ++j) {
    piece_.equation[j] = has_.closed[j] ? RowEquation::Fixed : RowEquation::Free;
    indicated_[j] = has_.closed[j] ? RowState::Lower : RowState::Free;
  }
  piece_.tie.setZero(n);
  piece_.shift.setZero(n);
  gap0_ = 0;
}

double InteriorPoint::step(LinearSystem& system, IslandChunks& chunks) {
  const IslandSystem& s = *s_;
  const int n = s.rows;
  slacks(s, lambda_, slo_, shi_, chunks);
  apply_a(s, lambda_, du_, w_, chunks);
  if (bounds_ == 0) return 0;
  // The mean complementarity gap; each row's shift and tie on the way.
  const double gap = chunks.sum(n, [&](int j) {
    w_[j] += s.q[j];
    const double dlo = has_.lo[j] ? zlo_[j] / slo_[j] : 0.0, dhi = has_.hi[j] ? zhi_[j] / shi_[j] : 0.0;
    piece_.shift[j] = dlo + dhi;
    if (s.normal_of[j] >= 0 && !has_.closed[j]) piece_.tie[j] = s.mu[j] * (dhi - dlo);
    return (has_.lo[j] ? zlo_[j] * slo_[j] : 0.0) + (has_.hi[j] ? zhi_[j] * shi_[j] : 0.0);
  }) / bounds_;
  if (gap0_ == 0) gap0_ = gap;
  // Complementarity met to round-off: further steps would only divide by vanishing slacks.
  if (!(gap > 1e-15 * gap0_)) return 0;
  if (!system.factor(piece_)) return 0;
  // Predictor (tau = 0): the right-hand side is -w (0 on closed rows, which do not move).
  r_.resize(n);
  chunks.each(n, [&](int j) { r_[j] = has_.closed[j] ? 0.0 : -w_[j]; });
  system.solve(r_, d_);
  slack_steps(s, has_, d_, dslo_, dshi_, chunks);
  chunks.each(n, [&](int j) {
    if (has_.closed[j]) return;
    const double lo = has_.lo[j] ? dslo_[j] / slo_[j] : 0.0, hi = has_.hi[j] ? dshi_[j] / shi_[j] : 0.0;
    indicated_[j] = lo < -0.5 && lo <= hi ? RowState::Lower : hi < -0.5 ? RowState::Upper : RowState::Free;
  });
  dzlo_.resize(n);
  dzhi_.resize(n);
  chunks.each(n, [&](int j) {
    dzlo_[j] = has_.lo[j] ? -zlo_[j] - zlo_[j] * dslo_[j] / slo_[j] : 0.0;
    dzhi_[j] = has_.hi[j] ? -zhi_[j] - zhi_[j] * dshi_[j] / shi_[j] : 0.0;
  });
  const double affine = step_to_boundary(has_, slo_, dslo_, shi_, dshi_, zlo_, dzlo_, zhi_, dzhi_, chunks);
  const double gap_affine = chunks.sum(n, [&](int j) {
    return (has_.lo[j] ? (zlo_[j] + affine * dzlo_[j]) * (slo_[j] + affine * dslo_[j]) : 0.0) +
           (has_.hi[j] ? (zhi_[j] + affine * dzhi_[j]) * (shi_[j] + affine * dshi_[j]) : 0.0);
  }) / bounds_;
  const double tau = std::clamp(std::pow(gap_affine / gap, 3), 0.0, 1.0) * gap;
  // Corrector: centring and the predictor's second-order term. dz_* holds the complementarity
  // target until the step is known.
  chunks.each(n, [&](int j) {
    double rhs = -(w_[j] - zlo_[j] + zhi_[j]);
    if (has_.lo[j]) {
      dzlo_[j] = tau - zlo_[j] * slo_[j] - dzlo_[j] * dslo_[j];
      rhs += dzlo_[j] / slo_[j];
    }
    if (has_.hi[j]) {
      dzhi_[j] = tau - zhi_[j] * shi_[j] - dzhi_[j] * dshi_[j];
      rhs -= dzhi_[j] / shi_[j];
    }
    r_[j] = has_.closed[j] ? 0.0 : rhs;
  });
  system.solve(r_, d_);
  slack_steps(s, has_, d_, dslo_, dshi_, chunks);
  chunks.each(n, [&](int j) {
    if (has_.lo[j]) dzlo_[j] = (dzlo_[j] - zlo_[j] * dslo_[j]) / slo_[j];
    if (has_.hi[j]) dzhi_[j] = (dzhi_[j] - zhi_[j] * dshi_[j]) / shi_[j];
  });
  // One step length for impulses and multipliers (they are coupled through w), 99 % of the way to
  // the boundary.
  const double alpha =
      std::min(1.0, kToBoundary * step_to_boundary(has_, slo_, dslo_, shi_, dshi_, zlo_, dzlo_, zhi_, dzhi_, chunks));
  if (!(alpha > 0)) return 0;
  trial_.resize(n);
  const double finite = chunks.min(n, [&](int j) {
    trial_[j] = lambda_[j] + alpha * d_[j];
    return std::isfinite(trial_[j]) ? 1.0 : 0.0;
  });
  if (!(finite > 0)) return 0;
  lambda_.swap(trial_);
  chunks.each(n, [&](int j) {
    zlo_[j] += alpha * dzlo_[j];
    zhi_[j] += alpha * dzhi_[j];
  });
  return alpha;
}

}  // namespace rbpart
