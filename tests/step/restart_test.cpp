// World::restart (`rbpart simulate --initial-state`): a run continued from its own state file is the
// run itself. Without contacts or joints a step is a function of the bodies' state alone, so N steps
// equal k steps, a state file and N - k steps bit for bit; with contacts the first resumed step is
// solved cold, and a resting stack must stay at rest.
#include <gtest/gtest.h>
#include <rbpart/world.hpp>

#include <cmath>
#include <memory>
#include <stdexcept>

#include "io/scene_json.hpp"
#include "io/state_json.hpp"
#include "scene/bodies.hpp"
#include "scenes/scenes.hpp"
#include "step/world_internals.hpp"

namespace rbpart {
namespace {

// A brick of unequal sides thrown up and tumbling about no principal axis, in empty space.
SceneDef tumbling_brick() {
  SceneDef s;
  s.name = "tumble";
  s.dt = 0.01;
  BodyDef b;
  b.name = "brick";
  b.shape.type = ShapeType::Box;
  b.shape.half_extents = Vec3(0.3, 0.2, 0.1);
  b.mass = 2;
  b.position = Vec3(0, 0, 5);
  b.velocity = Vec3(1, 0.5, 3);
  b.angular_velocity = Vec3(2, 5, 1);
  s.bodies.push_back(b);
  return s;
}

// A World continued from `from`'s state, as `simulate --state` writes it and `--initial-state` reads it.
std::unique_ptr<World> resumed(const World& from) {
  const std::string text = state_to_json(from.scene(), world_bodies(from), from.time());
  const SceneState state = parse_state(text, "state.json", from.scene());
  auto world = std::make_unique<World>(from.scene());
  world->restart(state.time, state.bodies);
  return world;
}

TEST(Restart, FreeFlightResumedEqualsTheUninterruptedRunBitForBit) {
  const int N = 60;
  World whole(tumbling_brick());
  for (int i = 0; i < N; ++i) whole.step();
  std::unique_ptr<World> rest;
  for (int k : {1, 12, 23, 47}) {
    World first(tumbling_brick());
    for (int i = 0; i < k; ++i) first.step();
    rest = resumed(first);
    EXPECT_EQ(rest->step_count(), k);
    for (int i = k; i < N; ++i) EXPECT_EQ(rest->step().step, i + 1);
    EXPECT_EQ(rest->state_hash(), whole.state_hash()) << "resumed at step " << k;
    EXPECT_EQ(rest->time(), whole.time()) << "resumed at step " << k;
  }
  // And both are semi-implicit Euler's parabola: v_N = v_0 + N h g, x_N = x_0 + N h v_0 + h^2 g N(N+1)/2.
  const SceneDef s = tumbling_brick();
  const double h = s.dt;
  const Vec3 g = s.gravity;
  const BodyState end = rest->body_state(0);
  EXPECT_LT((end.velocity - (s.bodies[0].velocity + N * h * g)).norm(), 1e-12);
  const Vec3 com = world_bodies(*rest).x[0];
  EXPECT_LT((com - (s.bodies[0].position + N * h * s.bodies[0].velocity + h * h * g * N * (N + 1) / 2.0)).norm(),
            1e-12);
}

TEST(Restart, ATimeBetweenStepsContinuesAndStepsAreNumberedFromItsNearestStep) {
  World w(tumbling_brick());
  w.restart(0.126, {w.body_state(0)});
  EXPECT_EQ(w.step_count(), 13);
  EXPECT_EQ(w.time(), 0.126);
  EXPECT_EQ(w.step().step, 14);
  EXPECT_NEAR(w.time(), 0.136, 1e-15);
}

TEST(Restart, AResumedRestingStackStaysAtRest) {
  // 2 s of a 6-box stack, then 1 s more from its state with a cold first solve: a box that fell
  // for one step would have 1/2 m (g h)^2; the whole stack must stay below a millionth of that, and
  // every box within 0.1 mm of where the state put it.
  const SceneDef def = make_builtin_scene("box_stack", {{"boxes", "6"}});
  World settle(def);
  for (int i = 0; i < 120; ++i) settle.step();
  const auto rest = resumed(settle);
  const std::vector<Vec3> start = world_bodies(*rest).x;
  double worst = 0;
  for (int i = 0; i < 60; ++i) worst = std::max(worst, rest->step().kinetic_energy);
  const double drop = 0.5 * world_bodies(*rest).mass[1] * std::pow(def.gravity.norm() * def.dt, 2);
  EXPECT_LT(worst, 1e-6 * drop);
  for (int i = 0; i < rest->body_count(); ++i)
    EXPECT_LT((world_bodies(*rest).x[i] - start[i]).norm(), 1e-4) << "box " << i;
}

TEST(Restart, RefusesAStateThatCannotBeTheScenes) {
  World w(tumbling_brick());
  BodyState s = w.body_state(0);
  EXPECT_THROW(w.restart(0, {}), std::invalid_argument);
  EXPECT_THROW(w.restart(-0.5, {s}), std::invalid_argument);
  s.orientation = Quat(1.1, 0, 0, 0);
  EXPECT_THROW(w.restart(0, {s}), std::invalid_argument);
  s = w.body_state(0);
  s.velocity.x() = std::nan("");
  EXPECT_THROW(w.restart(0, {s}), std::invalid_argument);
  w.step();
  EXPECT_THROW(w.restart(0, {w.body_state(0)}), std::logic_error);
}

}  // namespace
}  // namespace rbpart
