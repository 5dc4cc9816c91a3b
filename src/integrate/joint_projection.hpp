#pragma once
// Post-stabilisation of joints (Cline & Pai 2003, "Post-stabilization for rigid body simulation
// with contact and constraints"). Velocity-level joint rows hold the joints only to first order:
// a link spinning at w drifts ~ w^2 r h^2 / 2 per step (centimetres for a whipping chain at 60 Hz),
// more than Baumgarte feedback can take back. After the positions are integrated, the rigid joints'
// position errors phi are projected out with the same mass metric, x += M^-1 J^T delta, a
// Gauss-Newton step on the joint manifold. As in Cline & Pai, the contacts of jointed bodies take
// part as one-sided rows: a projection that only saw the joints pulled a chain draped over a bar
// 86 mm into it (a heavy end link barely moves, so the light links take the whole correction).
// Each step is therefore the BLCP
//   joint rows:   (A delta + phi)_j = 0                      delta_j free
//   contact rows: w_c = (A delta)_c + max(g_c, 0) >= 0,     delta_c >= 0, w_c delta_c = 0
// with A = J M^-1 J^T (+ the rigid-row floor) and g_c the contact's gap after the step, predicted
// from its distance at collision time, the new velocity and the projection's moves so far: a contact
// is never pushed deeper than it already is, nor a gap closed past zero. It is solved by the
// monolithic direct solver. Velocities are not touched, so the projection adds no energy;
// penetration itself is left to the contacts' Baumgarte/slop treatment.
#include <rbpart/params.hpp>

#include <vector>

#include "assembly/assemble.hpp"
#include "assembly/rows.hpp"
#include "collision/collide.hpp"
#include "graph/islands.hpp"
#include "scene/bodies.hpp"

namespace rbpart {

class JointProjection {
 public:
  // Projects until every rigid joint row's error is below `tolerance` (m or rad) or after
  // `max_iterations` steps. `contacts` and `step_rows` are the step's (assemble_rows' order: one
  // normal and two friction rows per contact, first), `bodies` hold the integrated poses and the
  // new velocities, h is the step. Returns the largest remaining joint error.
  double project(const std::vector<JointFrame>& joints, const std::vector<Contact>& contacts, const Rows& step_rows,
                 Bodies& bodies, double h, double sigma_floor, double tolerance, int max_iterations,
                 const SolverParams& solver);

 private:
  Rows joint_rows_, rows_;
  std::vector<char> jointed_;
  std::vector<int> contact_row_;  // step_rows' normal row of each projected contact
  std::vector<double> gap_;       // predicted gap of each projected contact (m)
  Islands islands_;
};

}  // namespace rbpart
