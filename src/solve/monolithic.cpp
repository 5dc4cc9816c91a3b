#include "solve/monolithic.hpp"

#include <algorithm>

namespace rbpart {

void MonolithicSystem::assign(const IslandSystem& s, int dense_max_bodies) {
  s_ = &s;
  dense_ = s.bodies <= dense_max_bodies;
  mass_ = body_masses(s);
  inv_s_.setZero(s.rows);
  h_.resize(6 * s.bodies);
  cholmod_ready_ = klu_ready_ = false;
  if (dense_) {
    dense_n_.resize(6 * s.bodies, 6 * s.bodies);
    return;
  }
  // The body graph, one list per body, from the rows with two bodies.
  std::vector<std::array<int, 2>> pairs;
  pairs.reserve(2 * s.rows + s.bodies);
  for (int b = 0; b < s.bodies; ++b) pairs.push_back({b, b});
  for (int j = 0; j < s.rows; ++j)
    if (s.body[j][1] >= 0) {
      pairs.push_back({s.body[j][0], s.body[j][1]});
      pairs.push_back({s.body[j][1], s.body[j][0]});
    }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  adjacent_start_.assign(s.bodies + 1, 0);
  adjacent_.resize(pairs.size());
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    ++adjacent_start_[pairs[k][0] + 1];
    adjacent_[k] = pairs[k][1];
  }
  for (int b = 0; b < s.bodies; ++b) adjacent_start_[b + 1] += adjacent_start_[b];
  colptr_.assign(1, 0);
  rowind_.clear();
  for (int c = 0; c < s.bodies; ++c)
    for (int k = 0; k < 6; ++k) {
      for (int a = adjacent_start_[c]; a < adjacent_start_[c + 1]; ++a)
        for (int i = 0; i < 6; ++i) rowind_.push_back(6 * adjacent_[a] + i);
      colptr_.push_back(static_cast<int>(rowind_.size()));
    }
  values_.assign(rowind_.size(), 0.0);
}

int MonolithicSystem::offset(int r, int c) const {
  if (dense_) return 6 * c * 6 * s_->bodies + 6 * r;
  const int* first = adjacent_.data() + adjacent_start_[c];
  const int* last = adjacent_.data() + adjacent_start_[c + 1];
  return colptr_[6 * c] + 6 * static_cast<int>(std::lower_bound(first, last, r) - first);
}

bool MonolithicSystem::factor(const Piece& piece) {
  const IslandSystem& s = *s_;
  piece_ = &piece;
  if (dense_) dense_n_.setZero();
  else std::fill(values_.begin(), values_.end(), 0.0);
  for (int b = 0; b < s.bodies; ++b) block(b, b) = mass_[b];
  tied_ = false;
  for (int j = 0; j < s.rows; ++j)
    if (piece.equation[j] == RowEquation::Free) inv_s_[j] = 1.0 / (s.sigma[j] + piece.shift[j]);
  for (int j = 0; j < s.rows; ++j) {
    // Free: + J_j^T J_j / s_j; Tied: + (c_t / s_n) J_t^T J_n (the normal's slots on the same bodies).
    int k = j;
    double scale = 0;
    if (piece.equation[j] == RowEquation::Free) {
      scale = inv_s_[j];
    } else if (piece.equation[j] == RowEquation::Tied) {
      k = s.normal_of[j];
      scale = piece.tie[j] * inv_s_[k];
      tied_ = true;
    } else {
      continue;
    }
    for (int p = 0; p < 2; ++p) {
      if (s.body[j][p] < 0) continue;
      const Vec6 jp = scale * s.jac[j][p];
      for (int q = 0; q < 2; ++q)
        if (s.body[k][q] >= 0) block(s.body[j][p], s.body[k][q]).noalias() += jp * s.jac[k][q].transpose();
    }
  }
  if (dense_) {
    if (!tied_) {
      llt_.compute(dense_n_);
      if (llt_.info() == Eigen::Success) return true;
      tied_ = true;  // not numerically positive definite: LU below
    }
    lu_.compute(dense_n_);
    const double pivot = lu_.matrixLU().diagonal().cwiseAbs().minCoeff();
    return std::isfinite(pivot) && pivot > 0;
  }
  const CscView view{6 * s.bodies, colptr_.data(), rowind_.data(), values_.data()};
  if (!tied_) {
    if (!cholmod_ready_) cholmod_.analyze(view);
    cholmod_ready_ = true;
    if (cholmod_.factorize()) return true;
    tied_ = true;
  }
  if (!klu_ready_) klu_.analyze(view);
  klu_ready_ = true;
  return klu_.factorize();
}

void MonolithicSystem::solve(const Eigen::VectorXd& g, Eigen::VectorXd& x) {
  const IslandSystem& s = *s_;
  const Piece& piece = *piece_;
  h_.setZero();
  for (int j = 0; j < s.rows; ++j) {
    double value = g[j];
    if (piece.equation[j] == RowEquation::Free) value *= inv_s_[j];
    else if (piece.equation[j] == RowEquation::Tied) value += piece.tie[j] * g[s.normal_of[j]] * inv_s_[s.normal_of[j]];
    for (int p = 0; p < 2; ++p)
      if (s.body[j][p] >= 0) h_.segment<6>(6 * s.body[j][p]) += s.jac[j][p] * value;
  }
  if (dense_) h_ = tied_ ? Eigen::VectorXd(lu_.solve(h_)) : Eigen::VectorXd(llt_.solve(h_));
  else if (tied_) klu_.solve(h_.data());
  else cholmod_.solve(h_.data());
  x.resize(s.rows);
  for (int j = 0; j < s.rows; ++j) {
    if (piece.equation[j] == RowEquation::Free) x[j] = (g[j] - row_velocity(s, j, h_)) * inv_s_[j];
    else x[j] = g[j];
  }
  for (int j = 0; j < s.rows; ++j)
    if (piece.equation[j] == RowEquation::Tied) x[j] += piece.tie[j] * x[s.normal_of[j]];
}

}  // namespace rbpart
