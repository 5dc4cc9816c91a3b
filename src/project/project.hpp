#pragma once
// Project stage (docs/pipeline.md#project): position post-stabilisation after the positions are
// integrated, when the scene has joints to close, some body turned by more than projection_turn in
// the step (its contacts' linearisation no longer guards its corners), or the caller asks: the solve
// left an island unsettled (its impulses are then only approximate: a 1000 kg rock landing on 10 kg
// ones sank 12 mm into them), or a step's collide stage found a contact deeper than
// projection_depth (step/world.cpp). It finds the contacts again at the new poses with a collider of its own (the
// collide stage's keeps its pairs' persistent state from one step to the next) and projects them
// and the joints out (position_projection.hpp).
#include <rbpart/params.hpp>
#include <rbpart/scene.hpp>

#include <vector>

#include "assembly/assemble.hpp"
#include "collision/collide.hpp"
#include "project/position_projection.hpp"
#include "scene/bodies.hpp"

namespace rbpart {

class ProjectStage {
 public:
  ProjectStage(const SceneDef& scene, double contact_margin) : collider_(scene, contact_margin) {}

  // Projects the poses in `bodies` when the rule above asks for it (`asked`: the caller's reasons);
  // returns whether it did.
  bool run(const std::vector<JointFrame>& joints, bool asked, double dt, Bodies& bodies, const StepParams& params,
           const SolverParams& solver);

 private:
  Collider collider_;
  PositionProjection projection_;
  // Per-step scratch, reused across steps.
  std::vector<Vec3> frame_position_, still_;  // still: zero velocities, the collision needs no sweep
  std::vector<Contact> contacts_;
  std::vector<Vec3> before_x_;  // poses before a round
  std::vector<Quat> before_q_;
};

}  // namespace rbpart
