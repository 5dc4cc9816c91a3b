#include "solve/pattern_factor.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <type_traits>

#include "core/validate.hpp"

#include <Eigen/SparseCore>
#include "solve/solve_check.hpp"

namespace rbpart {

void PatternFactor::assign_dense(int n) {
  n_ = n;
  dense_ = true;
  dense_values_.setZero(n, n);
}

void PatternFactor::assign_blocks(int blocks, const std::vector<std::array<int, 2>>& pairs, int dense_max_blocks) {
  if (blocks <= dense_max_blocks) {
    assign_dense(6 * blocks);
    return;
  }
  std::vector<int> start(blocks + 1, 0), adjacent(pairs.size());
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    ++start[pairs[k][0] + 1];
    adjacent[k] = pairs[k][1];
  }
  for (int b = 0; b < blocks; ++b) start[b + 1] += start[b];
  // The same pattern keeps its analysis.
  if (!dense_ && n_ == 6 * blocks && start == adjacent_start_ && adjacent == adjacent_) return;
  n_ = 6 * blocks;
  dense_ = false;
  adjacent_start_ = std::move(start);
  adjacent_ = std::move(adjacent);
  values_.assign(36 * adjacent_.size(), 0.0);
  analysed_ = false;
}

PatternFactor::Slot PatternFactor::slot(int r, int c) const {
  if (dense_) return {n_ * 6 * c + 6 * r, n_};
  // Pairs are stored by block column, each block's 36 entries column-major.
  const int* first = adjacent_.data() + adjacent_start_[c];
  const int* last = adjacent_.data() + adjacent_start_[c + 1];
  return {36 * static_cast<int>(std::lower_bound(first, last, r) - adjacent_.data()), 6};
}

void PatternFactor::set_zero() {
  if (dense_) dense_values_.setZero();
  else std::fill(values_.begin(), values_.end(), 0.0);
}

bool PatternFactor::factor(bool symmetric) {
  lu_ = !symmetric;
  schur_ = false;
  if (dense_) {
    if (!lu_) {
      llt_.compute(dense_values_);
      if (llt_.info() == Eigen::Success) return true;
      lu_ = true;
    }
    plu_.compute(dense_values_);
    const double pivot = plu_.matrixLU().diagonal().cwiseAbs().minCoeff();
    return std::isfinite(pivot) && pivot > 0;
  }
  lu_ = true;
  analyse(-1);
  return block_lu_.factor(values_.data());
}

void PatternFactor::analyse(int interior_blocks) {
  if (analysed_ && block_lu_.interior() == interior_blocks) return;
  block_lu_.analyze(n_ / 6, adjacent_start_, adjacent_, interior_blocks);
  analysed_ = true;
}

bool PatternFactor::factor_schur(int interior, Eigen::MatrixXd& schur) {
  lu_ = true;
  schur_ = true;
  interior_ = interior;
  const int k = n_ - interior;
  schur.resize(k, k);
  if (dense_) {
    const auto a_ii = dense_values_.topLeftCorner(interior, interior);
    const auto a_ik = dense_values_.topRightCorner(interior, k);
    const auto a_ki = dense_values_.bottomLeftCorner(k, interior);
    schur = dense_values_.bottomRightCorner(k, k);
    if (interior == 0) return true;
    plu_.compute(a_ii);
    const double pivot = plu_.matrixLU().diagonal().cwiseAbs().minCoeff();
    if (!(std::isfinite(pivot) && pivot > 0)) return false;
    // Without K there is nothing to eliminate (and Eigen's triangular solves would bind a
    // reference to an empty matrix's null data).
    if (k == 0) return true;
    u_ik_ = plu_.permutationP() * a_ik;
    plu_.matrixLU().triangularView<Eigen::UnitLower>().solveInPlace(u_ik_);
    l_ki_ = a_ki;
    plu_.matrixLU().triangularView<Eigen::Upper>().solveInPlace<Eigen::OnTheRight>(l_ki_);
    schur.noalias() -= l_ki_ * u_ik_;
    return schur.allFinite();
  }
  if (interior % 6 != 0) throw std::invalid_argument("PatternFactor::factor_schur: a sparse interior of part of a block");
  analyse(interior / 6);
  return block_lu_.factor_schur(values_.data(), schur);
}

void PatternFactor::forward_interior(double* b) {
  if (!dense_) {
    block_lu_.forward_interior(b);
    return;
  }
  const int k = n_ - interior_;
  Eigen::Map<Eigen::VectorXd> b_i(b, interior_), b_k(b + interior_, k);
  if (interior_ == 0) return;
  // P b_I through a kept buffer: an in-place permutation allocates a mask.
  permuted_.resize(interior_);
  permuted_.noalias() = plu_.permutationP() * b_i;
  b_i = permuted_;
  plu_.matrixLU().triangularView<Eigen::UnitLower>().solveInPlace(b_i);
  if (k > 0) b_k.noalias() -= l_ki_ * b_i;
}

void PatternFactor::back_interior(double* b, const double* u_k) {
  if (!dense_) {
    block_lu_.back_interior(b, u_k);
    return;
  }
  const int k = n_ - interior_;
  Eigen::Map<Eigen::VectorXd> b_i(b, interior_), b_k(b + interior_, k);
  const Eigen::Map<const Eigen::VectorXd> u(u_k, k);
  if (interior_ > 0) {
    if (k > 0) b_i.noalias() -= u_ik_ * u;
    plu_.matrixLU().triangularView<Eigen::Upper>().solveInPlace(b_i);
  }
  b_k = u;
}

void PatternFactor::solve(double* x, int columns) {
  // factor_schur() factors A_II, not A.
  if (schur_) throw std::logic_error("PatternFactor::solve after factor_schur");
  // Nothing to solve; Eigen's triangular solve would bind a reference to an empty map's null data.
  if (columns == 0) return;
  if (dense_) {
    Eigen::MatrixXd rhs;
    if constexpr (kValidate) rhs = Eigen::Map<const Eigen::MatrixXd>(x, n_, columns);
    // PartialPivLU's solve, step by step: P b into a kept buffer (its own in-place permutation of
    // an aliased result allocates a mask), then the same two triangular solves.
    const auto dense_solve = [&](auto&& b) {
      if (!lu_) {
        llt_.solveInPlace(b);
        return;
      }
      permuted_.resize(b.size());
      std::decay_t<decltype(b)> p(permuted_.data(), b.rows(), b.cols());
      p.noalias() = plu_.permutationP() * b;
      plu_.matrixLU().template triangularView<Eigen::UnitLower>().solveInPlace(p);
      plu_.matrixLU().template triangularView<Eigen::Upper>().solveInPlace(p);
      b = p;
    };
    // One column through Eigen's vector kernels, as a plain dense solve: the blocked matrix kernels
    // round differently, and Newton's path can turn on round-off (resting stacks).
    if (columns == 1) dense_solve(Eigen::Map<Eigen::VectorXd>(x, n_));
    else dense_solve(Eigen::Map<Eigen::MatrixXd>(x, n_, columns));
    RBPART_CHECK(solve_violation(dense_values_, Eigen::Map<const Eigen::MatrixXd>(x, n_, columns), rhs));
    return;
  }
  Eigen::MatrixXd rhs;
  if constexpr (kValidate) rhs = Eigen::Map<const Eigen::MatrixXd>(x, n_, columns);
  for (int c = 0; c < columns; ++c) block_lu_.solve(x + static_cast<std::ptrdiff_t>(c) * n_);
  if constexpr (kValidate) {  // against the values as they are now
    std::vector<Eigen::Triplet<double>> entries;
    for (int c = 0; c < n_ / 6; ++c)
      for (int a = adjacent_start_[c]; a < adjacent_start_[c + 1]; ++a)
        for (int k = 0; k < 36; ++k) entries.emplace_back(6 * adjacent_[a] + k % 6, 6 * c + k / 6, values_[36 * a + k]);
    Eigen::SparseMatrix<double> a(n_, n_);
    a.setFromTriplets(entries.begin(), entries.end());
    RBPART_CHECK(solve_violation(a, Eigen::Map<const Eigen::MatrixXd>(x, n_, columns), rhs));
  }
}

}  // namespace rbpart
