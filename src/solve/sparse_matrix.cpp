#include "solve/sparse_matrix.hpp"

#include "solve/sparse_factor.hpp"

#include <algorithm>
#include <mutex>
#include <stdexcept>

namespace rbpart {

// --- SparseBlcpMatrix ------------------------------------------------------------------------------

SparseBlcpMatrix::SparseBlcpMatrix() : chol_(std::make_unique<CholmodFactor>()) {}
SparseBlcpMatrix::~SparseBlcpMatrix() = default;

void SparseBlcpMatrix::assign(LowerCsc a) {
  a_ = std::move(a);
  masked_ = a_.values;
  diag_.resize(a_.n);
  for (int c = 0; c < a_.n; ++c) diag_[c] = a_.values[a_.colptr[c]];  // rows sorted: diagonal first
  rhs_.resize(a_.n);
  chol_->analyze({a_.n, a_.colptr.data(), a_.rowind.data(), masked_.data()});
  invalidate();
}

void SparseBlcpMatrix::multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) {
  y.setZero(a_.n);
  for (int c = 0; c < a_.n; ++c) {
    double yc = 0;
    for (int p = a_.colptr[c]; p < a_.colptr[c + 1]; ++p) {
      const int r = a_.rowind[p];
      const double v = a_.values[p];
      yc += v * x[r];
      if (r != c) y[r] += v * x[c];
    }
    y[c] += yc;
  }
}

bool SparseBlcpMatrix::factor(const std::vector<char>& free) {
  for (int c = 0; c < a_.n; ++c)
    for (int p = a_.colptr[c]; p < a_.colptr[c + 1]; ++p) {
      const int r = a_.rowind[p];
      masked_[p] = (free[r] && free[c]) || r == c ? a_.values[p] : 0.0;
    }
  free_ = &free;
  return chol_->factorize();
}

void SparseBlcpMatrix::solve(Eigen::VectorXd& x) {
  // The clamped block is diagonal and decoupled: a zero right-hand side there stays zero.
  const std::vector<char>& free = *free_;
  for (int j = 0; j < a_.n; ++j) rhs_[j] = free[j] ? x[j] : 0.0;
  chol_->solve(rhs_.data());
  for (int j = 0; j < a_.n; ++j)
    if (free[j]) x[j] = rhs_[j];
}

// --- BodySpaceBlcpMatrix -----------------------------------------------------------------------------

BodySpaceBlcpMatrix::BodySpaceBlcpMatrix() : chol_(std::make_unique<CholmodFactor>()) {}
BodySpaceBlcpMatrix::~BodySpaceBlcpMatrix() = default;

void BodySpaceBlcpMatrix::assign(const IslandSystem& s) {
  s_ = &s;
  const int nb = s.bodies;
  // Body graph: the lower block (max, min) of every row with two bodies, per column body.
  std::vector<std::vector<int>> below(nb);
  for (int r = 0; r < s.rows; ++r)
    if (s.body[r][1] >= 0) {
      const int lo_b = std::min(s.body[r][0], s.body[r][1]), hi_b = std::max(s.body[r][0], s.body[r][1]);
      below[lo_b].push_back(hi_b);
    }
  for (auto& list : below) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  // Scalar CSC of N: column 6c + t holds the six rows of every block of body c (diagonal first).
  n_.n = 6 * nb;
  n_.colptr.assign(1, 0);
  n_.rowind.clear();
  stride_.resize(nb);
  diag_base_.resize(nb);
  for (int c = 0; c < nb; ++c) {
    stride_[c] = 6 * (1 + static_cast<int>(below[c].size()));
    diag_base_[c] = n_.colptr.back();
    for (int t = 0; t < 6; ++t) {
      for (int i = 0; i < 6; ++i) n_.rowind.push_back(6 * c + i);
      for (int r : below[c])
        for (int i = 0; i < 6; ++i) n_.rowind.push_back(6 * r + i);
      n_.colptr.push_back(static_cast<int>(n_.rowind.size()));
    }
  }
  n_.values.assign(n_.rowind.size(), 0.0);
  off_base_.assign(s.rows, -1);
  for (int r = 0; r < s.rows; ++r)
    if (s.body[r][1] >= 0) {
      const int c = std::min(s.body[r][0], s.body[r][1]), hi_b = std::max(s.body[r][0], s.body[r][1]);
      const int position = static_cast<int>(std::lower_bound(below[c].begin(), below[c].end(), hi_b) - below[c].begin());
      off_base_[r] = diag_base_[c] + 6 * (1 + position);
    }
  mass_ = body_masses(s);
  g_.resize(6 * nb);
  du_.resize(6 * nb);
  chol_->analyze({n_.n, n_.colptr.data(), n_.rowind.data(), n_.values.data()});
  tied_.assign(s);
  invalidate();
}

void BodySpaceBlcpMatrix::multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) { apply_a(*s_, x, du_, y); }

bool BodySpaceBlcpMatrix::factor(const std::vector<char>& free) {
  sigma_ = s_->sigma;
  return factor_n(free);
}

// A_FF + Theta_F = J_F M^-1 J_F^T + (Sigma + Theta)_F: the same form with larger compliances.
bool BodySpaceBlcpMatrix::factor_shifted(const std::vector<char>& free, const Eigen::VectorXd& shift) {
  sigma_ = s_->sigma + shift;
  return factor_n(free);
}

bool BodySpaceBlcpMatrix::factor_n(const std::vector<char>& free) {
  using Block = Eigen::Map<Eigen::Matrix<double, 6, 6>, 0, Eigen::OuterStride<>>;
  const IslandSystem& s = *s_;
  std::fill(n_.values.begin(), n_.values.end(), 0.0);
  for (int b = 0; b < s.bodies; ++b) Block(&n_.values[diag_base_[b]], 6, 6, Eigen::OuterStride<>(stride_[b])) = mass_[b];
  // N += J_j^T J_j / sigma_j for every free row j.
  for (int j = 0; j < s.rows; ++j) {
    if (!free[j]) continue;
    const double inv_sigma = 1.0 / sigma_[j];
    const int a = s.body[j][0], b = s.body[j][1];
    const Vec6 ja = inv_sigma * s.jac[j][0];
    Block(&n_.values[diag_base_[a]], 6, 6, Eigen::OuterStride<>(stride_[a])).noalias() += ja * s.jac[j][0].transpose();
    if (b < 0) continue;
    Block(&n_.values[diag_base_[b]], 6, 6, Eigen::OuterStride<>(stride_[b])).noalias() +=
        (inv_sigma * s.jac[j][1]) * s.jac[j][1].transpose();
    // Off-diagonal block (rows of the higher body, columns of the lower one).
    const bool a_low = a < b;
    const int c = a_low ? a : b;
    const Vec6& j_row = s.jac[j][a_low ? 1 : 0];
    const Vec6& j_col = s.jac[j][a_low ? 0 : 1];
    Block(&n_.values[off_base_[j]], 6, 6, Eigen::OuterStride<>(stride_[c])).noalias() +=
        (inv_sigma * j_row) * j_col.transpose();
  }
  free_ = &free;
  return chol_->factorize();
}

void BodySpaceBlcpMatrix::solve(Eigen::VectorXd& x) {
  // Woodbury: u = N^-1 J_F^T Sigma_F^-1 b, x_F = Sigma_F^-1 (b_F - J_F u).
  const IslandSystem& s = *s_;
  const std::vector<char>& free = *free_;
  g_.setZero();
  for (int j = 0; j < s.rows; ++j) {
    if (!free[j]) continue;
    const double xs = x[j] / sigma_[j];
    for (int slot = 0; slot < 2; ++slot)
      if (s.body[j][slot] >= 0) g_.segment<6>(6 * s.body[j][slot]) += s.jac[j][slot] * xs;
  }
  chol_->solve(g_.data());
  for (int j = 0; j < s.rows; ++j)
    if (free[j]) x[j] = (x[j] - row_velocity(s, j, g_)) / sigma_[j];
}

}  // namespace rbpart
