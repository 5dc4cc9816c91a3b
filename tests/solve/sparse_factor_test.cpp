// The SuiteSparse factorisations (solve/sparse_factor.hpp) under concurrency: islands and parts are
// factored in parallel, each with its own CholmodFactor, and CHOLMOD calls BLAS.
#include "solve/sparse_factor.hpp"

#include <gtest/gtest.h>

#include <Eigen/Core>

#include <algorithm>
#include <random>
#include <thread>
#include <vector>

namespace rbpart {
namespace {

// The lower triangle of a dense symmetric matrix, compressed by column, as CscView reads it.
struct LowerTriangle {
  std::vector<int> colptr{0}, rowind;
  std::vector<double> values;
  explicit LowerTriangle(const Eigen::MatrixXd& a) {
    for (int c = 0; c < a.cols(); ++c) {
      for (int r = c; r < a.rows(); ++r) {
        rowind.push_back(r);
        values.push_back(a(r, c));
      }
      colptr.push_back(static_cast<int>(rowind.size()));
    }
  }
  CscView view() const {
    return {static_cast<int>(colptr.size()) - 1, colptr.data(), rowind.data(), values.data()};
  }
};

// Two threads factor and solve the same small dense matrices (one supernode) many times, switching
// between two matrices of the same pattern every 10 solves; every answer must be bit for bit the
// serial one. Without the lock of sparse_factor.cpp, Debian's single-threaded OpenBLAS failed this
// in 18 of 18 runs (2 to 2212 wrong answers of 40000).
TEST(SparseFactor, ConcurrentCholmodSolvesAreTheSerialOnes) {
  std::mt19937 rng(2024);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int n = 120;
  const Eigen::MatrixXd b = Eigen::MatrixXd::NullaryExpr(n, n, [&] { return u(rng); });
  std::vector<Eigen::MatrixXd> matrices(2, b * b.transpose() / n);
  matrices[0].diagonal().array() += 1.0;
  matrices[1].diagonal().array() += 2.0;
  const Eigen::VectorXd rhs = Eigen::VectorXd::NullaryExpr(n, [&] { return u(rng); });
  const std::vector<LowerTriangle> triangles = {LowerTriangle(matrices[0]), LowerTriangle(matrices[1])};
  // Solves with matrix k, refactoring `f` (analysed for `triangle`) when `factored` is another.
  const auto solve_with = [&](CholmodFactor& f, LowerTriangle& triangle, int& factored, int k) {
    if (factored != k) {
      std::copy(triangles[k].values.begin(), triangles[k].values.end(), triangle.values.begin());
      EXPECT_TRUE(f.factorize());
      factored = k;
    }
    Eigen::VectorXd x = rhs;
    f.solve(x.data());
    return x;
  };
  std::vector<Eigen::VectorXd> serial;
  {
    LowerTriangle triangle = triangles[0];
    CholmodFactor f;
    f.analyze(triangle.view());
    int factored = -1;
    for (int k = 0; k < 2; ++k) serial.push_back(solve_with(f, triangle, factored, k));
  }
  const int rounds = 20000;
  std::vector<int> mismatches(2, 0);
  std::vector<std::thread> threads;
  for (int t = 0; t < 2; ++t)
    threads.emplace_back([&, t] {
      LowerTriangle triangle = triangles[0];
      CholmodFactor f;
      f.analyze(triangle.view());
      int factored = -1;
      for (int i = 0; i < rounds; ++i) {
        const int k = (i / 10) % 2;
        mismatches[t] += solve_with(f, triangle, factored, k) != serial[k];
      }
    });
  for (auto& thread : threads) thread.join();
  EXPECT_EQ(mismatches[0] + mismatches[1], 0) << "of " << 2 * rounds << " concurrent solves";
}

}  // namespace
}  // namespace rbpart
