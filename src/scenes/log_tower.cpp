// Log Tower (docs/design.md#scenes): a crib of `layers` layers of `logs` logs, each layer turned 90 degrees,
// hit by a heavy block dropped on top.
#include <algorithm>
#include <cmath>

#include "scenes/scenes.hpp"

namespace rbpart {

namespace {

SceneDef make_log_tower(const SceneParameters& p) {
  SceneDef scene = scene_base("log_tower", p);
  scene.bodies.push_back(static_box("ground", {0, 0, -0.5}, {10, 10, 0.5}));
  const int layers = std::max(1, static_cast<int>(p.at("layers")));
  const int logs = std::max(1, static_cast<int>(p.at("logs")));
  const double r = p.at("radius"), half = p.at("half_length"), span = 0.8 * half;
  // Round logs (capsules) make the crib a mechanism: a log rolling between the layers above and below
  // shears the tower at no cost in potential energy, and rigid point contacts have no rolling
  // resistance, so any asymmetry under the block grows until the tower falls (measured: it collapses
  // within 60 steps even when the block is set down gently). Square-hewn logs (boxes of side 2r,
  // the default) rest face on face and stand or shake as a crib of notched logs does.
  const bool round = p.at("round") != 0;
  const double log_mass = round ? p.at("density") * M_PI * r * r * (2 * half + 4.0 / 3.0 * r)
                                : p.at("density") * 8 * r * r * (half + r);
  const Quat along_x = Quat::FromTwoVectors(Vec3::UnitZ(), Vec3::UnitX());
  const Quat along_y = Quat::FromTwoVectors(Vec3::UnitZ(), Vec3::UnitY());
  for (int layer = 0; layer < layers; ++layer) {
    const bool x_layer = layer % 2 == 0;
    for (int k = 0; k < logs; ++k) {
      const double offset = logs == 1 ? 0 : -span + 2 * span * k / (logs - 1);
      BodyDef b;
      b.name = "log" + std::to_string(layer) + "_" + std::to_string(k);
      if (round) {
        b.shape.type = ShapeType::Capsule;
        b.shape.radius = r;
        b.shape.half_length = half;
      } else {
        b.shape.type = ShapeType::Box;
        b.shape.half_extents = {r, r, half + r};  // long axis = body z, as the capsule's
      }
      b.density = p.at("density");
      b.position = x_layer ? Vec3(0, offset, r + 2 * r * layer) : Vec3(offset, 0, r + 2 * r * layer);
      b.orientation = x_layer ? along_x : along_y;
      scene.bodies.push_back(std::move(b));
    }
  }
  // The block: `block_ratio` times a log's mass, dropped from `drop_height` above the top layer.
  BodyDef block;
  block.name = "block";
  block.shape.type = ShapeType::Box;
  const double bh = p.at("block_size") / 2;
  block.shape.half_extents = Vec3::Constant(bh);
  block.mass = p.at("block_ratio") * log_mass;
  block.position = {0.1 * half, 0.1 * half, 2 * r * layers + p.at("drop_height") + bh};
  scene.bodies.push_back(std::move(block));
  return scene;
}

}  // namespace

SceneInfo log_tower_scene() {
  return {"log_tower",
          "crib tower of square-hewn (or round) logs, layers turned 90 degrees, a heavy block dropped on top",
          {{"layers", 16, "number of layers"},
           {"logs", 3, "logs per layer"},
           {"round", 0, "1: round logs (capsules), 0: square-hewn logs (boxes of side 2 radius)"},
           {"radius", 0.08, "log radius, or half side of a square log (m)"},
           {"half_length", 0.5, "log half length without caps (m)"},
           {"density", 600, "log density (kg/m^3)"},
           {"block_ratio", 30, "block mass / log mass"},
           {"block_size", 0.6, "block side (m)"},
           {"drop_height", 1.0, "block's fall height above the top layer (m)"},
           {"friction", 0.6, "Coulomb coefficient"},
           {"dt", 1.0 / 60.0, "time step (s)"},
           {"steps", 500, "default step count"}},
          make_log_tower};
}

}  // namespace rbpart
