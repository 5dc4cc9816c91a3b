// A sphere on a ball joint to the world, released from rest at a small angle (analytic period).
#include <cmath>

#include "scenes/scenes.hpp"

namespace rbpart {

namespace {

SceneDef make_pendulum(const SceneParameters& p) {
  SceneDef scene = scene_base("pendulum", p);
  const double L = p.at("length"), theta = p.at("angle") * M_PI / 180.0;
  const Vec3 pivot(0, 0, 2 * L);
  BodyDef b;
  b.name = "bob";
  b.shape.type = ShapeType::Sphere;
  b.shape.radius = p.at("radius");
  b.mass = p.at("mass");
  b.position = pivot + L * Vec3(std::sin(theta), 0, -std::cos(theta));
  scene.bodies.push_back(std::move(b));
  JointDef j;
  j.type = JointType::Ball;
  j.body_a = 0;
  j.body_b = -1;
  j.anchor = pivot;
  scene.joints.push_back(j);
  return scene;
}

}  // namespace

SceneInfo pendulum_scene() {
  return {"pendulum",
          "a sphere hanging from the world on a ball joint (analytic period test)",
          {{"length", 1, "pivot to sphere centre (m)"},
           {"angle", 5, "initial angle from the vertical (degrees)"},
           {"radius", 0.05, "sphere radius (m)"},
           {"mass", 1, "kg"},
           {"dt", 1.0 / 240.0, "time step (s)"},
           {"steps", 2400, "default step count"}},
          make_pendulum};
}

}  // namespace rbpart
