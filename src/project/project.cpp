#include "project/project.hpp"

#include <algorithm>

#include "integrate/integrate.hpp"

namespace rbpart {

namespace {
constexpr int kRounds = 6;  // collide-and-project rounds at most (a round that is not deep and closed ends it)
}  // namespace

bool ProjectStage::run(const std::vector<JointFrame>& joints, bool asked, double dt, Bodies& bodies,
                       const StepParams& params, const SolverParams& solver) {
  double turn = 0;
  for (int i = 0; i < bodies.size(); ++i) turn = std::max(turn, dt * bodies.w[i].norm());
  if (params.joint_projection_iterations <= 0 || (joints.empty() && turn <= params.projection_turn && !asked))
    return false;
  update_world_inertia(bodies);
  frame_position_.resize(bodies.size());
  for (int i = 0; i < bodies.size(); ++i) frame_position_[i] = bodies.frame_position(i);
  still_.assign(bodies.size(), Vec3::Zero());
  // The contact distances are linearised at the poses the round starts from, and a large push
  // that turns a body can leave it deeper than the linear model says (a rock pushed 27 mm out of
  // a neighbour ended 12 mm in). And a round only guards the pairs it found within the contact
  // margin: closing a chain's joints can pull a link through a body it was not touching (the
  // heavy end of a falling chain, 15 mm deep). So the contacts are found again at the projected
  // poses, and projected once more while a round found a contact deeper than projection_depth, left
  // a joint open (its Gauss-Newton steps hold the contacts' Jacobians of the round's poses, and a
  // folding chain's can stall on them), or moved a body's points more than half the margin (a pair
  // it did not see may have met).
  bool open = false;  // a joint the last round left above joint_tolerance
  for (int round = 0; round < kRounds; ++round) {
    collider_.collide(frame_position_, bodies.q, still_, still_, dt, contacts_);
    const bool deep = deepest_penetration(contacts_) > params.projection_depth;
    if (round > 0 && !deep && !open) break;
    before_x_ = bodies.x;
    before_q_ = bodies.q;
    open = projection_.project(joints, contacts_, bodies, params, solver) > params.joint_tolerance;
    double moved = 0;
    for (int i = 0; i < bodies.size(); ++i)
      moved = std::max(moved, (bodies.x[i] - before_x_[i]).norm() +
                                  collider_.reach(i) * bodies.q[i].angularDistance(before_q_[i]));
    if (!deep && !open && 2 * moved <= params.contact_margin) break;
    for (int i = 0; i < bodies.size(); ++i) frame_position_[i] = bodies.frame_position(i);
  }
  return true;
}

}  // namespace rbpart
