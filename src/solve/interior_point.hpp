#pragma once
// Interior-point restart of the BLCP core (DESIGN.md §3). The BLCP with SPD A is the optimality
// condition of the box QP  min 1/2 l^T A l + q^T l,  lo <= l <= hi.  Block principal pivoting solves it
// exactly but, without the M-matrix structure that frictionless contact has, can stall with many
// infeasible rows (box friction does this: hundreds of rows across a sliding pile), where Murty's
// single swaps would need as many factorisations as there are wrong rows. A primal-dual
// interior-point method (Mehrotra's predictor-corrector) converges in a few tens of factorisations
// whatever the number of wrong rows; its iterate predicts the index sets, from which pivoting then
// finishes exactly. It uses the same BlcpMatrix: each step factors A_FF + diag(z/s) (F = rows
// with lo < hi), so every backend, including the body-space one, serves it unchanged.
#include "solve/blcp.hpp"

namespace rbpart {

// Predicts the index sets of the BLCP (A, q, lo, hi) into `state`. Returns the number of
// factorisations used (at most max_iterations).
int interior_point_sets(BlcpMatrix& A, const Eigen::VectorXd& q, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi,
                        std::vector<RowState>& state, int max_iterations, InteriorPointWorkspace& ws);

}  // namespace rbpart
