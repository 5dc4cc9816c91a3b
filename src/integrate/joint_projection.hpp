#pragma once
// Post-stabilisation of joints (Cline & Pai 2003, "Post-stabilization for rigid body simulation
// with contact and constraints"). Velocity-level joint rows hold the joints only to first order:
// a link spinning at w drifts ~ w^2 r h^2 / 2 per step (centimetres for a whipping chain at 60 Hz),
// more than Baumgarte feedback can take back. After the positions are integrated, the rigid joints'
// position errors phi are projected out with the same mass metric: (J M^-1 J^T) delta = -phi,
// x += M^-1 J^T delta, a Gauss-Newton step on the joint manifold. Velocities are not touched, so
// the projection adds no energy. Contacts keep their Baumgarte/slop treatment.
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <vector>

#include "assembly/assemble.hpp"
#include "assembly/rows.hpp"
#include "scene/bodies.hpp"

namespace rbpart {

class JointProjection {
 public:
  // Projects until every rigid joint row's error is below `tolerance` (m or rad) or after
  // `max_iterations` Gauss-Newton steps. Returns the largest remaining error.
  double project(const std::vector<JointFrame>& joints, Bodies& bodies, double sigma_floor, double tolerance,
                 int max_iterations);

 private:
  Rows rows_;
  std::vector<int> rigid_;                      // rigid rows of rows_
  std::vector<int> body_row_offset_, body_rows_;  // CSR: rigid rows touching each body (row*2+slot)
  std::vector<Eigen::Triplet<double>> triplets_;
  Eigen::SparseMatrix<double> a_;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt_;
  Eigen::VectorXd phi_, delta_;
};

}  // namespace rbpart
