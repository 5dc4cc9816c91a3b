// Fast impacts through whole steps (docs/design.md#step, #dynamics): bodies that move further in one step
// than the contact margin, or than the thickness of what they hit, must be stopped by the speculative
// contacts (collide.hpp: the pair's margin grows with its approach speed) rather than tunnel or sink, and the
// margin must not grow for bodies at rest.
#include <gtest/gtest.h>
#include <rbpart/world.hpp>

#include <algorithm>
#include <cmath>

#include "scene/bodies.hpp"
#include "scenes/scenes.hpp"
#include "step/world_internals.hpp"

namespace rbpart {
namespace {

constexpr double kPenetration = 0.01;  // issue #3: max penetration on every scene

BodyDef static_slab(const Vec3& centre, const Vec3& half) {
  BodyDef b;
  b.name = "slab";
  b.is_static = true;
  b.shape.type = ShapeType::Box;
  b.shape.half_extents = half;
  b.position = centre;
  return b;
}

// A 0.1 m ball of 1000 kg/m^3 at `position` with `velocity` over a ground slab whose top is z = 0.
SceneDef ball_over_ground(const Vec3& position, const Vec3& velocity) {
  SceneDef scene;
  scene.bodies.push_back(static_slab(Vec3(0, 0, -0.5), Vec3(5, 5, 0.5)));
  BodyDef s;
  s.name = "ball";
  s.shape.radius = 0.1;
  s.density = 1000;
  s.position = position;
  s.velocity = velocity;
  scene.bodies.push_back(s);
  return scene;
}

// Runs `w` for `steps` steps; returns the deepest penetration any step reported.
double run(World& w, int steps) {
  double deepest = 0;
  for (int i = 0; i < steps; ++i) deepest = std::max(deepest, w.step().max_penetration);
  return deepest;
}

TEST(Impact, FastSphereStopsOnTheGround) {
  // At 20 m/s the sphere moves 0.33 m per step, more than its diameter: without a speculative
  // contact it would first be seen 0.1 m or more inside the ground.
  const double r = 0.1;
  for (double speed : {10.0, 15.0, 20.0}) {
    World w(ball_over_ground(Vec3(0.2, -0.1, 1.0), Vec3(0, 0, -speed)));
    SCOPED_TRACE(speed);
    double lowest = INFINITY, deepest = 0;
    for (int i = 0; i < 60; ++i) {
      deepest = std::max(deepest, w.step().max_penetration);
      lowest = std::min(lowest, world_bodies(w).x[1].z());
    }
    EXPECT_LE(deepest, kPenetration);
    EXPECT_GE(lowest, r - kPenetration);  // never further into the ground than 1 cm
    EXPECT_NEAR(world_bodies(w).x[1].z(), r, 1e-3);
    EXPECT_LT(world_bodies(w).v[1].norm(), 1e-3);
  }
}

TEST(Impact, FastBoxDoesNotTunnelThroughAThinPlate) {
  // A 1 cm plate, 20 m/s: the box (0.2 m tall) would pass it within one step of 0.34 m, from 7 cm
  // above it to 6 cm below (the start is chosen so).
  const double plate_top = 0.005, half = 0.1;
  for (ShapeType type : {ShapeType::Box, ShapeType::Sphere}) {
    SceneDef scene;
    scene.bodies.push_back(static_slab(Vec3(0, 0, 0), Vec3(1, 1, plate_top)));
    BodyDef b;
    b.name = "falling";
    b.shape.type = type;
    b.shape.half_extents = Vec3::Constant(half);
    b.shape.radius = half;
    b.density = 500;
    b.position = Vec3(0.1, 0.2, 0.845);
    b.velocity = Vec3(0, 0, -20);
    scene.bodies.push_back(b);
    World w(scene);
    SCOPED_TRACE(type == ShapeType::Box ? "box" : "sphere");
    EXPECT_LE(run(w, 90), kPenetration);
    EXPECT_NEAR(world_bodies(w).x[1].z(), plate_top + half, kPenetration);
    EXPECT_LT(world_bodies(w).v[1].norm(), 1e-3);
  }
}

TEST(Impact, CapsulesThrownAtEachOtherCollideInelastically) {
  // Two chain-link capsules (radius 2.5 cm) head-on at a closing speed of 30 m/s (0.5 m per step,
  // ten times their thickness), no gravity, side by side or crossed. Contacts have no restitution
  // and the contact line passes through both centres: they end at the common velocity
  // (m_a v_a + m_b v_b) / (m_a + m_b), unturned, touching, in their original order.
  const double ma = 1, mb = 3, va = 20, vb = -10, r = 0.025;
  const Quat along_y(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitX()));  // motion along x
  for (bool crossed : {false, true}) {
    SceneDef scene;
    scene.gravity = Vec3::Zero();
    for (int k = 0; k < 2; ++k) {
      BodyDef c;
      c.name = k == 0 ? "a" : "b";
      c.shape.type = ShapeType::Capsule;
      c.shape.radius = r;
      c.shape.half_length = 0.05;
      c.mass = k == 0 ? ma : mb;
      c.position = Vec3(k == 0 ? -0.6 : 0.6, 0, 0);
      c.orientation = k == 1 && crossed ? Quat::Identity() : along_y;
      c.velocity = Vec3(k == 0 ? va : vb, 0, 0);
      scene.bodies.push_back(c);
    }
    World w(scene);
    SCOPED_TRACE(crossed ? "crossed" : "side by side");
    double deepest = 0;
    for (int i = 0; i < 30; ++i) {
      deepest = std::max(deepest, w.step().max_penetration);
      ASSERT_LT(world_bodies(w).x[0].x(), world_bodies(w).x[1].x()) << "passed through at step " << i + 1;
    }
    EXPECT_LE(deepest, kPenetration);
    const double common = (ma * va + mb * vb) / (ma + mb);
    for (int k = 0; k < 2; ++k) {
      EXPECT_NEAR(world_bodies(w).v[k].x(), common, 1e-6);
      EXPECT_LT(world_bodies(w).w[k].norm(), 1e-6);
    }
    EXPECT_NEAR(world_bodies(w).x[1].x() - world_bodies(w).x[0].x(), 2 * r, kPenetration);
  }
}

TEST(Impact, TumblingRocksLandWithoutSinking) {
  // Rocks as in the Rock Pile (hulls of 20 random points on a perturbed ellipsoid, 0.15-0.35 m)
  // thrown spinning onto the ground (20 rad/s, 4 m/s down, up to 2 m/s across). A rock's faces are small triangles: landing on one and
  // turning, it brings down vertices beside it that lie within the contact margin but outside the
  // face, and each must be stopped by its own contact (collide.hpp) rather than sink until the
  // error correction pushes it out. At rest the rock lies on its lowest vertices: the lowest is
  // at the ground, up to the solver's slop.
  SceneRandom rng(5);
  double deepest = 0;
  for (int trial = 0; trial < 30; ++trial) {
    SceneDef scene;
    scene.bodies.push_back(static_slab(Vec3(0, 0, -0.5), Vec3(5, 5, 0.5)));
    BodyDef rock;
    rock.name = "rock";
    rock.shape.type = ShapeType::Convex;
    const double size = rng.uniform(0.15, 0.35);
    const Vec3 semi(0.5 * size, rng.uniform(0.6, 1.0) * 0.5 * size, rng.uniform(0.5, 0.9) * 0.5 * size);
    for (int i = 0; i < 20; ++i) rock.shape.vertices.push_back(semi.cwiseProduct(rng.unit_vector()) * rng.uniform(0.85, 1.0));
    rock.density = 2500;
    rock.position = Vec3(0, 0, 0.2 + 0.5 * size);
    rock.orientation = rng.rotation();
    rock.velocity = Vec3(2 * rng.uniform(-1, 1), 2 * rng.uniform(-1, 1), -4);
    rock.angular_velocity = 20 * rng.unit_vector();
    scene.bodies.push_back(rock);
    World w(scene);
    SCOPED_TRACE(trial);
    const double trial_deepest = run(w, 300);
    deepest = std::max(deepest, trial_deepest);
    EXPECT_LE(trial_deepest, 0.005);  // before vertex-face contacts: up to 38 mm
    const Bodies& b = world_bodies(w);
    double lowest = INFINITY;
    for (const Vec3& v : w.scene().bodies[1].shape.vertices) lowest = std::min(lowest, Vec3(b.frame_position(1) + b.q[1] * v).z());
    EXPECT_NEAR(lowest, 0, w.step_params().slop + 1e-4);
    EXPECT_LT(b.v[1].norm() + b.w[1].norm(), 1e-2);
  }
  EXPECT_GT(deepest, 0);  // the rocks did land
}

TEST(Impact, CapsuleDroppedCrosswiseOnACapsuleRestsOnIt) {
  // A chain link (capsule, radius 2.5 cm) dropped crosswise onto a static one from 0.5 m: the two
  // axes end one radius sum apart, the falling link's centre 2 r above the static one's, and it
  // must never have gone through (it reaches 3.1 m/s, 5 cm per step, its own thickness).
  const double r = 0.025, half = 0.05;
  SceneDef scene;
  for (int k = 0; k < 2; ++k) {
    BodyDef c;
    c.name = k == 0 ? "bar" : "link";
    c.is_static = k == 0;
    c.shape.type = ShapeType::Capsule;
    c.shape.radius = r;
    c.shape.half_length = k == 0 ? 1.0 : half;
    c.mass = 1;
    c.position = Vec3(0, 0, k == 0 ? 1.0 : 1.5);
    c.orientation = Quat(Eigen::AngleAxisd(M_PI / 2, k == 0 ? Vec3::UnitY() : Vec3::UnitX()));
    scene.bodies.push_back(c);
  }
  World w(scene);
  double deepest = 0, lowest = INFINITY;
  for (int i = 0; i < 90; ++i) {
    deepest = std::max(deepest, w.step().max_penetration);
    lowest = std::min(lowest, world_bodies(w).x[1].z());
  }
  EXPECT_LE(deepest, kPenetration);
  EXPECT_GE(lowest, 1.0 + 2 * r - kPenetration);
  EXPECT_NEAR(world_bodies(w).x[1].z(), 1.0 + 2 * r, w.step_params().slop + 1e-4);
  EXPECT_LT(world_bodies(w).v[1].norm(), 1e-3);
}

TEST(Impact, RestingStackKeepsItsContacts) {
  // At rest the margin is the contact margin: a ten-cube stack has exactly 4 corner contacts under
  // each cube (12 rows each), every step, and no pair of cubes two apart (0.5 m gap) ever appears.
  World w(make_builtin_scene("box_stack", {}));
  for (int i = 0; i < 120; ++i) {
    const StepStats& s = w.step();
    ASSERT_EQ(s.contacts, 40) << "step " << i + 1;
    ASSERT_EQ(s.rows, 120) << "step " << i + 1;
  }
}

TEST(Impact, AStepStartingDeepProjectsBeforeItSolves) {
  // A ball at rest 3 cm into the ground: a settled step does not run the project stage after it,
  // so the step that finds the contact deeper than projection_depth projects it out before its
  // solve. The solve sees it at half the depth, and the stabilisation's push out (erp/h times the
  // depth: 0.36 m/s from 3 cm) stays small; the projection itself adds no velocity.
  const double r = 0.1, sunk = 0.03;
  World w(ball_over_ground(Vec3(0, 0, r - sunk), Vec3::Zero()));
  const StepParams& p = w.step_params();
  const StepStats& first = w.step();
  EXPECT_LE(first.max_penetration, p.projection_depth);
  EXPECT_GT(world_bodies(w).x[1].z(), r - p.projection_depth);
  EXPECT_LT(world_bodies(w).v[1].norm(), p.erp / w.scene().dt * p.projection_depth);
}

}  // namespace
}  // namespace rbpart
