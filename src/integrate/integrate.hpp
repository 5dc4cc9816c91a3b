#pragma once
// Integration stage (docs/design.md#step, #dynamics): free velocities before the solve, then impulses and
// positions after it (semi-implicit Euler, unit quaternions).
#include <rbpart/scene.hpp>

#include <vector>

#include "assembly/rows.hpp"
#include "scene/bodies.hpp"

namespace rbpart {

// World inverse inertia (R I R^T + k 1)^-1 of every body, k its geometric stiffness (zero for
// static bodies).
void update_world_inertia(Bodies& bodies);

// Geometric stiffness of joints (Andrews, Teichmann & Kry 2017, "Geometric stiffness for real-time
// constrained multibody dynamics", diagonal approximation): a joint row carrying impulse lambda at
// lever r stiffens its bodies' rotation by h |lambda| |r x e| (= h^2 |f| |r|). Treating that term
// implicitly, as an inertia added for the next step, removes the instability of light links under
// high tension (a chain holding a 100x heavier end at 60 Hz) that an explicit treatment has.
void update_geometric_stiffness(const Rows& rows, Bodies& bodies, double h);

// u* = u + h M^-1 f_ext: gravity, and the gyroscopic term taken implicitly (one Newton step in the
// body frame, as explicit gyroscopic torque is unstable for long bodies such as logs).
void apply_external_forces(Bodies& bodies, const Vec3& gravity, double h);

// u* += h M^-1 (f, tau): forces and torques applied to the bodies for this step (World::apply_force).
void apply_body_forces(Bodies& bodies, const std::vector<Vec3>& force, const std::vector<Vec3>& torque, double h);

// u+ = u* + M^-1 J^T lambda.
void apply_impulses(const Rows& rows, Bodies& bodies);

// x += h v, q += h/2 (w, 0) q, then normalise q.
void integrate_positions(Bodies& bodies, double h);

}  // namespace rbpart
