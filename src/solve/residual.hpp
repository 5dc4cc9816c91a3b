#pragma once
// The quality measure of a BLCP solution (DESIGN.md §3): the natural-map residual
//   r_j = lambda_j - clamp(lambda_j - w_j / A_jj, lo_j, hi_j),
// reported as max_j |r_j| A_jj / s with s = max(max_k |q_k|, 1e-12). r_j A_jj is in units of w (a
// velocity), so the measure is dimensionless: 1e-10 means every row's complementarity holds to
// 1e-10 of the largest free-velocity term. The scale s is per BLCP (per island).
#include <Eigen/Core>

namespace rbpart {

// From w = A lambda + q already computed.
double scaled_natural_map_residual(const Eigen::VectorXd& lambda, const Eigen::VectorXd& w,
                                   const Eigen::VectorXd& diag, const Eigen::VectorXd& lo,
                                   const Eigen::VectorXd& hi, const Eigen::VectorXd& q);

// For an explicit (A, q, lo, hi, lambda).
double natural_map_residual(const Eigen::MatrixXd& a, const Eigen::VectorXd& q, const Eigen::VectorXd& lo,
                            const Eigen::VectorXd& hi, const Eigen::VectorXd& lambda);

}  // namespace rbpart
