#pragma once
// Scene definition: what the user describes (docs/design.md#contracts). Immutable once a World is built from
// it; the evolving body state lives in the World, per-step scratch data in the pipeline stages.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <utility>
#include <vector>

namespace rbpart {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;

enum class ShapeType { Sphere, Box, Capsule, Cylinder, Convex };

// Geometry in the body's shape frame. Capsule and cylinder axes are the frame's z axis.
struct Shape {
  ShapeType type = ShapeType::Sphere;
  double radius = 0;                  // sphere, capsule, cylinder
  double half_length = 0;             // capsule, cylinder: half the axis length (capsule: without caps)
  Vec3 half_extents = Vec3::Zero();   // box
  std::vector<Vec3> vertices;         // convex: points whose hull is the shape
};

struct BodyDef {
  std::string name;
  bool is_static = false;
  Shape shape;
  double mass = 0;       // kg; when 0, mass = density * volume
  double density = 0;    // kg/m^3
  Vec3 position = Vec3::Zero();              // of the shape frame (not of the centre of mass)
  Quat orientation = Quat::Identity();
  Vec3 velocity = Vec3::Zero();              // of the centre of mass
  Vec3 angular_velocity = Vec3::Zero();
  double friction = -1;  // < 0: the scene's default
};

enum class JointType { Ball, Hinge, Fixed };

struct JointDef {
  JointType type = JointType::Ball;
  int body_a = -1;                  // scene body index
  int body_b = -1;                  // scene body index, -1 = the world
  Vec3 anchor = Vec3::Zero();       // world, at scene start
  Vec3 axis = Vec3::UnitZ();        // hinge: world, at scene start
  double compliance = 0;            // m/N (rad/(N m) for angular rows); 0 = rigid
  bool collide_connected = false;   // joined bodies collide only if asked
};

struct SceneDef {
  std::string name;
  Vec3 gravity{0, 0, -9.81};
  double dt = 1.0 / 60.0;
  double friction = 0.5;  // default Coulomb coefficient; a contact uses sqrt(mu_a * mu_b)
  int steps = 500;        // default step count of the scene
  std::vector<BodyDef> bodies;
  std::vector<JointDef> joints;
};

// The built-in scenes (README, "Built-in scenes"; `rbpart scenes -v` lists their parameters).
std::vector<std::string> builtin_scene_names();

// What the CLI's --scene takes: a built-in scene by name, with `parameters` (name, value as text,
// e.g. {"boxes", "3"}) over its defaults; or else the scene file at that path (docs/formats.md#scene-file).
// Throws std::runtime_error naming the problem (an unknown scene or parameter, a value outside its
// domain, a malformed file).
SceneDef load_scene(const std::string& scene, const std::vector<std::pair<std::string, std::string>>& parameters = {});

}  // namespace rbpart
