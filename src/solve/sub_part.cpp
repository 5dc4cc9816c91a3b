#include "solve/sub_part.hpp"

#include "core/timer.hpp"

#include <limits>

namespace rbpart {

namespace {

// Refinement of solve_exact(): at most this many corrections, stopping at the round-off of the
// residual (kRoundoff eps times the largest term of a row, as the BLCP core's tolerance floor) or
// when a correction no longer halves it.
constexpr int kMaxRefinements = 4;
constexpr double kRoundoff = 64;

}  // namespace

void PartMatrix::assign(const IslandSystem& s, const std::vector<int>& rows, const std::vector<int>& bodies,
                        const std::vector<int>& body_index, const std::vector<Mat6>& mass) {
  s_ = &s;
  rows_ = rows.data();
  const int n = static_cast<int>(rows.size()), nb = static_cast<int>(bodies.size());
  body_.resize(n);
  diag_.resize(n);
  sigma_.resize(n);
  for (int j = 0; j < n; ++j) {
    const int r = rows[j];
    for (int slot = 0; slot < 2; ++slot) body_[j][slot] = s.body[r][slot] < 0 ? -1 : body_index[s.body[r][slot]];
    diag_[j] = s.diag[r];
    sigma_[j] = s.sigma[r];
  }
  mass_.resize(nb);
  for (int b = 0; b < nb; ++b) mass_[b] = mass[bodies[b]];
  n_.resize(6 * nb, 6 * nb);
  g_.resize(6 * nb);
  du_.resize(6 * nb);
  b_.resize(n);
  r_.resize(n);
  d_.resize(n);
  free_.assign(n, 0);
  llt_.reset();
  factorizations_ = 0;
  factor_ms_ = 0;
  invalidate();
}

void PartMatrix::multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) {
  const IslandSystem& s = *s_;
  const int n = size();
  du_.setZero();
  for (int j = 0; j < n; ++j)
    for (int slot = 0; slot < 2; ++slot)
      if (body_[j][slot] >= 0) du_.segment<6>(6 * body_[j][slot]) += s.mjac[rows_[j]][slot] * x[j];
  y.resize(n);
  for (int j = 0; j < n; ++j) {
    double v = sigma_[j] * x[j];
    for (int slot = 0; slot < 2; ++slot)
      if (body_[j][slot] >= 0) v += s.jac[rows_[j]][slot].dot(du_.segment<6>(6 * body_[j][slot]));
    y[j] = v;
  }
}

bool PartMatrix::factor(const std::vector<char>& free) {
  using Block = Eigen::Block<Eigen::MatrixXd, 6, 6>;
  const Timer timer;
  const IslandSystem& s = *s_;
  const int nb = static_cast<int>(mass_.size());
  // N = M + sum over free rows of J_j^T J_j / sigma_j; Cholesky reads the lower triangle only.
  n_.setZero();
  for (int b = 0; b < nb; ++b) n_.block<6, 6>(6 * b, 6 * b) = mass_[b];
  for (int j = 0; j < size(); ++j) {
    if (!free[j]) continue;
    const int a = body_[j][0], c = body_[j][1];
    const std::array<Vec6, 2>& jac = s.jac[rows_[j]];
    const Vec6 scaled = jac[0] / sigma_[j];
    Block(n_, 6 * a, 6 * a).noalias() += scaled * jac[0].transpose();
    if (c < 0) continue;
    Block(n_, 6 * c, 6 * c).noalias() += (jac[1] / sigma_[j]) * jac[1].transpose();
    if (a > c) Block(n_, 6 * a, 6 * c).noalias() += scaled * jac[1].transpose();
    else Block(n_, 6 * c, 6 * a).noalias() += (jac[1] / sigma_[j]) * jac[0].transpose();
  }
  free_ = free;
  Eigen::Ref<Eigen::MatrixXd> whole(n_);
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
  llt_.emplace(whole);
#pragma GCC diagnostic pop
  ++factorizations_;
  factor_ms_ += timer.ms();
  return llt_->info() == Eigen::Success;
}

void PartMatrix::solve(Eigen::VectorXd& x) {
  // Woodbury: g = N^-1 J_F^T Sigma_F^-1 x_F, x_F = Sigma_F^-1 (x_F - J_F g).
  const IslandSystem& s = *s_;
  const int n = size();
  g_.setZero();
  for (int j = 0; j < n; ++j) {
    if (!free_[j]) continue;
    const double xs = x[j] / sigma_[j];
    for (int slot = 0; slot < 2; ++slot)
      if (body_[j][slot] >= 0) g_.segment<6>(6 * body_[j][slot]) += s.jac[rows_[j]][slot] * xs;
  }
  llt_->solveInPlace(g_);
  for (int j = 0; j < n; ++j) {
    if (!free_[j]) continue;
    double v = x[j];
    for (int slot = 0; slot < 2; ++slot)
      if (body_[j][slot] >= 0) v -= s.jac[rows_[j]][slot].dot(g_.segment<6>(6 * body_[j][slot]));
    x[j] = v / sigma_[j];
  }
}

void PartMatrix::solve_exact(Eigen::VectorXd& x) {
  const int n = size();
  for (int j = 0; j < n; ++j) b_[j] = free_[j] ? x[j] : 0.0;
  x = b_;
  solve(x);
  const double b_max = max_abs(b_);
  double previous = std::numeric_limits<double>::infinity();
  for (int k = 0;; ++k) {
    multiply(x, r_);
    double residual = 0, terms = b_max;
    for (int j = 0; j < n; ++j) {
      r_[j] = free_[j] ? r_[j] - b_[j] : 0.0;
      residual = std::max(residual, std::abs(r_[j]));
      terms = std::max(terms, diag_[j] * std::abs(x[j]));
    }
    if (!(residual < 0.5 * previous)) {
      if (k > 0 && !(residual <= previous)) x += d_;  // the last correction made it worse: undo it
      return;
    }
    if (k == kMaxRefinements || residual <= kRoundoff * std::numeric_limits<double>::epsilon() * terms) return;
    previous = residual;
    d_ = r_;
    solve(d_);
    x -= d_;
  }
}

void PartMatrix::effective_inverse_mass(int k, Eigen::MatrixXd& w) {
  const int m = 6 * k;
  // X = L22^-1, W = X^T X = (L22 L22^T)^-1.
  x_.setIdentity(m, m);
  n_.bottomRightCorner(m, m).triangularView<Eigen::Lower>().solveInPlace(x_);
  w.resize(m, m);
  w.noalias() = x_.transpose() * x_.triangularView<Eigen::Lower>();
}

}  // namespace rbpart
