// solve_violation, the validate builds' check of solves with kept factorisations: it passes a
// solve by a factor of the matrix itself and names one by a factor of another (stale) matrix; and,
// in validate builds, the block sparse factor throws from a solve after its matrix changed.
#include "solve/solve_check.hpp"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/SparseCore>

#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/validate.hpp"
#include "solve/pattern_factor.hpp"

namespace rbpart {
namespace {

// The tridiagonal matrix 4, -1 of size n, symmetric positive definite, in compressed columns.
struct Tridiagonal {
  int n;
  std::vector<int> colptr{0}, rowind;
  std::vector<double> values;
  explicit Tridiagonal(int size) : n(size) {
    for (int c = 0; c < n; ++c) {
      for (int r = std::max(c - 1, 0); r <= std::min(c + 1, n - 1); ++r) {
        rowind.push_back(r);
        values.push_back(r == c ? 4.0 : -1.0);
      }
      colptr.push_back(static_cast<int>(rowind.size()));
    }
  }
  Eigen::MatrixXd dense() const {
    Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n, n);
    for (int c = 0; c < n; ++c)
      for (int p = colptr[c]; p < colptr[c + 1]; ++p) a(rowind[p], c) = values[p];
    return a;
  }
  // The diagonal doubled: the matrix after its factorisation was made.
  void change() {
    for (int c = 0; c < n; ++c)
      for (int p = colptr[c]; p < colptr[c + 1]; ++p) values[p] *= rowind[p] == c ? 2.0 : 1.0;
  }
};

TEST(SolveCheck, PassesAFactorOfTheMatrixAndNamesAStaleOne) {
  Tridiagonal t(30);
  const Eigen::MatrixXd a = t.dense();
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(30, -1.0, 2.0);
  const Eigen::VectorXd x = a.llt().solve(b);
  EXPECT_EQ(solve_violation(a, x, b), "");
  const Eigen::SparseMatrix<double> sparse = a.sparseView();
  EXPECT_EQ(solve_violation(sparse, x, b), "");
  t.change();
  const std::string stale = solve_violation(t.dense(), x, b);
  EXPECT_NE(stale.find("solve of a 30x30 system, column 0: residual"), std::string::npos) << stale;
  // Several columns: the one that fails is named.
  Eigen::MatrixXd xs(30, 2), bs(30, 2);
  bs << b, b;
  xs << a.llt().solve(b), t.dense().llt().solve(b);
  EXPECT_NE(solve_violation(t.dense(), xs, bs).find("column 0"), std::string::npos);
  EXPECT_EQ(solve_violation(t.dense(), xs.col(1), b), "");
}

// The block LU answers correctly while its matrix is the one it factored; after the matrix changes
// without a refactorisation, a validate build's solve throws.
TEST(SolveCheck, ValidateBuildsRejectASolveWithAStaleFactor) {
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(30, -1.0, 2.0);
  const Tridiagonal matrix(30);
  const Eigen::MatrixXd a = matrix.dense();
  // Five bodies in a chain: the tridiagonal matrix's blocks.
  std::vector<std::array<int, 2>> pairs;
  for (int r = 0; r < 5; ++r)
    for (int c = std::max(0, r - 1); c <= std::min(4, r + 1); ++c) pairs.push_back({r, c});
  PatternFactor f;
  f.assign_blocks(5, pairs);
  for (const auto& [r, c] : pairs) f.block(r, c) = a.block<6, 6>(6 * r, 6 * c);
  ASSERT_TRUE(f.factor());
  Eigen::VectorXd x = b;
  f.solve(x.data());
  EXPECT_LT((x - a.llt().solve(b)).norm(), 1e-12);
  if (!kValidate) GTEST_SKIP() << "the checks are compiled in with RBPART_VALIDATE only";
  f.block(2, 2).diagonal() *= 2.0;
  x = b;
  EXPECT_THROW(f.solve(x.data()), std::logic_error);
}

}  // namespace
}  // namespace rbpart
