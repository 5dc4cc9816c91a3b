#pragma once
// One sub-system of the substructured solver (DESIGN.md §7): the BLCP matrix of a part's own rows,
// A_pp = J_p M_p^-1 J_p^T + Sigma_p, in body space. Parts hold at most n_max bodies but, on piles,
// about twenty rows per body, so the body-space matrix N = M_p + J_F^T Sigma_F^-1 J_F (6 per body)
// is several times smaller than A_FF and its dense Cholesky factor tens of times cheaper;
// A_FF^-1 follows by Woodbury (as sparse_matrix.hpp's BodySpaceBlcpMatrix, dense here), exact after
// the refinement against multiply() that the BLCP core does and solve_exact() repeats.
//
// The same factor gives the part's effective inverse mass on its interface bodies, which the Schur
// complement needs: W_p = M^-1 - M^-1 J_F^T A_FF^-1 J_F M^-1 = N^-1 (Woodbury once more:
// M^-1 J^T (Sigma + J M^-1 J^T)^-1 J M^-1 = M^-1 - (M + J^T Sigma^-1 J)^-1). With the interface
// bodies ordered last, N = L L^T gives N^-1 on them as (L22 L22^T)^-1, from the trailing 6k x 6k
// block of L alone.
#include "solve/blcp.hpp"
#include "solve/island_system.hpp"

#include <Eigen/Cholesky>

#include <array>
#include <optional>
#include <vector>

namespace rbpart {

class PartMatrix final : public BlcpMatrix {
 public:
  // The part's rows (island rows whose bodies all lie in the part) and bodies; `body_index` maps an
  // island body to its position in `bodies`. `mass` is M per island body. `s` must outlive this.
  void assign(const IslandSystem& s, const std::vector<int>& rows, const std::vector<int>& bodies,
              const std::vector<int>& body_index, const std::vector<Mat6>& mass);

  int size() const override { return static_cast<int>(diag_.size()); }
  const Eigen::VectorXd& diagonal() const override { return diag_; }
  // Exact: y = Sigma x + J (M^-1 J^T x) row by row.
  void multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) override;
  // Woodbury on the factor of N (loses the digits 1/sigma costs; refine against multiply()).
  void solve(Eigen::VectorXd& x) override;
  // x_F <- A_FF^-1 x_F refined to round-off; x_C <- 0.
  void solve_exact(Eigen::VectorXd& x);
  // W = N^-1 on the last k bodies (6k x 6k), for the free set of the last factorisation.
  void effective_inverse_mass(int k, Eigen::MatrixXd& w);

  // The free set of the last successful factorisation.
  const std::vector<char>& free() const { return free_; }
  int factorizations() const { return factorizations_; }
  double factor_ms() const { return factor_ms_; }

 protected:
  bool factor(const std::vector<char>& free) override;

 private:
  const IslandSystem* s_ = nullptr;
  const int* rows_ = nullptr;                 // part row -> island row
  std::vector<std::array<int, 2>> body_;      // part body per slot, -1 = none
  std::vector<Mat6> mass_;                    // per part body
  Eigen::VectorXd diag_, sigma_;
  Eigen::MatrixXd n_;                         // N, factored in place (lower triangle)
  std::optional<Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>>> llt_;
  std::vector<char> free_;
  Eigen::VectorXd g_, du_, b_, r_, d_;        // scratch
  Eigen::MatrixXd x_;                         // scratch of effective_inverse_mass
  int factorizations_ = 0;
  double factor_ms_ = 0;
};

}  // namespace rbpart
