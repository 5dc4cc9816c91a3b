// Scene files: export -> load reproduces a scene bit for bit, defaults, normalisation
// (docs/design.md#contracts).
#include "io/scene_json.hpp"

#include "core/error.hpp"
#include "io/temp_dir.hpp"
#include "scene/limits.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>

namespace rbpart {
namespace {

std::uint64_t bits(double x) {
  std::uint64_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

// Bitwise equality (so -0.0 != 0.0), with the field named on failure.
void expect_same(double a, double b, const std::string& field) {
  EXPECT_EQ(bits(a), bits(b)) << field << ": " << a << " vs " << b;
}
void expect_same(const Vec3& a, const Vec3& b, const std::string& field) {
  for (int k = 0; k < 3; ++k) expect_same(a[k], b[k], field + "[" + std::to_string(k) + "]");
}

void expect_same(const SceneDef& a, const SceneDef& b) {
  EXPECT_EQ(a.name, b.name);
  expect_same(a.gravity, b.gravity, "gravity");
  expect_same(a.dt, b.dt, "dt");
  expect_same(a.friction, b.friction, "friction");
  EXPECT_EQ(a.steps, b.steps);
  ASSERT_EQ(a.bodies.size(), b.bodies.size());
  for (std::size_t i = 0; i < a.bodies.size(); ++i) {
    const BodyDef& x = a.bodies[i];
    const BodyDef& y = b.bodies[i];
    const std::string at = "bodies[" + std::to_string(i) + "].";
    EXPECT_EQ(x.name, y.name) << at;
    EXPECT_EQ(x.is_static, y.is_static) << at;
    EXPECT_EQ(x.shape.type, y.shape.type) << at;
    expect_same(x.shape.radius, y.shape.radius, at + "radius");
    expect_same(x.shape.half_length, y.shape.half_length, at + "half_length");
    expect_same(x.shape.half_extents, y.shape.half_extents, at + "half_extents");
    ASSERT_EQ(x.shape.vertices.size(), y.shape.vertices.size()) << at;
    for (std::size_t v = 0; v < x.shape.vertices.size(); ++v)
      expect_same(x.shape.vertices[v], y.shape.vertices[v], at + "vertices");
    expect_same(x.mass, y.mass, at + "mass");
    expect_same(x.density, y.density, at + "density");
    expect_same(x.position, y.position, at + "position");
    for (int k = 0; k < 4; ++k)
      expect_same(x.orientation.coeffs()[k], y.orientation.coeffs()[k], at + "orientation");
    expect_same(x.velocity, y.velocity, at + "velocity");
    expect_same(x.angular_velocity, y.angular_velocity, at + "angular_velocity");
    expect_same(x.friction, y.friction, at + "friction");
  }
  ASSERT_EQ(a.joints.size(), b.joints.size());
  for (std::size_t j = 0; j < a.joints.size(); ++j) {
    const JointDef& x = a.joints[j];
    const JointDef& y = b.joints[j];
    const std::string at = "joints[" + std::to_string(j) + "].";
    EXPECT_EQ(x.type, y.type) << at;
    EXPECT_EQ(x.body_a, y.body_a) << at;
    EXPECT_EQ(x.body_b, y.body_b) << at;
    expect_same(x.anchor, y.anchor, at + "anchor");
    expect_same(x.axis, y.axis, at + "axis");
    expect_same(x.compliance, y.compliance, at + "compliance");
    EXPECT_EQ(x.collide_connected, y.collide_connected) << at;
  }
}

// A finite double with random bits: any exponent, subnormals and signed zeros included.
double random_finite(std::mt19937_64& rng) {
  for (;;) {
    const std::uint64_t b = rng();
    double x;
    std::memcpy(&x, &b, sizeof x);
    if (std::isfinite(x)) return x;
  }
}

// Every shape and joint type, awkward numbers (thirds, -0.0, subnormals, quaternions that are unit
// only to round-off), and many bodies whose state is random bit patterns.
SceneDef awkward_scene() {
  SceneDef scene;
  scene.name = "round \"trip\" \xc3\xa9";
  scene.gravity = Vec3(0.1, -0.0, -9.80665);
  scene.dt = 1.0 / 240.0;
  scene.friction = 0.1 + 0.2;
  scene.steps = 1234;

  BodyDef ground;
  ground.name = "ground";
  ground.is_static = true;
  ground.shape.type = ShapeType::Box;
  ground.shape.half_extents = Vec3(10, 10.0 / 3.0, 0.5);
  ground.position = Vec3(0, 0, -0.5);
  ground.friction = 0.8;
  scene.bodies.push_back(ground);

  BodyDef sphere;
  sphere.name = "sphere";
  sphere.shape.radius = 0.25;
  sphere.mass = 1.0 / 3.0;
  sphere.position = Vec3(0.1, -0.0, 4.9e-324);
  sphere.velocity = Vec3(limits::kMaxRate, -1e-300, 2.0 / 7.0);
  scene.bodies.push_back(sphere);

  BodyDef capsule;
  capsule.name = "capsule";
  capsule.shape.type = ShapeType::Capsule;
  capsule.shape.radius = 0.05;
  capsule.shape.half_length = 0.2;
  capsule.density = 1000.0 / 3.0;
  capsule.orientation = Quat(Eigen::AngleAxisd(0.3, Vec3(1, 2, 3).normalized()));
  capsule.angular_velocity = Vec3(M_PI, -M_E, std::sqrt(2.0));
  scene.bodies.push_back(capsule);

  BodyDef cylinder;
  cylinder.name = "cylinder";
  cylinder.shape.type = ShapeType::Cylinder;
  cylinder.shape.radius = 0.1;
  cylinder.shape.half_length = 0.5;
  cylinder.mass = 12.5;
  cylinder.orientation = Quat(Eigen::AngleAxisd(2.9, Vec3(0.2, -0.7, 0.1).normalized())) *
                         Quat(Eigen::AngleAxisd(-1.1, Vec3::UnitX()));
  cylinder.friction = 0;
  scene.bodies.push_back(cylinder);

  BodyDef rock;
  rock.name = "rock";
  rock.shape.type = ShapeType::Convex;
  rock.shape.vertices = {Vec3(0.3, 0, 0),       Vec3(-0.1, 0.2 / 3, 0),  Vec3(0, -0.25, 0.01),
                         Vec3(0.05, 0.05, 0.3), Vec3(0.02, 0.01, -0.27), Vec3(-1.0 / 7, -0.1, 0.1)};
  rock.density = 2500;
  rock.position = Vec3(1, 2, 3);
  scene.bodies.push_back(rock);

  // Duplicate names are allowed.
  BodyDef box;
  box.name = "rock";
  box.shape.type = ShapeType::Box;
  box.shape.half_extents = Vec3(0.1, 0.2, 0.3);
  box.mass = 2;
  scene.bodies.push_back(box);

  std::mt19937_64 rng(20240601);
  std::uniform_real_distribution<double> mass(1e-3, 1e3);
  for (int i = 0; i < 100; ++i) {
    BodyDef b;
    b.name = "random" + std::to_string(i);
    b.shape.radius = mass(rng) * 1e-3;
    b.mass = mass(rng);
    // Unit only to round-off: renormalising would change the last bits of about a third of them.
    const Vec3 axis(mass(rng) - 500, mass(rng) - 500, mass(rng) - 500);
    b.orientation = Quat(Eigen::AngleAxisd(mass(rng) * 6e-3, axis.normalized()));
    for (int k = 0; k < 3; ++k) {
      b.position[k] = random_finite(rng);
      // Rates are bounded (limits::kMaxRate); fmod is exact, so the bits stay awkward.
      b.velocity[k] = std::fmod(random_finite(rng), limits::kMaxRate);
      b.angular_velocity[k] = std::fmod(random_finite(rng), limits::kMaxRate);
    }
    scene.bodies.push_back(b);
  }

  JointDef ball;
  ball.type = JointType::Ball;
  ball.body_a = 1;
  ball.body_b = 2;
  ball.anchor = Vec3(0.1, 0.05, 1.0 / 3.0);
  ball.compliance = 1e-7;
  scene.joints.push_back(ball);

  JointDef hinge;
  hinge.type = JointType::Hinge;
  hinge.body_a = 2;
  hinge.body_b = 3;
  hinge.anchor = Vec3(-0.0, 0.2, 0.7);
  hinge.axis = Vec3(0, 0.6, 0.8);
  hinge.collide_connected = true;
  scene.joints.push_back(hinge);

  JointDef fixed;
  fixed.type = JointType::Fixed;
  fixed.body_a = 4;
  fixed.body_b = -1;
  fixed.anchor = Vec3(1, 2, 3);
  scene.joints.push_back(fixed);

  JointDef ball_to_static;
  ball_to_static.body_a = 0;
  ball_to_static.body_b = 5;
  ball_to_static.anchor = Vec3(0, 0, 0.1);
  scene.joints.push_back(ball_to_static);
  return scene;
}

TEST(SceneJson, ExportThenLoadIsBitIdentical) {
  const SceneDef scene = awkward_scene();
  const std::string text = scene_to_json(scene);
  const SceneDef loaded = parse_scene(text, "export.json");
  expect_same(scene, loaded);
  // And the text is a fixed point: exporting the loaded scene writes the same file.
  EXPECT_EQ(scene_to_json(loaded), text);
}

TEST(SceneJson, ExportWritesEveryFieldIncludingExtensions) {
  const SceneDef scene = awkward_scene();
  const auto json = nlohmann::json::parse(scene_to_json(scene));
  EXPECT_EQ(json.at("steps"), 1234);
  EXPECT_EQ(json.at("dt").get<double>(), 1.0 / 240.0);
  EXPECT_EQ(json.at("joints").at(1).at("collide_connected"), true);
  EXPECT_EQ(json.at("joints").at(1).at("axis"), nlohmann::json({0.0, 0.6, 0.8}));
  EXPECT_FALSE(json.at("joints").at(0).contains("axis"));  // only a hinge has one
  EXPECT_EQ(json.at("joints").at(2).at("bodies"), nlohmann::json({4, -1}));
  const auto& ground = json.at("bodies").at(0);
  EXPECT_EQ(ground.at("static"), true);
  EXPECT_FALSE(ground.contains("mass"));
  EXPECT_FALSE(ground.contains("density"));
  EXPECT_EQ(ground.at("friction"), 0.8);
  const auto& sphere = json.at("bodies").at(1);
  EXPECT_FALSE(sphere.contains("friction"));  // -1: the scene default
  EXPECT_EQ(sphere.at("shape"), nlohmann::json({{"type", "sphere"}, {"radius", 0.25}}));
  EXPECT_EQ(json.at("bodies").at(2).at("density").get<double>(), 1000.0 / 3.0);
  EXPECT_EQ(json.at("bodies").at(4).at("shape").at("vertices").size(), 6u);
}

TEST(SceneJson, WriteThenLoadFile) {
  test::TempDir dir;
  const SceneDef scene = awkward_scene();
  write_scene_file(dir.file("scene.json"), scene);
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"scene.json"});
  expect_same(scene, load_scene_file(dir.file("scene.json")));
}

TEST(SceneJson, DefaultsForOptionalKeys) {
  const char* text = R"({
    "bodies": [
      {"shape": {"type": "sphere", "radius": 1}, "mass": 2},
      {"static": true, "shape": {"type": "box", "half_extents": [1, 1, 1]}}
    ],
    "joints": [{"type": "ball", "bodies": [0, -1], "anchor": [0, 0, 1]}]
  })";
  const SceneDef scene = parse_scene(text, "defaults.json");
  EXPECT_EQ(scene.name, "");
  EXPECT_EQ(scene.gravity, Vec3(0, 0, -9.81));
  EXPECT_EQ(scene.dt, 1.0 / 60.0);
  EXPECT_EQ(scene.friction, 0.5);
  EXPECT_EQ(scene.steps, 500);
  ASSERT_EQ(scene.bodies.size(), 2u);
  const BodyDef& b = scene.bodies[0];
  EXPECT_EQ(b.name, "body0");
  EXPECT_EQ(scene.bodies[1].name, "body1");
  EXPECT_FALSE(b.is_static);
  EXPECT_TRUE(scene.bodies[1].is_static);
  EXPECT_EQ(b.mass, 2);
  EXPECT_EQ(b.density, 0);
  EXPECT_EQ(b.position, Vec3::Zero());
  EXPECT_EQ(b.orientation.coeffs(), Quat::Identity().coeffs());
  EXPECT_EQ(b.velocity, Vec3::Zero());
  EXPECT_EQ(b.angular_velocity, Vec3::Zero());
  EXPECT_EQ(b.friction, -1);  // the scene's default
  ASSERT_EQ(scene.joints.size(), 1u);
  EXPECT_EQ(scene.joints[0].compliance, 0);
  EXPECT_FALSE(scene.joints[0].collide_connected);
  EXPECT_EQ(scene.joints[0].body_b, -1);
}

const char* kOneBody = R"({"bodies": [{"shape": {"type": "sphere", "radius": 1}, "mass": 1,
                           "orientation": %s}]})";

Quat orientation_of(const std::string& wxyz) {
  char text[512];
  std::snprintf(text, sizeof text, kOneBody, wxyz.c_str());
  return parse_scene(text, "q.json").bodies[0].orientation;
}

TEST(SceneJson, QuaternionsAreNormalised) {
  // [1, 1, 1, 1] / 2 is exact in binary.
  const Quat half = orientation_of("[1, 1, 1, 1]");
  EXPECT_EQ(half.coeffs(), Eigen::Vector4d(0.5, 0.5, 0.5, 0.5));  // coeffs() is [x, y, z, w]
  const Quat turn = orientation_of("[-3, 0, 0, 4]");
  EXPECT_EQ(turn.w(), -0.6);
  EXPECT_EQ(turn.z(), 0.8);
  // Seven digits of cos 45 deg: normalised to unit length, direction kept.
  const Quat rounded = orientation_of("[0.7071068, 0, 0, 0.7071068]");
  EXPECT_NEAR(rounded.norm(), 1.0, 1e-15);
  EXPECT_EQ(rounded.w(), rounded.z());
  // Within 1e-12 of unit: kept bit for bit (renormalising could change the last bits).
  const Quat almost = orientation_of("[1.0000000000001, 0, 0, 0]");
  EXPECT_EQ(almost.w(), 1.0000000000001);
}

TEST(SceneJson, UnreadableFileIsAnInputError) {
  test::TempDir dir;
  const std::string path = dir.file("absent.json");
  try {
    load_scene_file(path);
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()), path + ": cannot read: No such file or directory");
  }
  EXPECT_THROW(load_scene_file(dir.file("")), InputError);  // a directory
}

}  // namespace
}  // namespace rbpart
