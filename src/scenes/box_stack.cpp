// A vertical stack of cubes resting on the ground, optionally alternating light and heavy (the
// 1000:1 case iterative solvers cannot hold up).
#include <algorithm>

#include "scenes/scenes.hpp"

namespace rbpart {

namespace {

SceneDef make_box_stack(const SceneParameters& p) {
  SceneDef scene = scene_base("box_stack", p);
  scene.bodies.push_back(static_box("ground", {0, 0, -0.5}, {5, 5, 0.5}));
  const double h = 0.5 * p.at("size");
  const int n = std::max(1, static_cast<int>(p.at("boxes")));
  for (int i = 0; i < n; ++i) {
    BodyDef b;
    b.name = "box" + std::to_string(i);
    b.shape.type = ShapeType::Box;
    b.shape.half_extents = Vec3::Constant(h);
    b.mass = i % 2 == 0 ? p.at("mass_even") : p.at("mass_odd");
    b.position = {0, 0, h + 2 * h * i};
    scene.bodies.push_back(std::move(b));
  }
  return scene;
}

}  // namespace

SceneInfo box_stack_scene() {
  return {"box_stack",
          "a stack of cubes resting on the ground; masses alternate between mass_even and mass_odd",
          {{"boxes", 10, "number of cubes"},
           {"size", 0.5, "cube side (m)"},
           {"mass_even", 125, "mass of cubes 0, 2, 4, ... from the bottom (kg)"},
           {"mass_odd", 125, "mass of cubes 1, 3, 5, ... (kg)"},
           {"friction", 0.5, "Coulomb coefficient"},
           {"dt", 1.0 / 60.0, "time step (s)"},
           {"steps", 600, "default step count"}},
          make_box_stack};
}

}  // namespace rbpart
