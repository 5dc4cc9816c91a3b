#pragma once
// The quality measure of a BLCP solution (DESIGN.md §3): the natural-map residual
//   r_j = lambda_j - clamp(lambda_j - w_j / A_jj, lo_j, hi_j),
// reported as max_j |r_j| A_jj / s with s = max(max_k |q_k|, 1e-12). r_j A_jj is in units of w (a
// velocity), so the measure is dimensionless: 1e-10 means every row's complementarity holds to
// 1e-10 of the largest free-velocity term. The scale s is per BLCP (per island).
#include <Eigen/Core>

#include <vector>

#include "assembly/rows.hpp"

namespace rbpart {

struct IslandSystem;

// From w = A lambda + q already computed.
double scaled_natural_map_residual(const Eigen::VectorXd& lambda, const Eigen::VectorXd& w,
                                   const Eigen::VectorXd& diag, const Eigen::VectorXd& lo,
                                   const Eigen::VectorXd& hi, const Eigen::VectorXd& q);

// An island's answer written back into `rows`: impulses, index sets, and the bounds in s.lo/s.hi
// (those the answer is exact for), as every solver of DESIGN.md §3 leaves them.
void store_island_solution(const IslandSystem& s, const Eigen::VectorXd& lambda, const std::vector<RowState>& state,
                           Rows& rows);

// The residual every solver reports for an island's answer: friction bounds of its own final normal
// impulses (written into s.lo/s.hi), w = A lambda + q afresh from J and M^-1 J^T. du, w: scratch.
double island_residual(IslandSystem& s, const Eigen::VectorXd& lambda, Eigen::VectorXd& du, Eigen::VectorXd& w);

}  // namespace rbpart
