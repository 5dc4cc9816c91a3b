// State files: the shape-frame pose and velocities of every body, in scene order, exact.
#include "io/state_json.hpp"

#include "core/error.hpp"
#include "io/temp_dir.hpp"
#include "scene/bodies.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <stdexcept>

namespace rbpart {
namespace {

// Two bodies with off-centre centres of mass, so the shape-frame position differs from x.
struct TwoBodies {
  SceneDef scene;
  Bodies bodies;
  TwoBodies() {
    scene.bodies.resize(2);
    scene.bodies[0].name = "rock";
    scene.bodies[1].name = "log";
    bodies.com_local = {Vec3(1, 0, 0), Vec3(0.1, 0.2, 1.0 / 3.0)};
    // Body 0 turned 90 degrees about z: its centre of mass, 1 m along the frame's x, lies 1 m along
    // world y from the frame origin.
    bodies.q = {Quat(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ())), Quat(0.5, -0.5, 0.5, -0.5)};
    bodies.x = {Vec3(5, 0, 0), Vec3(0.1, -0.0, 1e-300)};
    bodies.v = {Vec3(1.0 / 3.0, 0, -9.81 / 60), Vec3(0, 0, 0)};
    bodies.w = {Vec3(0, 0, 2.0 / 7.0), Vec3(-1e-17, 3, 4)};
  }
};

TEST(StateJson, WritesPosesAndVelocitiesInSceneOrder) {
  const TwoBodies s;
  test::TempDir dir;
  const std::string path = dir.file("state.json");
  write_state_json(path, s.scene, s.bodies, 1.0 / 3.0, {{"erp", "0.2"}, {"solver", "direct"}});
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"state.json"});

  const auto state = nlohmann::json::parse(test::read_text(path));
  EXPECT_EQ(state.at("time").get<double>(), 1.0 / 3.0);
  const auto& list = state.at("bodies");
  ASSERT_EQ(list.size(), 2u);
  EXPECT_EQ(list[0].at("name"), "rock");
  EXPECT_EQ(list[1].at("name"), "log");
  for (int i = 0; i < 2; ++i) {
    const auto& b = list[i];
    const auto vec = [&](const char* key) { return b.at(key).get<std::vector<double>>(); };
    // Exact: the numbers parse back to the bits that were written.
    const Vec3 frame = s.bodies.frame_position(i);
    EXPECT_EQ(vec("position"), std::vector<double>(frame.data(), frame.data() + 3));
    const Quat& q = s.bodies.q[i];
    EXPECT_EQ(vec("orientation"), (std::vector<double>{q.w(), q.x(), q.y(), q.z()}));
    EXPECT_EQ(vec("velocity"), std::vector<double>(s.bodies.v[i].data(), s.bodies.v[i].data() + 3));
    EXPECT_EQ(vec("angular_velocity"), std::vector<double>(s.bodies.w[i].data(), s.bodies.w[i].data() + 3));
  }
  // The shape frame of body 0 is x - R com = (5, 0, 0) - (0, 1, 0).
  const auto p0 = list[0].at("position").get<std::vector<double>>();
  EXPECT_NEAR(p0[0], 5, 1e-15);
  EXPECT_NEAR(p0[1], -1, 1e-15);
  EXPECT_NEAR(p0[2], 0, 1e-15);
  EXPECT_EQ(state.at("params"), nlohmann::json({{"erp", "0.2"}, {"solver", "direct"}}));
}

TEST(StateJson, ParamsOnlyWhenGiven) {
  const TwoBodies s;
  EXPECT_FALSE(nlohmann::json::parse(state_to_json(s.scene, s.bodies, 0)).contains("params"));
}

TEST(StateJson, BodiesOfAnotherSceneAreAnInternalError) {
  TwoBodies s;
  s.scene.bodies.pop_back();
  EXPECT_THROW(state_to_json(s.scene, s.bodies, 0), std::logic_error);
}

TEST(StateJson, UnwritableDirectoryLeavesNothing) {
  const TwoBodies s;
  test::TempDir dir;
  EXPECT_THROW(write_state_json(dir.file("missing/state.json"), s.scene, s.bodies, 0), InputError);
  EXPECT_TRUE(dir.entries().empty());
}

}  // namespace
}  // namespace rbpart
