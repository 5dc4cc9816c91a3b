#pragma once
// Validate builds' check of a solve with a factorisation kept from earlier (core/validate.hpp):
// the block LU's order and fill kept per pattern, any factor kept across solves. The solution must satisfy the matrix the
// factor stands for now, to a normwise backward error of 1e-8 (infinity norms, per column):
//   ||A x - b|| <= 1e-8 (||A|| ||x|| + ||b||).
// A backward-stable solve with a factor of A itself passes with digits to spare (about n eps,
// whatever A's condition); a factor of another matrix (stale values, a stale pattern) fails unless
// the two nearly agree. O(nonzeros) per column, as the solve itself.
#include <Eigen/Core>

#include <cstdio>
#include <string>

namespace rbpart {

inline constexpr double kSolveBackwardError = 1e-8;

// "" or the first column whose residual is too large. `a` is any Eigen matrix, dense or sparse.
template <class Matrix>
std::string solve_violation(const Matrix& a, const Eigen::Ref<const Eigen::MatrixXd>& x,
                            const Eigen::Ref<const Eigen::MatrixXd>& b) {
  if (a.rows() == 0) return "";
  const Eigen::RowVectorXd residual = (a * x - b).cwiseAbs().colwise().maxCoeff();
  const double a_norm = (a.cwiseAbs() * Eigen::VectorXd::Ones(a.cols())).maxCoeff();
  const Eigen::RowVectorXd bound =
      kSolveBackwardError * (a_norm * x.cwiseAbs().colwise().maxCoeff() + b.cwiseAbs().colwise().maxCoeff());
  for (Eigen::Index c = 0; c < residual.size(); ++c) {
    // Not-a-number passes: callers test solutions for finiteness themselves (BLCP core, Newton).
    if (!(residual[c] > bound[c])) continue;
    char words[160];
    std::snprintf(words, sizeof words, "solve of a %dx%d system, column %d: residual %.3g above the bound %.3g",
                  static_cast<int>(a.rows()), static_cast<int>(a.cols()), static_cast<int>(c), residual[c], bound[c]);
    return std::string(words) + " (a stale factorisation?)";
  }
  return "";
}

}  // namespace rbpart
