#pragma once
// The monolithic backend of the Newton solver's linear algebra (linear_system.hpp, DESIGN.md §3):
// the whole island factored in body space. With u = M^-1 J^T x, a Free row gives
// x_j = (g_j - J_j u) / s_j (s_j = sigma_j + shift_j), a Fixed row x_j = g_j and a Tied row
// x_t = g_t + c_t x_n, so M u = J^T x becomes
//   N u = h,  N = M + sum_Free J_j^T J_j / s_j + sum_Tied (c_t / s_n) J_t^T J_n,
//   h = sum_Free J_j^T g_j / s_j + sum_Fixed J_j^T g_j + sum_Tied J_t^T (g_t + c_t g_n / s_n).
// N has 6 x 6 blocks on the body graph: 6 unknowns per body against ~20 rows per body on a pile.
// A tie adds a non-symmetric 12 x 12 term on its contact's two bodies, whose blocks N already has,
// so the pattern depends on the island alone and is analysed once per island. Factorisation:
// symmetric (no Tied row) by Cholesky, otherwise by LU with partial pivoting; dense (Eigen) for
// islands of at most dense_max_bodies bodies, else sparse (CHOLMOD, KLU).
#include "solve/island_system.hpp"
#include "solve/linear_system.hpp"
#include "solve/sparse_factor.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include <array>
#include <vector>

namespace rbpart {

class MonolithicSystem final : public LinearSystem {
 public:
  // Keeps a reference to `system`, which must outlive the solves, and builds N's pattern.
  void assign(const IslandSystem& system, int dense_max_bodies);
  bool factor(const Piece& piece) override;
  void solve(const Eigen::VectorXd& g, Eigen::VectorXd& x) override;

 private:
  using Block = Eigen::Map<Mat6, 0, Eigen::OuterStride<>>;
  // Offset in the value array of N's block (row body r, column body c); the column stride of
  // column body c.
  int offset(int r, int c) const;
  int stride(int c) const { return dense_ ? 6 * s_->bodies : 6 * (adjacent_start_[c + 1] - adjacent_start_[c]); }
  Block block(int r, int c) { return Block(values() + offset(r, c), 6, 6, Eigen::OuterStride<>(stride(c))); }
  double* values() { return dense_ ? dense_n_.data() : values_.data(); }

  const IslandSystem* s_ = nullptr;
  const Piece* piece_ = nullptr;
  bool dense_ = false, tied_ = false;
  std::vector<Mat6> mass_;
  Eigen::VectorXd inv_s_;  // 1 / (sigma_j + shift_j) on Free rows
  // Sparse: the bodies adjacent to each body (itself included, increasing), and N in compressed
  // columns with every block stored (both triangles): column 6c + k holds the six rows of each
  // adjacent body's block, in order.
  std::vector<int> adjacent_start_, adjacent_, colptr_, rowind_;
  std::vector<double> values_;
  bool cholmod_ready_ = false, klu_ready_ = false;
  CholmodFactor cholmod_;
  KluFactor klu_;
  // Dense.
  Eigen::MatrixXd dense_n_;
  Eigen::LLT<Eigen::MatrixXd> llt_;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_;
  Eigen::VectorXd h_;
};

}  // namespace rbpart
