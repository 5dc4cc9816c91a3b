#pragma once
// A sparse LU of a matrix of 6 x 6 blocks on a fixed pattern, factored as often as its values change:
// the body-space systems of DESIGN.md §3 and §7, one block per pair of adjacent bodies (pattern_factor.hpp).
// The blocks are eliminated in one order found once per pattern (SuiteSparse's AMD on the block graph),
// each diagonal block by a dense LU with partial pivoting within the block, and its fill is found once
// (a symbolic factorisation along the elimination tree). Every numeric operation is then a product of
// two 6 x 6 blocks, where a scalar sparse LU (KLU, and CHOLMOD's small supernodes) spends most of its
// time indexing single entries: on an island of 559 bodies of the Large Rock Pile a factorisation
// takes 0.47 ms against KLU's 1.33 ms without a pivot search and CHOLMOD's 2.61 ms (bench/results/
// intel-xeon-2core/block-lu/).
//
// A = L U, L unit block lower triangular with L_ij = A_ij^(j) D_j^-1, U block upper triangular with
// U_jj = D_j and U_jk = A_jk^(j) (A^(j): A after eliminating the blocks before j). Pivoting stays
// within each diagonal block, so the order, and with it the fill, never changes; a diagonal block
// that is numerically singular fails the factorisation. The body-space systems are dominated by their
// diagonal blocks (M plus every row's J^T J / sigma on its body), which is what makes that safe, and
// the Newton solver refines every solution against the exact equations (newton.cpp).
//
// Eliminating block j updates every pair of blocks below it in its column and row, each update
// writing its own block, so they can run in parallel: given IslandChunks (the substructured
// backend's interface system and parts), a column with at least kChunkedUpdates updates runs them in
// its chunks, each chunk a range of the column's L blocks, divided by D_j and then multiplied into
// their rows of updates. The result is the same bit for bit.
//
// With an `interior`, the first `interior` blocks are eliminated first (in SuiteSparse's CAMD order on
// the whole graph, the others constrained last) and the others after them in their own order, every
// two of them adjacent; factor_schur() stops after the interior, and the trailing blocks then hold
// their Schur complement.
#include <Eigen/Core>
#include <Eigen/LU>
#include <Eigen/StdVector>

#include <array>
#include <vector>

namespace rbpart {

class IslandChunks;

class BlockLU {
 public:
  using Mat6 = Eigen::Matrix<double, 6, 6>;
  // Updates of one column below which it is not chunked: 16 chunks of fewer products (~50 ns each)
  // would be shorter than the barrier a column needs on real cores, so the critical path would
  // promise what no machine reaches.
  static constexpr int kChunkedUpdates = 256;

  // `blocks` block rows and columns; block column c holds the block rows adjacent[start[c]] ..
  // adjacent[start[c + 1] - 1] (increasing, both triangles, the diagonal among them). interior < 0:
  // every block in AMD order, for factor(); else the split of factor_schur() (CAMD).
  void analyze(int blocks, const std::vector<int>& start, const std::vector<int>& adjacent, int interior);
  // The interior analyze() was called with (-1: none).
  int interior() const { return interior_; }

  // Factors the values (pattern entry k's block at values + 36 k, column-major, in analyze()'s order
  // of the entries); false if a diagonal block is numerically singular. Needs interior() < 0. With
  // `chunks`, large columns' updates run in them.
  bool factor(const double* values, IslandChunks* chunks = nullptr);
  // Eliminates the interior only; schur (6 x 6 blocks on the trailing blocks, in their order) <- A_KK -
  // A_KI A_II^-1 A_IK. False if a diagonal block of the elimination is numerically singular. Needs
  // interior() >= 0.
  bool factor_schur(const double* values, Eigen::MatrixXd& schur, IslandChunks* chunks = nullptr);
  // x <- A^-1 x after factor().
  void solve(double* x);
  // After factor_schur(): b <- [y_I; b_K - A_KI A_II^-1 b_I] (y_I: the forward substitution's, for
  // back_interior()).
  void forward_interior(double* b);
  // After forward_interior(b): b <- [A_II^-1 (b_I - A_IK u_K); u_K] for the given u_K.
  void back_interior(double* b, const double* u_k);

 private:
  using Vec6 = Eigen::Matrix<double, 6, 1>;
  // Copies the values into the factor's blocks (fill zero) and eliminates the first `count` blocks.
  bool eliminate(const double* values, int count, IslandChunks* chunks);
  // target -= L U for an update {target, L block, U block}; inlined into both of eliminate()'s loops
  // (a call per 6 x 6 product cost a tenth of the factorisation).
  [[gnu::always_inline]] void apply_update(const std::array<int, 3>& t) {
    block_[t[0]].noalias() -= block_[t[1]] * block_[t[2]];
  }
  // Storage slots: position j's diagonal block is j; pattern entry e (row i > j of column j) has its
  // L block (i, j) at nb + 2e and its U block (j, i) at nb + 2e + 1.
  int lower(int e) const { return blocks_ + 2 * e; }
  int upper(int e) const { return blocks_ + 2 * e + 1; }
  // The storage slot of the block at positions (i, k), which must be in the fill.
  int slot(int i, int k) const;

  int blocks_ = 0, interior_ = -1, eliminated_ = 0;
  std::vector<int> block_of_, position_of_;   // position <-> block
  std::vector<int> fill_start_, fill_;        // per position j: the positions i > j of its column
  std::vector<int> source_;                   // per pattern entry: its storage slot
  std::vector<int> fill_only_;                // the storage slots no pattern entry lands on
  std::vector<int> update_start_;             // per position j: its updates
  std::vector<std::array<int, 3>> update_;    // {target, L block, U block}: target -= L U
  std::vector<Mat6, Eigen::aligned_allocator<Mat6>> block_;  // the factor
  std::vector<Eigen::PartialPivLU<Mat6>, Eigen::aligned_allocator<Eigen::PartialPivLU<Mat6>>> diagonal_;  // D_j's LU
  std::vector<Vec6, Eigen::aligned_allocator<Vec6>> z_;                // the substitutions' vector
};

}  // namespace rbpart
