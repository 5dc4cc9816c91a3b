// The position projection (project/position_projection.hpp) against the geometry it must
// respect: a light ball resting on the ground, ball-jointed to a heavy ball whose anchor sits 1 cm
// low. In the mass metric alone the light ball would take almost all of the correction, its centre
// 2.8 mm down into the ground; with its contact as a one-sided row it may only turn. And a ball
// sunk into the ground deeper than the allowed depth is pushed back to half of it, and no further.
#include <gtest/gtest.h>

#include <cmath>

#include "assembly/assemble.hpp"
#include "collision/collide.hpp"
#include "project/position_projection.hpp"
#include "scene/bodies.hpp"

namespace rbpart {
namespace {

constexpr double kRadius = 0.1;

void add_body(Bodies& b, bool is_static, double mass, const Vec3& x) {
  const double inertia = 0.4 * mass * kRadius * kRadius;
  b.is_static.push_back(is_static);
  b.mass.push_back(is_static ? 0 : mass);
  b.inv_mass.push_back(is_static ? 0 : 1 / mass);
  b.inertia_body.push_back(Mat3::Identity() * (is_static ? 0 : inertia));
  b.inv_inertia_body.push_back(Mat3::Identity() * (is_static ? 0 : 1 / inertia));
  b.inv_inertia.push_back(b.inv_inertia_body.back());
  b.com_local.push_back(Vec3::Zero());
  b.friction.push_back(0.5);
  b.x.push_back(x);
  b.q.push_back(Quat::Identity());
  b.v.push_back(Vec3::Zero());
  b.w.push_back(Vec3::Zero());
  b.geometric_stiffness.push_back(0);
}

struct Pair {
  Bodies bodies;
  std::vector<JointFrame> joints;
  std::vector<Contact> contacts;
};

// Body 0 the ground, 1 the light ball on it, 2 the heavy ball beside it; the joint's anchors are the
// balls' facing points, 1 cm apart vertically. The light ball is `distance` above the ground.
Pair make_pair(double light, double heavy, double distance) {
  Pair s;
  add_body(s.bodies, true, 0, Vec3(0, 0, -1));
  add_body(s.bodies, false, light, Vec3(0, 0, kRadius + distance));
  add_body(s.bodies, false, heavy, Vec3(2 * kRadius, 0, kRadius + distance - 0.01));
  JointFrame j;
  j.body[0] = 1;
  j.body[1] = 2;
  j.anchor[0] = Vec3(kRadius, 0, 0);
  j.anchor[1] = Vec3(-kRadius, 0, 0);
  s.joints.push_back(j);
  Contact c;
  c.body_a = 1;
  c.body_b = 0;
  c.point = Vec3(0, 0, distance / 2);
  c.normal = Vec3::UnitZ();
  c.distance = distance;
  c.id = 7;
  s.contacts.push_back(c);
  return s;
}

double joint_error(const Pair& s) {
  const Vec3 a = s.bodies.x[1] + s.bodies.q[1] * s.joints[0].anchor[0];
  const Vec3 b = s.bodies.x[2] + s.bodies.q[2] * s.joints[0].anchor[1];
  return (a - b).norm();
}

double project(Pair& s, double depth = 0) {
  PositionProjection projection;
  StepParams params;
  params.joint_tolerance = 1e-9;
  params.projection_depth = depth;
  return projection.project(s.joints, s.contacts, s.bodies, params, SolverParams{});
}

// Tolerance on the contact: the rows' regularisation floor (1e-6 of A_jj) lets it yield by about
// that fraction of the correction.
constexpr double kYield = 1e-7;

TEST(PositionProjection, ClosesTheJointWithoutPushingAContactDeeper) {
  Pair s = make_pair(1, 100, 0);
  EXPECT_LE(project(s), 1e-9);
  EXPECT_LE(joint_error(s), 1e-9);
  EXPECT_GE(s.bodies.x[1].z(), kRadius - kYield);
}

TEST(PositionProjection, AGapMayCloseButNotPastContact) {
  // 1 mm of gap, less than the 2.8 mm the free projection would drop the light ball: it closes.
  Pair s = make_pair(1, 100, 0.001);
  EXPECT_LE(project(s), 1e-9);
  EXPECT_LE(joint_error(s), 1e-9);
  EXPECT_NEAR(s.bodies.x[1].z(), kRadius, kYield);
}

TEST(PositionProjection, WithoutContactTheMassMetricDecides) {
  // 5 cm of gap: the contact stays open, and one impulse delta moves the balls' centres by
  // delta / m in opposite directions (x += M^-1 J^T delta): the drop and the rise are as 100 : 1,
  // and the light ball's centre drops delta = 1 cm / (1/m + r^2/I + 1/M + r^2/I_M) = 2.83 mm, to
  // first order (the balls turn by 0.07 rad, which bends the Gauss-Newton path by about 1 %).
  Pair s = make_pair(1, 100, 0.05);
  const double light_z = s.bodies.x[1].z(), heavy_z = s.bodies.x[2].z();
  EXPECT_LE(project(s), 1e-9);
  const double light_drop = light_z - s.bodies.x[1].z(), heavy_rise = s.bodies.x[2].z() - heavy_z;
  EXPECT_NEAR(light_drop, 100 * heavy_rise, 1e-8);
  EXPECT_NEAR(light_drop, 0.01 / 3.535, 3e-5);
}

TEST(PositionProjection, AContactDeeperThanTheDepthIsPushedBackToHalfOfIt) {
  // The light ball alone, 2 cm into the ground: it rises to 2.5 mm deep, not out of the ground
  // (half the depth of 5 mm: room for the error of the linearised distance at the next collision).
  Pair s = make_pair(1, 100, -0.02);
  s.joints.clear();
  project(s, 0.005);
  EXPECT_NEAR(s.bodies.x[1].z(), kRadius - 0.0025, kYield);
  // Within the depth nothing moves.
  Pair t = make_pair(1, 100, -0.004);
  t.joints.clear();
  project(t, 0.005);
  EXPECT_EQ(t.bodies.x[1].z(), kRadius - 0.004);
}

TEST(PositionProjection, ADeepPairSharesTheMoveByInverseMass) {
  // The light and the heavy ball 2 cm into each other along the line of their centres (no lever):
  // pushed back to 2.5 mm deep by x += M^-1 J^T delta, the 17.5 mm split as 1/m : 1/M.
  Pair s = make_pair(1, 3, 0.05);
  s.joints.clear();
  s.bodies.x[2] = s.bodies.x[1] + Vec3(2 * kRadius - 0.02, 0, 0);
  Contact& c = s.contacts[0];
  c.body_a = 2;
  c.body_b = 1;
  c.normal = Vec3::UnitX();
  c.point = s.bodies.x[1] + Vec3(kRadius - 0.01, 0, 0);
  c.distance = -0.02;
  const Vec3 light = s.bodies.x[1], heavy = s.bodies.x[2];
  project(s, 0.005);
  EXPECT_NEAR((s.bodies.x[2] - s.bodies.x[1]).x(), 2 * kRadius - 0.0025, kYield);
  EXPECT_NEAR(light.x() - s.bodies.x[1].x(), 0.0175 * 3 / 4, kYield);
  EXPECT_NEAR(s.bodies.x[2].x() - heavy.x(), 0.0175 * 1 / 4, kYield);
  EXPECT_NEAR((s.bodies.x[1] - light).tail<2>().norm(), 0, kYield);
}

TEST(PositionProjection, SeparatedBodiesAreLeftAlone) {
  // Apart, or touching, with no joint: nothing to project.
  for (double distance : {0.0, 0.003}) {
    Pair s = make_pair(1, 100, distance);
    s.joints.clear();
    const Pair before = s;
    project(s, 0.005);
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(s.bodies.x[k], before.bodies.x[k]);
      EXPECT_EQ(s.bodies.q[k].coeffs(), before.bodies.q[k].coeffs());
    }
  }
}

}  // namespace
}  // namespace rbpart
