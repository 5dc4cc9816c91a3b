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
// The factor is computed owner by owner: position m owns its diagonal block, column m's L blocks and
// row m's U blocks, and before eliminating m it applies to them every update from the positions
// below it (left-looking), each block's updates in the order of the positions they come from: the
// same operations in the same order as eliminating column by column and updating every pair of
// blocks below (right-looking), so the same factor bit for bit. An owner's updates read only
// blocks of its descendants in the elimination tree, and write only its own, so the subtrees of
// the tree are independent: given IslandChunks (the substructured backend's interface system),
// factor() runs the tree as tasks, each after its children, and an owner with at least
// kChunkedUpdates updates splits them into kMaxChunks ranges of target blocks. Its critical path is
// the tree's longest chain of tasks (each large owner at its slowest chunk), the time on
// unlimited cores.
//
// With an `interior`, the first `interior` blocks are eliminated first (in AMD order among themselves)
// and the others after them in their own order, every two of them adjacent; factor_schur() stops
// after the interior, and the trailing blocks then hold their Schur complement.
#include <Eigen/Core>
#include <Eigen/LU>
#include <Eigen/StdVector>

#include <array>
#include <atomic>
#include <memory>
#include <vector>

namespace rbpart {

class IslandChunks;

class BlockLU {
 public:
  using Mat6 = Eigen::Matrix<double, 6, 6>;
  // The least work (block products, ~50 ns each) handed out as its own task or chunk: a subtree of
  // less runs as one task, and an owner with fewer updates is not split; smaller ones would be
  // shorter than handing them out on real cores, so the critical path would promise what no machine
  // reaches.
  static constexpr int kChunkedUpdates = 256;

  // `blocks` block rows and columns; block column c holds the block rows adjacent[start[c]] ..
  // adjacent[start[c + 1] - 1] (increasing, both triangles, the diagonal among them). interior < 0:
  // every block in AMD order, for factor(); else the split of factor_schur().
  void analyze(int blocks, const std::vector<int>& start, const std::vector<int>& adjacent, int interior);
  // The interior analyze() was called with (-1: none).
  int interior() const { return interior_; }

  // Factors the values (pattern entry k's block at values + 36 k, column-major, in analyze()'s order
  // of the entries); false if a diagonal block is numerically singular. Needs interior() < 0. With
  // `chunks`, the elimination tree runs as tasks (in parallel when it has at least
  // IslandChunks::kMinParallelItems updates) and its time is added to the chunks' tallies: the
  // tasks' work, the tree's critical path and the wall time.
  bool factor(const double* values, IslandChunks* chunks = nullptr);
  // Eliminates the interior only; schur (6 x 6 blocks on the trailing blocks, in their order) <- A_KK -
  // A_KI A_II^-1 A_IK. False if a diagonal block of the elimination is numerically singular. Needs
  // interior() >= 0.
  bool factor_schur(const double* values, Eigen::MatrixXd& schur);
  // x <- A^-1 x after factor().
  void solve(double* x);
  // After factor_schur(): b <- [y_I; b_K - A_KI A_II^-1 b_I] (y_I: the forward substitution's, for
  // back_interior()).
  void forward_interior(double* b);
  // After forward_interior(b): b <- [A_II^-1 (b_I - A_IK u_K); u_K] for the given u_K.
  void back_interior(double* b, const double* u_k);

 private:
  using Vec6 = Eigen::Matrix<double, 6, 1>;
  // Copies the values into the factor's blocks (fill zero).
  void load(const double* values);
  // Eliminates the first `count` blocks in order (the trailing ones of a split only take their
  // updates).
  bool eliminate(int count);
  // Eliminates every block as the elimination tree's tasks, timed into `chunks`.
  bool eliminate_tree(IslandChunks& chunks);
  // Applies owner m's updates (targets [first, last) of its own), each target's in order.
  void update(int first, int last) {
    for (int t = first; t < last; ++t)
      for (int g = gather_start_[t]; g < gather_start_[t + 1]; ++g)
        block_[target_slot_[t]].noalias() -= block_[gather_[g][0]] * block_[gather_[g][1]];
  }
  // Factors position m's diagonal block and divides its column's L blocks by it; false if singular.
  bool pivot(int m);
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
  // Per owner m: its target blocks [target_start_[m], target_start_[m + 1]); per target: its slot and
  // its updates [gather_start_[t], gather_start_[t + 1]), {L block, U block}: target -= L U.
  std::vector<int> target_start_, target_slot_, gather_start_;
  std::vector<std::array<int, 2>> gather_;
  // The elimination tree as tasks (factor() with chunks), in increasing order of their top position:
  // task k eliminates positions task_node_[task_start_[k] ..] in increasing order (one large owner,
  // or a subtree of less than kChunkedUpdates work), after its children; its parent task is
  // task_parent_[k] (-1: a root).
  std::vector<int> task_start_, task_node_, task_parent_, task_children_;
  long long tree_updates_ = 0;  // every owner's updates
  std::unique_ptr<std::atomic<int>[]> pending_;  // per task: children not finished
  std::vector<double> task_work_, task_path_, task_longest_;  // per task: ms of work, of its own path, of its chain
  std::vector<Mat6, Eigen::aligned_allocator<Mat6>> block_;  // the factor
  std::vector<Eigen::PartialPivLU<Mat6>, Eigen::aligned_allocator<Eigen::PartialPivLU<Mat6>>> diagonal_;  // D_j's LU
  std::vector<Vec6, Eigen::aligned_allocator<Vec6>> z_;                // the substitutions' vector
};

}  // namespace rbpart
