// A chain of capsule links on ball joints hanging from the world, its last link much heavier,
// released at an angle so it swings (joint drift test).
#include <algorithm>
#include <cmath>

#include "scenes/scenes.hpp"

namespace rbpart {

namespace {

SceneDef make_hanging_chain(const SceneParameters& p) {
  SceneDef scene;
  scene.name = "hanging_chain";
  scene.dt = p.at("dt");
  scene.steps = static_cast<int>(p.at("steps"));
  const int n = std::max(1, static_cast<int>(p.at("links")));
  const double r = p.at("radius"), half = p.at("half_length"), pitch = 2 * (half + r);
  const double theta = p.at("angle") * M_PI / 180.0;
  const Vec3 down(std::sin(theta), 0, -std::cos(theta));
  const Quat along = Quat::FromTwoVectors(Vec3::UnitZ(), down);
  const Vec3 top(0, 0, n * pitch + 1);
  for (int i = 0; i < n; ++i) {
    BodyDef b;
    b.name = "link" + std::to_string(i);
    b.shape.type = ShapeType::Capsule;
    b.shape.radius = r;
    b.shape.half_length = half;
    b.mass = i == n - 1 ? p.at("mass") * p.at("end_ratio") : p.at("mass");
    b.position = top + (i + 0.5) * pitch * down;
    b.orientation = along;
    scene.bodies.push_back(std::move(b));
    JointDef j;
    j.type = JointType::Ball;
    j.body_a = i;
    j.body_b = i == 0 ? -1 : i - 1;
    j.anchor = top + i * pitch * down;
    scene.joints.push_back(j);
  }
  return scene;
}

}  // namespace

SceneInfo hanging_chain_scene() {
  return {"hanging_chain",
          "capsule links on ball joints hanging from the world, the last link heavier",
          {{"links", 20, "number of links"},
           {"radius", 0.03, "capsule radius (m)"},
           {"half_length", 0.07, "capsule half length without caps (m)"},
           {"mass", 1, "link mass (kg)"},
           {"end_ratio", 100, "last link's mass / link mass"},
           {"angle", 60, "initial angle from the vertical (degrees)"},
           {"dt", 1.0 / 60.0, "time step (s)"},
           {"steps", 600, "default step count"}},
          make_hanging_chain};
}

}  // namespace rbpart
