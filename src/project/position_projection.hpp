#pragma once
// Post-stabilisation of positions (Cline & Pai 2003, "Post-stabilization for rigid body simulation
// with contact and constraints"). The velocity-level rows hold joints and contacts only to first
// order in the step, and two second-order errors are large at 60 Hz:
// - a link spinning at w drifts from its joint by ~ w^2 r h^2 / 2 per step (centimetres for a
//   whipping chain), more than Baumgarte feedback can take back;
// - a rock turning at 30 rad/s (0.5 rad per step) brings a corner that its contacts at the start of
//   the step did not guard about 1 cm into a neighbour.
// So after the positions are integrated, when the project stage asks for it (project.hpp), the
// contacts are found again at the new poses and both errors are projected out with the mass
// metric, x += M^-1 J^T delta (velocities untouched: no kinetic energy is added). Each
// Gauss-Newton step is a BLCP solved by the direct solver (solve_newton_direct):
//   rigid joint rows: (A delta + phi)_j = 0,                       delta_j free
//   contact rows:     w_c = (A delta)_c + s(d_c) >= 0,              delta_c >= 0, w_c delta_c = 0
//                     s(d) = max(d, 0) + min(0, d + depth_c)
// with A = J M^-1 J^T (+ the rigid-row floor), phi the joint errors at the current poses and d_c
// the contact's distance plus the projection's moves so far along it; depth_c is `depth`, or half of
// it for a contact found deeper than `depth`. Every rigid joint closes; a contact deeper than
// `depth` is pushed back to half of it; and no contact is pushed deeper than it is, nor
// a gap closed past touching. So a joint is never closed by pushing a body into another: a
// projection that saw only the joints pulled a chain draped over a bar 86 mm into it, as the light
// links took the whole correction of a heavy end. Penetration below `depth` is left to the
// contacts' Baumgarte/slop treatment.
#include <rbpart/params.hpp>

#include <vector>

#include "assembly/assemble.hpp"
#include "assembly/rows.hpp"
#include "collision/collide.hpp"
#include "graph/islands.hpp"
#include "scene/bodies.hpp"
#include "solve/island_cache.hpp"

namespace rbpart {

class PositionProjection {
 public:
  // Projects the poses in `bodies` until every rigid joint row's error is below
  // params.joint_tolerance (m or rad) and no contact is deeper than params.projection_depth, or
  // after params.joint_projection_iterations steps. `contacts` are the contacts at these poses.
  // Returns the largest remaining joint error.
  double project(const std::vector<JointFrame>& joints, const std::vector<Contact>& contacts, Bodies& bodies,
                 const StepParams& params, const SolverParams& solver);

 private:
  Rows joint_rows_, contact_rows_, rows_;
  Islands islands_;
  // The solves' analyses and buffers: a projection's steps share their rows' pattern.
  DirectCache island_cache_;
  std::vector<Vec6> move_, du_;  // per body: the projection so far, and this step's move
};

}  // namespace rbpart
