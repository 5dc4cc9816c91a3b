#include "solve/tied_factor.hpp"

#include <algorithm>

#include "core/validate.hpp"
#include "solve/solve_check.hpp"

namespace rbpart {

void TiedBodySpaceLu::assign(const IslandSystem& system) {
  s_ = &system;
  analysed_ = false;
  mass_.clear();
}

void TiedBodySpaceLu::build_pattern() {
  const IslandSystem& s = *s_;
  const int nb = s.bodies;
  std::vector<std::vector<int>> near(nb);
  for (int b = 0; b < nb; ++b) near[b].push_back(b);
  for (int r = 0; r < s.rows; ++r)
    if (s.body[r][1] >= 0) {
      near[s.body[r][0]].push_back(s.body[r][1]);
      near[s.body[r][1]].push_back(s.body[r][0]);
    }
  adjacency_start_.assign(1, 0);
  adjacency_.clear();
  std::vector<Eigen::Triplet<double>> pattern;
  for (int c = 0; c < nb; ++c) {
    std::vector<int>& list = near[c];
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
    adjacency_.insert(adjacency_.end(), list.begin(), list.end());
    adjacency_start_.push_back(static_cast<int>(adjacency_.size()));
    for (const int r : list)
      for (int i = 0; i < 6; ++i)
        for (int t = 0; t < 6; ++t) pattern.emplace_back(6 * r + i, 6 * c + t, 0.0);
  }
  n_.resize(6 * nb, 6 * nb);
  n_.setFromTriplets(pattern.begin(), pattern.end());
  n_.makeCompressed();
  mass_ = body_masses(s);
  h_.resize(6 * nb);
  lu_.analyzePattern(n_);
  analysed_ = true;
}

// Column 6q + t holds the six rows of every body in q's adjacency, in increasing order, so the
// block (p, q) starts at p's place in the first column and has the column length as stride.
Eigen::Map<Mat6, 0, Eigen::OuterStride<>> TiedBodySpaceLu::block(int p, int q) {
  const int* first = adjacency_.data() + adjacency_start_[q];
  const int* last = adjacency_.data() + adjacency_start_[q + 1];
  const int place = static_cast<int>(std::lower_bound(first, last, p) - first);
  const int* outer = n_.outerIndexPtr();
  return {n_.valuePtr() + outer[6 * q] + 6 * place, 6, 6, Eigen::OuterStride<>(outer[6 * q + 1] - outer[6 * q])};
}

void TiedBodySpaceLu::add_product(int j, int k, double scale) {
  const IslandSystem& s = *s_;
  for (int a = 0; a < 2; ++a) {
    const int p = s.body[j][a];
    if (p < 0) continue;
    const Vec6 left = scale * s.jac[j][a];
    for (int b = 0; b < 2; ++b) {
      const int q = s.body[k][b];
      if (q >= 0) block(p, q).noalias() += left * s.jac[k][b].transpose();
    }
  }
}

bool TiedBodySpaceLu::factor(const std::vector<char>& free, const std::vector<int>& sliding,
                             const std::vector<double>& coef) {
  const IslandSystem& s = *s_;
  if (!analysed_) build_pattern();
  kind_.assign(s.rows, kOther);
  coef_.assign(s.rows, 0.0);
  for (int j = 0; j < s.rows; ++j)
    if (free[j]) {
      if (!(s.sigma[j] > 0)) return false;
      kind_[j] = kFree;
    }
  for (std::size_t i = 0; i < sliding.size(); ++i) {
    const int t = sliding[i];
    if (kind_[s.normal_of[t]] != kFree) return false;
    kind_[t] = kSliding;
    coef_[t] = coef[i];
  }
  std::fill(n_.valuePtr(), n_.valuePtr() + n_.nonZeros(), 0.0);
  for (int b = 0; b < s.bodies; ++b) block(b, b) = mass_[b];
  for (int j = 0; j < s.rows; ++j) {
    if (kind_[j] == kFree) add_product(j, j, 1.0 / s.sigma[j]);
    else if (kind_[j] == kSliding) add_product(j, s.normal_of[j], coef_[j] / s.sigma[s.normal_of[j]]);
  }
  lu_.factorize(n_);
  return lu_.info() == Eigen::Success;
}

void TiedBodySpaceLu::solve(Eigen::VectorXd& x) {
  const IslandSystem& s = *s_;
  h_.setZero();
  for (int j = 0; j < s.rows; ++j) {
    double weight = x[j];
    if (kind_[j] == kFree) weight /= s.sigma[j];
    else if (kind_[j] == kSliding) weight += coef_[j] * x[s.normal_of[j]] / s.sigma[s.normal_of[j]];
    for (int slot = 0; slot < 2; ++slot)
      if (s.body[j][slot] >= 0) h_.segment<6>(6 * s.body[j][slot]) += s.jac[j][slot] * weight;
  }
  const Eigen::VectorXd u = lu_.solve(h_);
  RBPART_CHECK(solve_violation(n_, u, h_));
  for (int j = 0; j < s.rows; ++j)
    if (kind_[j] == kFree) x[j] = (x[j] - row_velocity(s, j, u)) / s.sigma[j];
  for (int j = 0; j < s.rows; ++j)
    if (kind_[j] == kSliding) x[j] += coef_[j] * x[s.normal_of[j]];
}

}  // namespace rbpart
