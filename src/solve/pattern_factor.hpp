#pragma once
// A square matrix of fixed pattern, factored as often as its values change: the body-space system
// N of an island or of a part, and the substructured backend's interface Schur complement S
// (DESIGN.md §3, §7). A small matrix is held dense (Eigen, column-major): a matrix its caller calls
// symmetric is factored by Cholesky, and by LU if Cholesky finds it not numerically positive
// definite; any other by LU with partial pivoting. A larger one is held as its 6 x 6 blocks and
// factored by a block sparse LU (block_lu.hpp), symmetric or not, analysed once per pattern.
#include "solve/block_lu.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/LU>

#include <array>
#include <vector>

namespace rbpart {

class PatternFactor {
 public:
  void assign_dense(int n);
  // A matrix of 6 x 6 blocks on `blocks` block rows and columns holding the blocks (r, c) of
  // `pairs` (sorted, unique, both triangles, every diagonal block among them): dense if blocks <=
  // dense_max_blocks, else sparse. The same sparse pattern keeps its analyses.
  void assign_blocks(int blocks, const std::vector<std::array<int, 2>>& pairs, int dense_max_blocks);
  // Block (r, c) of a matrix assigned by assign_blocks(); it must be one of its pairs. Its slot (first
  // entry in values() and column stride; sparse: the pair's 36 entries, column-major) holds while the
  // pattern does: callers that assemble often look their blocks up once.
  using Block = Eigen::Map<Eigen::Matrix<double, 6, 6>, 0, Eigen::OuterStride<>>;
  struct Slot {
    int start = 0, stride = 0;
  };
  Slot slot(int r, int c) const;
  Block block(Slot at) { return Block(values() + at.start, 6, 6, Eigen::OuterStride<>(at.stride)); }
  Block block(int r, int c) { return block(slot(r, c)); }

  int size() const { return n_; }
  bool dense() const { return dense_; }
  double* values() { return dense_ ? dense_values_.data() : values_.data(); }
  void set_zero();

  // Factors the current values; false if numerically singular.
  bool factor(bool symmetric);
  // Factors the current values A = [A_II A_IK; A_KI A_KK] (I its first `interior` unknowns, K the
  // others; sparse: a multiple of 6, whole blocks) by LU with I's pivots taken among I's rows and K
  // eliminated last, and sets `schur` to K's Schur complement A_KK - A_KI A_II^-1 A_IK: the LU's
  // trailing block (sparse: BlockLU::factor_schur; dense: Eigen's LU of A_II). False if numerically
  // singular. Then forward_interior() and back_interior() solve with A_II; solve() throws until the
  // next factor().
  bool factor_schur(int interior, Eigen::MatrixXd& schur);
  // After factor_schur(): b (size() entries) <- [y_I; b_K - A_KI A_II^-1 b_I] (y_I: the forward
  // substitution's, for back_interior()).
  void forward_interior(double* b);
  // After forward_interior(b): b <- [A_II^-1 (b_I - A_IK u_K); u_K] for the given u_K.
  void back_interior(double* b, const double* u_k);
  // x <- A^-1 x for `columns` vectors of size() entries stored one after another.
  void solve(double* x, int columns = 1);

 private:
  // Analyses the sparse pattern for factor() (-1) or factor_schur() (its interior, in blocks), unless
  // it already is.
  void analyse(int interior_blocks);

  int n_ = 0;
  bool dense_ = true, lu_ = false;
  // assign_blocks(), sparse: the block rows of each block column (increasing); 36 values per block.
  std::vector<int> adjacent_start_, adjacent_;
  std::vector<double> values_;
  bool analysed_ = false;  // block_lu_ holds this pattern's analysis (for its interior)
  // factor_schur(), dense: I's size; plu_ holds A_II's LU; A_KI U_II^-1 and L_II^-1 P A_IK.
  int interior_ = 0;
  Eigen::MatrixXd l_ki_, u_ik_;
  bool schur_ = false;  // the last factorisation was factor_schur()'s
  BlockLU block_lu_;
  Eigen::MatrixXd dense_values_;
  Eigen::LLT<Eigen::MatrixXd> llt_;
  Eigen::PartialPivLU<Eigen::MatrixXd> plu_;
  Eigen::VectorXd permuted_;  // P b of solve() and forward_interior(), dense
};

}  // namespace rbpart
