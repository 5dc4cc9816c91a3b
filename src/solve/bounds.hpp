#pragma once
// The bounds rule of an island's contact problem, a BLCP with bounds that depend on the impulses
// (DESIGN.md §3): a friction row's box is +-mu times the impulse of its own contact's normal row.
// Shared by the Newton solver, PGS and the residual.
#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <vector>

namespace rbpart {

// max_j |v_j| by a plain loop (Eigen's vectorised reduction trips GCC 12's -Wmaybe-uninitialized
// under -march=native with AVX-512).
inline double max_abs(const Eigen::VectorXd& v) {
  double m = 0;
  for (Eigen::Index j = 0; j < v.size(); ++j) m = std::max(m, std::abs(v[j]));
  return m;
}

// Box friction coupling (DESIGN.md §2): row j with normal_of[j] >= 0 has bounds
// +-mu[j] * max(0, lambda[normal_of[j]]). Indices are the island's own.
struct FrictionCoupling {
  const std::vector<int>* normal_of = nullptr;
  const std::vector<double>* mu = nullptr;
};

inline void set_friction_bounds(const FrictionCoupling& f, const Eigen::VectorXd& lambda, Eigen::VectorXd& lo,
                                Eigen::VectorXd& hi) {
  const std::vector<int>& normal_of = *f.normal_of;
  for (std::size_t j = 0; j < normal_of.size(); ++j) {
    if (normal_of[j] < 0) continue;
    const double bound = (*f.mu)[j] * std::max(0.0, lambda[normal_of[j]]);
    lo[j] = -bound;
    hi[j] = bound;
  }
}

}  // namespace rbpart
