// A chain of capsule links on ball joints hanging from the world, its last link much heavier,
// released at an angle so it swings (joint drift test).
#include <cmath>

#include "scenes/scenes.hpp"

namespace rbpart {

namespace {

SceneDef make_hanging_chain(const SceneParameters& p) {
  SceneDef scene = scene_base("hanging_chain", p);
  const double pitch = 2 * (p.at("half_length") + p.at("radius"));
  const double theta = p.at("angle") * M_PI / 180.0;
  add_capsule_chain(scene, p, Vec3(0, 0, p.at("links") * pitch + 1), Vec3(std::sin(theta), 0, -std::cos(theta)),
                    true);
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
