#pragma once
// Sparse backends of the BLCP core, both on CHOLMOD's supernodal Cholesky (DESIGN.md §3). The
// symbolic analysis (fill-reducing ordering, supernodes) is done once per BLCP when the matrix is
// assigned; a pivoting iteration refactors numerically only. Each object owns its CHOLMOD workspace
// (cholmod_common is not thread safe), so islands solve in parallel with one object each.
//
// - SparseBlcpMatrix factors A itself. Clamped rows/columns are replaced by their diagonal entry
//   alone, so the pattern never changes: the factor is that of blockdiag(A_FF, diag(A_CC)).
// - BodySpaceBlcpMatrix never forms A = J M^-1 J^T + Sigma. It factors the body-space matrix
//   N = M + J_F^T Sigma_F^-1 J_F (6 x 6 blocks on the body graph, the constraint rows of the KKT
//   form [M, J_F^T; J_F, -Sigma_F] eliminated first) and solves A_FF x = b by the Woodbury identity
//   x = Sigma_F^-1 (b - J_F N^-1 J_F^T Sigma_F^-1 b). Far sparser on piles (a body with nine
//   contacts couples 27 rows densely in A but is one 6 x 6 block in N), but with sigma only a small
//   floor the subtraction cancels digits, so the BLCP core's iterative refinement against the
//   exact A (multiply()) is what makes its answers exact. Needs sigma_j > 0 on every row.
#include "solve/blcp.hpp"
#include "solve/island_system.hpp"
#include "solve/sparse_factor.hpp"
#include "solve/tied_factor.hpp"

#include <memory>

namespace rbpart {


class SparseBlcpMatrix final : public BlcpMatrix {
 public:
  SparseBlcpMatrix();
  ~SparseBlcpMatrix() override;
  // Takes A and runs the symbolic analysis of its pattern.
  void assign(LowerCsc a);
  const LowerCsc& matrix() const { return a_; }

  int size() const override { return a_.n; }
  const Eigen::VectorXd& diagonal() const override { return diag_; }
  void multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) override;
  void solve(Eigen::VectorXd& x) override;

 protected:
  bool factor(const std::vector<char>& free) override;

 private:
  LowerCsc a_;
  std::vector<double> masked_;  // values of blockdiag(A_FF, diag(A_CC)) on A's pattern
  Eigen::VectorXd diag_, rhs_;
  const std::vector<char>* free_ = nullptr;
  std::unique_ptr<CholmodFactor> chol_;
};

class BodySpaceBlcpMatrix final : public BlcpMatrix {
 public:
  BodySpaceBlcpMatrix();
  ~BodySpaceBlcpMatrix() override;
  // Keeps a reference to `system` (which must outlive the solve) and analyses the pattern of N.
  void assign(const IslandSystem& system);

  int size() const override { return s_->rows; }
  const Eigen::VectorXd& diagonal() const override { return s_->diag; }
  void multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) override;
  void solve(Eigen::VectorXd& x) override;
  bool factor_tied(const std::vector<char>& free, const std::vector<int>& sliding,
                   const std::vector<double>& coef) override {
    return tied_.factor(free, sliding, coef);
  }
  void solve_tied(Eigen::VectorXd& x) override { tied_.solve(x); }

 protected:
  bool factor(const std::vector<char>& free) override;
  bool factor_shifted(const std::vector<char>& free, const Eigen::VectorXd& shift) override;

 private:
  // Factors N with the rows' compliances sigma_ (sigma, plus the shift if any).
  bool factor_n(const std::vector<char>& free);

  const IslandSystem* s_ = nullptr;
  Eigen::VectorXd sigma_;
  // N's lower triangle, compressed by column, as dense 6 x 6 blocks: the block of bodies (r, c),
  // r >= c, starts at values_[base] with column stride stride_[c] (scalar columns of one body have
  // the same row pattern). Diagonal blocks are stored in full; CHOLMOD ignores their upper part.
  LowerCsc n_;
  std::vector<int> stride_;               // per body (column)
  std::vector<int> diag_base_;            // per body
  std::vector<int> off_base_;             // per row with two bodies: its off-diagonal block, else -1
  std::vector<Mat6> mass_;  // M per body
  const std::vector<char>* free_ = nullptr;
  Eigen::VectorXd g_, du_;
  std::unique_ptr<CholmodFactor> chol_;
  TiedBodySpaceLu tied_;
};

}  // namespace rbpart
