// A cube on an inclined plane: it stays put below the friction angle and slides with
// a = g (sin(theta) - mu cos(theta)) above it.
#include <cmath>

#include "scenes/scenes.hpp"

namespace rbpart {

namespace {

SceneDef make_slope(const SceneParameters& p) {
  SceneDef scene = scene_base("slope", p);
  const double theta = p.at("angle") * M_PI / 180.0;
  // The plane's normal is z turned by theta about y; downhill is (cos(theta), 0, -sin(theta)).
  const Quat tilt(Eigen::AngleAxisd(theta, Vec3::UnitY()));
  const Vec3 normal = tilt * Vec3::UnitZ();
  const double thickness = 0.25, h = 0.5 * p.at("size");
  scene.bodies.push_back(static_box("slope", -thickness * normal, {20, 5, thickness}, tilt));
  BodyDef b;
  b.name = "block";
  b.shape.type = ShapeType::Box;
  b.shape.half_extents = Vec3::Constant(h);
  b.mass = p.at("mass");
  b.position = h * normal;
  b.orientation = tilt;
  scene.bodies.push_back(std::move(b));
  return scene;
}

}  // namespace

SceneInfo slope_scene() {
  return {"slope",
          "a cube on an inclined plane (analytic friction test)",
          {{"angle", 20, "inclination (degrees)"},
           {"friction", 0.5, "Coulomb coefficient"},
           {"size", 0.2, "cube side (m)"},
           {"mass", 1, "kg"},
           {"dt", 1.0 / 60.0, "time step (s)"},
           {"steps", 120, "default step count"}},
          make_slope};
}

}  // namespace rbpart
