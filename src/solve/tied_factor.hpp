#pragma once
// The tied system of the coupled friction step's jump (blcp.hpp, CoupledPath), factored directly
// in body space. Its equations, for a free set F and sliding friction rows S (t in S slides with
// its normal n(t), which is in F):
//   (A x)_j = r_j            j in F
//   x_t - c_t x_n(t) = r_t   t in S   (c_t = +-mu_t: lambda_t tied to its normal impulse)
//   x_j = r_j                every other row.
// With u = M^-1 J^T x and A = J M^-1 J^T + Sigma, a free row gives x_j = (r_j - J_j u) / sigma_j and
// a sliding row x_t = r_t + c_t x_n(t), so M u = J^T x becomes
//   N_T u = h,  N_T = M + sum_F J_j^T J_j / sigma_j + sum_S (c_t / sigma_n(t)) J_t^T J_n(t),
//   h = sum_F J_j^T r_j / sigma_j + sum_S J_t^T (r_t + c_t r_n(t) / sigma_n(t)) + sum_other J_j^T r_j.
// N_T is N of the body-space backend (sparse_matrix.hpp) plus one non-symmetric 12 x 12 term per
// sliding row on its contact's two bodies, so it keeps N's block pattern (both triangles) and is
// factored by sparse LU. The GMRES of the jump needs one factorisation of A_FF and one solve per
// iteration (~45 to 1e-12 on a resting 200-rock pile's 189 sliding rows); this is one
// factorisation and one solve per refinement round. The same digits cancel as in the body-space
// backend (sigma is a small floor), so the caller refines against A.
#include "solve/island_system.hpp"

#include <Eigen/SparseCore>
#include <Eigen/SparseLU>

#include <vector>

namespace rbpart {

class TiedBodySpaceLu {
 public:
  // Keeps a reference to `system` (which must outlive the solves); the pattern is built and
  // analysed on the first factor().
  void assign(const IslandSystem& system);
  // Factors N_T for the rows with free[j] and the sliding rows `sliding`, row sliding[i] tied to
  // its normal with coefficient coef[i]. False if a sliding row's normal is not free, a row has no
  // compliance (sigma_j = 0) or the LU fails.
  bool factor(const std::vector<char>& free, const std::vector<int>& sliding, const std::vector<double>& coef);
  // x <- E^-1 x for the system of the last successful factor().
  void solve(Eigen::VectorXd& x);

 private:
  // N_T's block of bodies (row body p, column body q).
  Eigen::Map<Mat6, 0, Eigen::OuterStride<>> block(int p, int q);
  // N_T += scale * J_j^T J_k (rows j and k on the same bodies).
  void add_product(int j, int k, double scale);
  void build_pattern();

  enum Kind : char { kOther, kFree, kSliding };
  const IslandSystem* s_ = nullptr;
  std::vector<Mat6> mass_;
  std::vector<int> adjacency_start_, adjacency_;  // per body (column): the bodies it shares a row with and itself, increasing
  Eigen::SparseMatrix<double> n_;
  Eigen::SparseLU<Eigen::SparseMatrix<double>> lu_;
  bool analysed_ = false;
  std::vector<char> kind_;
  std::vector<double> coef_;  // per row: c_t of a sliding row
  Eigen::VectorXd h_;
};

}  // namespace rbpart
