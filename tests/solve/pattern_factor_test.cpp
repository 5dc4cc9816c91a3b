// PatternFactor (solve/pattern_factor.hpp) on random block-sparse matrices filled block by block
// through its slots, against dense algebra: solves, the Schur complement of the trailing blocks read
// off an LU that eliminates them last, and the substitutions over the leading ones, with and without
// a leading column whose partial pivoting over whole columns would take a trailing row.
#include "solve/pattern_factor.hpp"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/LU>

#include <array>
#include <random>
#include <vector>

namespace rbpart {
namespace {

// A random non-symmetric matrix of 6 x 6 blocks on a random graph of `blocks` bodies (each
// adjacent to the next, plus random pairs), diagonally strong like a body-space N.
struct BlockMatrix {
  std::vector<std::array<int, 2>> pairs;
  Eigen::MatrixXd dense;
  BlockMatrix(int blocks, std::mt19937& rng) {
    std::uniform_int_distribution<int> body(0, blocks - 1);
    std::uniform_real_distribution<double> value(-1, 1);
    for (int b = 0; b < blocks; ++b) pairs.push_back({b, b});
    for (int b = 0; b + 1 < blocks; ++b) {
      pairs.push_back({b, b + 1});
      pairs.push_back({b + 1, b});
    }
    for (int e = 0; e < blocks; ++e) {
      const int a = body(rng), b = body(rng);
      pairs.push_back({a, b});
      pairs.push_back({b, a});
    }
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    dense = Eigen::MatrixXd::Zero(6 * blocks, 6 * blocks);
    for (const auto& [r, c] : pairs)
      for (int j = 0; j < 6; ++j)
        for (int i = 0; i < 6; ++i) dense(6 * r + i, 6 * c + j) = value(rng);
    dense.diagonal().array() += 12.0;
  }
  void fill(PatternFactor& f) const {
    for (const auto& [r, c] : pairs) f.block(r, c) = dense.block<6, 6>(6 * r, 6 * c);
  }
};

void expect_schur_and_substitutions(const Eigen::MatrixXd& a, int interior_blocks, PatternFactor& f) {
  const int n = static_cast<int>(a.rows()), interior = 6 * interior_blocks, k = n - interior;
  Eigen::MatrixXd schur;
  ASSERT_TRUE(f.factor_schur(interior_blocks, schur));
  const Eigen::MatrixXd a_ii = a.topLeftCorner(interior, interior);
  const Eigen::MatrixXd expected =
      a.bottomRightCorner(k, k) - a.bottomLeftCorner(k, interior) * a_ii.lu().solve(a.topRightCorner(interior, k));
  ASSERT_EQ(schur.rows(), k);
  if (k > 0) EXPECT_LE((schur - expected).cwiseAbs().maxCoeff(), 1e-12 * expected.cwiseAbs().maxCoeff());

  std::mt19937 rng(7);
  std::uniform_real_distribution<double> value(-1, 1);
  Eigen::VectorXd b(n), u_k(k);
  for (int i = 0; i < n; ++i) b[i] = value(rng);
  for (int i = 0; i < k; ++i) u_k[i] = value(rng);
  Eigen::VectorXd x = b;
  f.forward_interior(x.data());
  const Eigen::VectorXd c = b.tail(k) - a.bottomLeftCorner(k, interior) * a_ii.lu().solve(b.head(interior));
  EXPECT_LE((x.tail(k) - c).norm(), 1e-12 * c.norm());  // (0 <= 0 without trailing unknowns)
  f.back_interior(x.data(), u_k.data());
  const Eigen::VectorXd u_i = a_ii.lu().solve(b.head(interior) - a.topRightCorner(interior, k) * u_k);
  EXPECT_LE((x.head(interior) - u_i).norm(), 1e-12 * u_i.norm());
  EXPECT_EQ(x.tail(k), u_k);
}

TEST(PatternFactor, SolvesWhatItsBlocksHold) {
  std::mt19937 rng(13);
  for (const int blocks : {1, 5, 40}) {
    const BlockMatrix m(blocks, rng);
    PatternFactor f;
    f.assign_blocks(blocks, m.pairs);
    m.fill(f);
    ASSERT_TRUE(f.factor());
    Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(6 * blocks, -1, 1), x = b;
    f.solve(x.data());
    const Eigen::VectorXd expected = m.dense.lu().solve(b);
    EXPECT_LE((x - expected).norm(), 1e-12 * expected.norm()) << blocks << " blocks";
  }
}

TEST(PatternFactor, SchurComplementAndSubstitutionsOverTheInterior) {
  std::mt19937 rng(11);
  for (const int blocks : {5, 9, 40})
    for (const int trailing : {0, 1, 3}) {
      SCOPED_TRACE(testing::Message() << blocks << " blocks, " << trailing << " trailing");
      const BlockMatrix m(blocks, rng);
      PatternFactor f;
      f.assign_blocks(blocks, m.pairs);
      m.fill(f);
      expect_schur_and_substitutions(m.dense, blocks - trailing, f);
    }
}

// A leading column whose diagonal entry is far below a trailing row's entry: partial pivoting over
// the whole column would take that row into the leading block; the block LU pivots within body 10's
// diagonal block only.
TEST(PatternFactor, SchurComplementWhenPivotingWouldCrossIntoTheInterior) {
  std::mt19937 rng(5);
  BlockMatrix m(12, rng);
  const int last = 11;  // the trailing body, adjacent to body 10
  m.dense(60, 60) = 1e-6;
  m.dense(6 * last, 60) = 50.0;
  PatternFactor f;
  f.assign_blocks(12, m.pairs);
  m.fill(f);
  expect_schur_and_substitutions(m.dense, last, f);
}

}  // namespace
}  // namespace rbpart
