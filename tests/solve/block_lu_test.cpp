// BlockLU (solve/block_lu.hpp) against dense algebra: solves of random block-sparse matrices (the
// pattern of a body graph, symmetric positive definite like an untied N, or not), Schur complements
// of a trailing set, diagonal blocks that need their own row pivoting, and singular diagonal blocks.
#include "solve/block_lu.hpp"

#include "solve/island_chunks.hpp"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/LU>

#include <algorithm>
#include <array>
#include <random>
#include <vector>

namespace rbpart {
namespace {

// A matrix of 6 x 6 blocks on a random graph of `blocks` bodies (a chain plus `extra` random pairs
// per body), its adjacency as BlockLU reads it and its values block by block.
struct Blocks {
  int blocks = 0;
  std::vector<int> start, adjacent;
  Eigen::MatrixXd dense;

  Blocks(int n, double extra, bool symmetric, std::mt19937& rng) : blocks(n) {
    std::vector<std::array<int, 2>> pairs;
    for (int b = 0; b < n; ++b) pairs.push_back({b, b});
    for (int b = 0; b + 1 < n; ++b) pairs.push_back({b, b + 1});
    std::uniform_int_distribution<int> body(0, n - 1);
    for (int e = 0; e < static_cast<int>(extra * n); ++e) pairs.push_back({body(rng), body(rng)});
    for (std::size_t k = 0, m = pairs.size(); k < m; ++k) pairs.push_back({pairs[k][1], pairs[k][0]});
    // By block column, then block row.
    for (auto& p : pairs) std::swap(p[0], p[1]);
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    start.assign(n + 1, 0);
    for (const auto& [c, r] : pairs) {
      ++start[c + 1];
      adjacent.push_back(r);
    }
    for (int b = 0; b < n; ++b) start[b + 1] += start[b];
    // Like a body-space N: a mass on every body plus rows' J^T J / sigma between adjacent bodies
    // (symmetric positive definite), or with a non-symmetric part of the same size (ties).
    std::normal_distribution<double> value(0, 1);
    dense = Eigen::MatrixXd::Zero(6 * n, 6 * n);
    for (const auto& [c, r] : pairs) {
      if (r > c) continue;
      // Three rows on bodies r and c (on one body if r == c).
      Eigen::Matrix<double, 3, 12> j;
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 12; ++k) j(i, k) = value(rng);
      if (r == c) j.rightCols<6>().setZero();
      Eigen::Matrix<double, 12, 12> term = 1e3 * j.transpose() * j;
      if (!symmetric) {
        Eigen::Matrix<double, 1, 12> t;
        for (int k = 0; k < 12; ++k) t(0, k) = value(rng);
        term += 0.5e3 * j.row(0).transpose() * t;
      }
      const int at[2] = {6 * r, 6 * c};
      for (int p = 0; p < 2; ++p)
        for (int q = 0; q < 2; ++q) dense.block<6, 6>(at[p], at[q]) += term.block<6, 6>(6 * p, 6 * q);
    }
    dense.diagonal().array() += 1.0;
  }

  std::vector<double> values() const {
    std::vector<double> v;
    for (int c = 0; c < blocks; ++c)
      for (int a = start[c]; a < start[c + 1]; ++a)
        for (int j = 0; j < 6; ++j)
          for (int i = 0; i < 6; ++i) v.push_back(dense(6 * adjacent[a] + i, 6 * c + j));
    return v;
  }
};

double backward_error(const Eigen::MatrixXd& a, const Eigen::VectorXd& x, const Eigen::VectorXd& b) {
  return (a * x - b).norm() / (a.norm() * x.norm());
}

TEST(BlockLU, SolvesRandomBlockSparseMatricesToRoundOff) {
  std::mt19937 rng(3);
  std::normal_distribution<double> value(0, 1);
  for (const bool symmetric : {true, false})
    for (const int n : {1, 2, 7, 40, 120})
      for (const double extra : {0.0, 1.0, 3.0}) {
        SCOPED_TRACE(testing::Message() << n << " blocks, " << extra << " extra pairs per block, "
                                        << (symmetric ? "symmetric" : "not symmetric"));
        const Blocks m(n, extra, symmetric, rng);
        BlockLU lu;
        lu.analyze(n, m.start, m.adjacent, -1);
        const std::vector<double> values = m.values();
        ASSERT_TRUE(lu.factor(values.data()));
        Eigen::VectorXd b(6 * n);
        for (int i = 0; i < 6 * n; ++i) b[i] = value(rng);
        Eigen::VectorXd x = b;
        lu.solve(x.data());
        EXPECT_LE(backward_error(m.dense, x, b), 1e-15);
        // Factored again from the same analysis, the same answer.
        ASSERT_TRUE(lu.factor(values.data()));
        Eigen::VectorXd again = b;
        lu.solve(again.data());
        EXPECT_EQ(again, x);
      }
}

// Large columns' updates run in chunks (the interface system's factorisation): the same factor bit
// for bit, in 3 and 16 chunks.
TEST(BlockLU, UpdatesInChunksGiveTheSameFactor) {
  std::mt19937 rng(5);
  std::normal_distribution<double> value(0, 1);
  for (const bool symmetric : {true, false}) {
    const Blocks m(120, 3.0, symmetric, rng);
    const std::vector<double> values = m.values();
    Eigen::VectorXd b(6 * m.blocks);
    for (int i = 0; i < b.size(); ++i) b[i] = value(rng);
    BlockLU lu;
    lu.analyze(m.blocks, m.start, m.adjacent, -1);
    ASSERT_TRUE(lu.factor(values.data()));
    Eigen::VectorXd serial = b;
    lu.solve(serial.data());
    for (const int count : {3, 16}) {
      IslandChunks chunks;
      chunks.set_count(count);
      ASSERT_TRUE(lu.factor(values.data(), &chunks));
      EXPECT_GT(chunks.work_ms, 0.0) << "no column had BlockLU::kChunkedUpdates updates";
      Eigen::VectorXd x = b;
      lu.solve(x.data());
      EXPECT_EQ(x, serial) << count << " chunks";
    }
  }
}

TEST(BlockLU, PivotsWithinADiagonalBlock) {
  std::mt19937 rng(8);
  Blocks m(12, 1.0, false, rng);
  // Block 5's diagonal block with a zero leading entry and its first two rows swapped: only row
  // pivoting inside the block factors it.
  m.dense.row(30).swap(m.dense.row(31));
  m.dense(30, 30) = 0;
  BlockLU lu;
  lu.analyze(12, m.start, m.adjacent, -1);
  const std::vector<double> values = m.values();
  ASSERT_TRUE(lu.factor(values.data()));
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(72, -1, 1);
  Eigen::VectorXd x = b;
  lu.solve(x.data());
  EXPECT_LE(backward_error(m.dense, x, b), 1e-15);
}

TEST(BlockLU, FailsOnASingularDiagonalBlock) {
  std::mt19937 rng(9);
  Blocks m(10, 1.0, true, rng);
  // Body 0 is eliminated at some point: with its diagonal block's last column zero, and no other block
  // in that column, the matrix is singular and so is that diagonal block whenever it is eliminated.
  for (int r = 0; r < 60; ++r) m.dense(r, 5) = 0;
  BlockLU lu;
  lu.analyze(10, m.start, m.adjacent, -1);
  const std::vector<double> values = m.values();
  EXPECT_FALSE(lu.factor(values.data()));
}

TEST(BlockLU, SchurComplementOfTheTrailingBlocksAndTheSubstitutionsOverTheInterior) {
  std::mt19937 rng(4);
  std::normal_distribution<double> value(0, 1);
  for (const int n : {3, 20, 60})
    for (const int trailing : {0, 1, 4})
      for (const bool symmetric : {true, false}) {
        if (trailing >= n) continue;
        SCOPED_TRACE(testing::Message() << n << " blocks, " << trailing << " trailing");
        const Blocks m(n, 1.5, symmetric, rng);
        const int interior = n - trailing, ni = 6 * interior, nk = 6 * trailing;
        BlockLU lu;
        lu.analyze(n, m.start, m.adjacent, interior);
        const std::vector<double> values = m.values();
        Eigen::MatrixXd schur;
        ASSERT_TRUE(lu.factor_schur(values.data(), schur));
        const Eigen::MatrixXd& a = m.dense;
        const Eigen::PartialPivLU<Eigen::MatrixXd> a_ii(a.topLeftCorner(ni, ni));
        ASSERT_EQ(schur.rows(), nk);
        // (Eigen's solves bind references to an empty matrix's null data: no trailing blocks, no
        // terms of theirs.)
        if (nk > 0) {
          const Eigen::MatrixXd expected =
              a.bottomRightCorner(nk, nk) - a.bottomLeftCorner(nk, ni) * a_ii.solve(a.topRightCorner(ni, nk));
          EXPECT_LE((schur - expected).cwiseAbs().maxCoeff(), 1e-12 * expected.cwiseAbs().maxCoeff());
        }

        Eigen::VectorXd b(6 * n), u_k(nk);
        for (int i = 0; i < 6 * n; ++i) b[i] = value(rng);
        for (int i = 0; i < nk; ++i) u_k[i] = value(rng);
        Eigen::VectorXd x = b;
        lu.forward_interior(x.data());
        Eigen::VectorXd rhs = b.head(ni);
        if (nk > 0) {
          const Eigen::VectorXd reduced = b.tail(nk) - a.bottomLeftCorner(nk, ni) * a_ii.solve(b.head(ni));
          EXPECT_LE((x.tail(nk) - reduced).norm(), 1e-12 * std::max(1.0, reduced.norm()));
          rhs -= a.topRightCorner(ni, nk) * u_k;
        }
        lu.back_interior(x.data(), u_k.data());
        const Eigen::VectorXd u_i = a_ii.solve(rhs);
        EXPECT_LE((x.head(ni) - u_i).norm(), 1e-12 * u_i.norm());
        EXPECT_EQ(x.tail(nk), u_k);
      }
}

// A part's elimination runs its large columns in chunks too (the substructured backend's parts): the
// same Schur complement and substitutions bit for bit, in 3 and 16 chunks.
TEST(BlockLU, SchurComplementInChunksIsTheSame) {
  std::mt19937 rng(6);
  std::normal_distribution<double> value(0, 1);
  for (const bool symmetric : {true, false}) {
    const Blocks m(120, 3.0, symmetric, rng);
    const int interior = 100;
    const std::vector<double> values = m.values();
    Eigen::VectorXd b(6 * m.blocks), u_k(6 * (m.blocks - interior));
    for (int i = 0; i < b.size(); ++i) b[i] = value(rng);
    for (int i = 0; i < u_k.size(); ++i) u_k[i] = value(rng);
    BlockLU lu;
    lu.analyze(m.blocks, m.start, m.adjacent, interior);
    Eigen::MatrixXd serial;
    ASSERT_TRUE(lu.factor_schur(values.data(), serial));
    Eigen::VectorXd serial_x = b;
    lu.forward_interior(serial_x.data());
    lu.back_interior(serial_x.data(), u_k.data());
    for (const int count : {3, 16}) {
      IslandChunks chunks;
      chunks.set_count(count);
      Eigen::MatrixXd schur;
      ASSERT_TRUE(lu.factor_schur(values.data(), schur, &chunks));
      EXPECT_GT(chunks.work_ms, 0.0) << "no column had BlockLU::kChunkedUpdates updates";
      EXPECT_EQ(schur, serial) << count << " chunks";
      Eigen::VectorXd x = b;
      lu.forward_interior(x.data());
      lu.back_interior(x.data(), u_k.data());
      EXPECT_EQ(x, serial_x) << count << " chunks";
    }
  }
}

TEST(BlockLU, RefusesCallsThatDoNotMatchItsAnalysis) {
  std::mt19937 rng(5);
  const Blocks m(6, 1.0, true, rng);
  const std::vector<double> values = m.values();
  Eigen::MatrixXd schur;
  BlockLU whole, split;
  whole.analyze(6, m.start, m.adjacent, -1);
  split.analyze(6, m.start, m.adjacent, 4);
  EXPECT_THROW(whole.factor_schur(values.data(), schur), std::logic_error);
  EXPECT_THROW(split.factor(values.data()), std::logic_error);
  Eigen::VectorXd x = Eigen::VectorXd::Ones(36);
  EXPECT_THROW(whole.solve(x.data()), std::logic_error);  // not factored yet
}

}  // namespace
}  // namespace rbpart
