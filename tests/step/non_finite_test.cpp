// A step whose result is not finite is a failure, never a row of statistics (issue #26: a hinge
// axis whose squared norm underflows ran to exit 0 with an infinite residual). Scene files refuse
// such an axis; a SceneDef built in code reaches the step's own check.
#include <gtest/gtest.h>
#include <rbpart/world.hpp>

#include <stdexcept>

namespace rbpart {
namespace {

TEST(NonFiniteStep, UnderflowingHingeAxisThrowsInsteadOfReporting) {
  SceneDef scene;
  BodyDef ball;
  ball.shape.type = ShapeType::Sphere;
  ball.shape.radius = 0.1;
  ball.mass = 1;
  ball.position = Vec3(0, 0, 1);
  scene.bodies.push_back(ball);
  JointDef hinge;
  hinge.type = JointType::Hinge;
  hinge.body_a = 0;
  hinge.anchor = Vec3(0, 0, 1.5);
  hinge.axis = Vec3(1e-200, 0, 0);
  scene.joints.push_back(hinge);
  World world(scene);
  bool threw = false;
  for (int i = 0; i < 5 && !threw; ++i) {
    try {
      world.step();
    } catch (const std::runtime_error& error) {
      threw = true;
      EXPECT_NE(std::string(error.what()).find("non-finite"), std::string::npos) << error.what();
    }
  }
  EXPECT_TRUE(threw);
}

}  // namespace
}  // namespace rbpart
