// The project stage (project/project.hpp): when it runs (joints, a body that turned far in the
// step, an unsettled solve) and what it leaves: a sphere sunk into the ground comes back up to
// half of projection_depth, found by the stage's own collider.
#include <gtest/gtest.h>

#include "project/project.hpp"
#include "support/bodies.hpp"

namespace rbpart {
namespace {

constexpr double kRadius = 0.1;
constexpr double kSunk = 0.03;  // m into the ground

// A static ground box whose top face is z = 0 and a 1 kg sphere kSunk into it.
struct Sunk {
  SceneDef scene;
  Bodies bodies;
  Sunk() {
    BodyDef ground;
    ground.name = "ground";
    ground.is_static = true;
    ground.shape.type = ShapeType::Box;
    ground.shape.half_extents = Vec3(2, 2, 0.5);
    ground.position = Vec3(0, 0, -0.5);
    BodyDef ball;
    ball.name = "ball";
    ball.shape.type = ShapeType::Sphere;
    ball.shape.radius = kRadius;
    ball.mass = 1;
    ball.position = Vec3(0, 0, kRadius - kSunk);
    scene.bodies = {ground, ball};
    test::add_static(bodies, ground.position);
    test::add_body(bodies, false, ball.mass, Mat3::Identity() * (0.4 * ball.mass * kRadius * kRadius), ball.position);
  }
};

constexpr double kDt = 1.0 / 60;

TEST(ProjectStage, RunsOnlyForJointsATurnOrAnUnsettledSolve) {
  Sunk s;
  const StepParams params;
  ProjectStage stage(s.scene, params.contact_margin);
  EXPECT_FALSE(stage.run({}, false, kDt, s.bodies, params, SolverParams{}));
  EXPECT_EQ(s.bodies.x[1].z(), kRadius - kSunk);  // left as it is
  // Turning by just over projection_turn in the step.
  s.bodies.w[1] = Vec3(0, 0, 1.01 * params.projection_turn / kDt);
  EXPECT_TRUE(stage.run({}, false, kDt, s.bodies, params, SolverParams{}));
  Sunk t;
  EXPECT_TRUE(stage.run({}, true, kDt, t.bodies, params, SolverParams{}));
  StepParams off = params;
  off.joint_projection_iterations = 0;
  Sunk u;
  EXPECT_FALSE(stage.run({}, true, kDt, u.bodies, off, SolverParams{}));
}

TEST(ProjectStage, ASunkSphereRisesToHalfTheProjectionDepth) {
  Sunk s;
  const StepParams params;
  ProjectStage stage(s.scene, params.contact_margin);
  ASSERT_TRUE(stage.run({}, true, kDt, s.bodies, params, SolverParams{}));
  // Pushed back to half of projection_depth, not out of the ground (the rows' 1e-6 regularisation
  // floor lets it yield by about that fraction of the correction); velocities untouched.
  EXPECT_NEAR(s.bodies.x[1].z(), kRadius - 0.5 * params.projection_depth, 1e-6 * kSunk + 1e-12);
  EXPECT_EQ(s.bodies.v[1], Vec3::Zero());
  EXPECT_EQ(s.bodies.x[1].x(), 0.0);
  EXPECT_EQ(s.bodies.x[1].y(), 0.0);
}

}  // namespace
}  // namespace rbpart
