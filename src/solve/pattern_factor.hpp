#pragma once
// A square matrix of 6 x 6 blocks on a fixed pattern, factored as often as its values change: the
// body-space system N of an island or of a part, and the substructured backend's interface Schur
// complement S (DESIGN.md §3, §7), one block per pair of adjacent bodies. It holds the blocks' values
// and factors them by the block sparse LU of block_lu.hpp, symmetric or not, whose analysis (order
// and fill) it keeps while the pattern holds.
#include "solve/block_lu.hpp"

#include <Eigen/Core>

#include <array>
#include <vector>

namespace rbpart {

class PatternFactor {
 public:
  // The blocks (r, c) of `pairs` (sorted, unique, both triangles, every diagonal block among them)
  // on `blocks` block rows and columns, all zero. The same pattern keeps its analysis (and values).
  void assign_blocks(int blocks, const std::vector<std::array<int, 2>>& pairs);
  // Block (r, c); it must be one of the pairs. Its slot (first entry in values(), column-major with
  // stride 6) holds while the pattern does: callers that assemble often look their blocks up once.
  using Block = Eigen::Map<Eigen::Matrix<double, 6, 6>>;
  using Slot = int;
  Slot slot(int r, int c) const;
  Block block(Slot at) { return Block(values_.data() + at); }
  Block block(int r, int c) { return block(slot(r, c)); }

  int size() const { return 6 * blocks_; }
  void set_zero();
  // Zeroes block column c, the blocks (., c).
  void set_zero_column(int c);

  // Factors the current values; false if numerically singular. With `chunks`, the block LU's large
  // columns run their updates in them (BlockLU::factor).
  bool factor(IslandChunks* chunks = nullptr);
  // Factors the current values A = [A_II A_IK; A_KI A_KK] (I its first `interior` blocks, K the
  // others) by LU with I's pivots taken among I's rows and K eliminated last, and sets `schur` to
  // K's Schur complement A_KK - A_KI A_II^-1 A_IK: the LU's trailing block (BlockLU::factor_schur).
  // False if numerically singular. Then forward_interior() and back_interior() solve with A_II;
  // solve() throws until the next factor(). With `chunks`, as factor().
  bool factor_schur(int interior, Eigen::MatrixXd& schur, IslandChunks* chunks = nullptr);
  // After factor_schur(): b (size() entries) <- [y_I; b_K - A_KI A_II^-1 b_I] (y_I: the forward
  // substitution's, for back_interior()).
  void forward_interior(double* b) { lu_.forward_interior(b); }
  // After forward_interior(b): b <- [A_II^-1 (b_I - A_IK u_K); u_K] for the given u_K.
  void back_interior(double* b, const double* u_k) { lu_.back_interior(b, u_k); }
  // x <- A^-1 x for `columns` vectors of size() entries stored one after another.
  void solve(double* x, int columns = 1);

 private:
  // Analyses the pattern for factor() (-1) or factor_schur() (its interior), unless it already is.
  void analyse(int interior);

  int blocks_ = 0;
  std::vector<int> adjacent_start_, adjacent_;  // the block rows of each block column (increasing)
  std::vector<double> values_;                  // 36 per pair, by block column
  bool analysed_ = false;                       // lu_ holds this pattern's analysis (for its interior)
  BlockLU lu_;
};

}  // namespace rbpart
