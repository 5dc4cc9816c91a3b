#pragma once
// A square matrix of fixed pattern, factored as often as its values change: the body-space system
// N of an island or of a part, and the substructured backend's interface Schur complement S
// (DESIGN.md §3, §7). A small matrix is held dense (Eigen, column-major); a larger one in
// compressed columns with both triangles stored, for CHOLMOD (which reads the lower one) or KLU
// (both), each analysed once per pattern (sparse_factor.hpp). A matrix its caller calls symmetric is
// factored by Cholesky, and by LU if Cholesky finds it not numerically positive definite; any other
// by LU with partial pivoting.
#include "solve/sparse_factor.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/LU>

#include <array>
#include <vector>

namespace rbpart {

class PatternFactor {
 public:
  void assign_dense(int n);
  // The pattern: colptr[n + 1], rowind sorted within each column, both triangles. The pattern of
  // the last call is kept as keep_pattern() keeps it.
  void assign_sparse(int n, std::vector<int> colptr, std::vector<int> rowind);
  // The same pattern with values of another kind (the island's next step): the CHOLMOD and KLU
  // analyses are kept, but KLU's next LU searches its pivots afresh. Within a Newton solve KLU
  // refactors with the first LU's pivots; reused from the step before they left far more steps
  // unsettled (Rock Pile, --solver direct: 462 against 91 of 500).
  void keep_pattern();

  // A matrix of 6 x 6 blocks on `blocks` block rows and columns holding the blocks (r, c) of
  // `pairs` (sorted, unique, both triangles, every diagonal block among them): dense if blocks <=
  // dense_max_blocks, else sparse. The same sparse pattern keeps its analyses (assign_sparse).
  void assign_blocks(int blocks, const std::vector<std::array<int, 2>>& pairs, int dense_max_blocks);
  // Block (r, c) of a matrix assigned by assign_blocks(); it must be one of its pairs. Its slot (first
  // entry in values() and column stride) holds while the pattern does: callers that assemble often
  // look their blocks up once.
  using Block = Eigen::Map<Eigen::Matrix<double, 6, 6>, 0, Eigen::OuterStride<>>;
  struct Slot {
    int start = 0, stride = 0;
  };
  Slot slot(int r, int c) const;
  Block block(Slot at) { return Block(values() + at.start, 6, 6, Eigen::OuterStride<>(at.stride)); }
  Block block(int r, int c) { return block(slot(r, c)); }

  int size() const { return n_; }
  bool dense() const { return dense_; }
  // Column c's entries in values() start here; a dense column holds every row, in order.
  int column_start(int c) const { return dense_ ? n_ * c : colptr_[c]; }
  const std::vector<int>& rowind() const { return rowind_; }
  double* values() { return dense_ ? dense_values_.data() : values_.data(); }
  void set_zero();

  // Factors the current values; false if numerically singular.
  bool factor(bool symmetric);
  // Factors the current values A = [A_II A_IK; A_KI A_KK] (I its first `interior` unknowns, K the
  // others) by LU with I's pivots taken among I's rows and K eliminated last, and sets `schur` to
  // K's Schur complement A_KK - A_KI A_II^-1 A_IK: the LU's trailing block. Sparse, by KLU in a
  // given order (KluFactor::trailing_schur); dense, by Eigen's LU of A_II. False if numerically
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
  int n_ = 0;
  bool dense_ = true, lu_ = false;
  std::vector<int> colptr_, rowind_;
  // assign_blocks(), sparse: the block rows of each block column (increasing).
  std::vector<int> adjacent_start_, adjacent_;
  std::vector<double> values_;
  bool cholmod_ready_ = false, klu_ready_ = false;
  int klu_interior_ = -1;  // the interior KLU was analysed for (factor_schur), -1: factor()'s analysis
  // factor_schur(), dense: I's size; plu_ holds A_II's LU; A_KI U_II^-1 and L_II^-1 P A_IK.
  int interior_ = 0;
  Eigen::MatrixXd l_ki_, u_ik_;
  bool schur_ = false;  // the last factorisation was factor_schur()'s
  CholmodFactor cholmod_;
  KluFactor klu_;
  Eigen::MatrixXd dense_values_;
  Eigen::LLT<Eigen::MatrixXd> llt_;
  Eigen::PartialPivLU<Eigen::MatrixXd> plu_;
  Eigen::VectorXd permuted_;  // P b of solve() and forward_interior(), dense
};

}  // namespace rbpart
