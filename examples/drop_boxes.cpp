// Drops three boxes of 1, 10 and 100 kg onto a floor, pushes the light one sideways for a moment,
// and once they rest prints every body's pose and velocity and every contact with its impulse.
// Exits 1 unless the floor's contacts carry the boxes' weight: at rest their impulses over one step
// sum to m g h for each box (docs/design.md#dynamics).
#include <rbpart/world.hpp>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace {

// A box of the given half extents (m) and mass (kg; 0 makes it static), turned by `turn` about z.
rbpart::BodyDef box(const std::string& name, double mass, const rbpart::Vec3& half_extents,
                    const rbpart::Vec3& position, double turn = 0) {
  rbpart::BodyDef b;
  b.name = name;
  b.mass = mass;
  b.is_static = mass == 0;
  b.position = position;
  b.orientation = rbpart::Quat(Eigen::AngleAxisd(turn, rbpart::Vec3::UnitZ()));
  b.shape.type = rbpart::ShapeType::Box;
  b.shape.half_extents = half_extents;
  return b;
}

}  // namespace

int main() {
  using namespace rbpart;
  SceneDef scene;
  scene.name = "drop_boxes";
  scene.dt = 1.0 / 60.0;
  scene.bodies.push_back(box("floor", 0, Vec3(5, 5, 0.1), Vec3(0, 0, -0.1)));
  const double masses[] = {1, 10, 100};
  for (int i = 0; i < 3; ++i)
    scene.bodies.push_back(box("box" + std::to_string(i), masses[i], Vec3(0.2, 0.15, 0.1),
                               Vec3(-1.0 + i, 0, 0.5 + 0.3 * i), 0.3 * i));

  World world(scene);
  // Step for 3 s; for the first 0.1 s a 5 N push along +y on the light box, at its top face.
  for (int step = 0; step < 180; ++step) {
    if (step < 6) {
      const Vec3 top = world.body_state(1).position + Vec3(0, 0, 0.1);
      world.apply_force(1, Vec3(0, 5, 0), top);
    }
    world.step();
  }

  std::printf("t = %.3f s; per body: position (m), orientation (w x y z), velocity (m/s)\n", world.time());
  for (int i = 0; i < world.body_count(); ++i) {
    const BodyState s = world.body_state(i);
    std::printf("%-6s %10.5f %10.5f %10.5f %10.6f %10.6f %10.6f %10.6f %9.2e %9.2e %9.2e\n",
                scene.bodies[i].name.c_str(), s.position.x(), s.position.y(), s.position.z(), s.orientation.w(),
                s.orientation.x(), s.orientation.y(), s.orientation.z(), s.velocity.x(), s.velocity.y(),
                s.velocity.z());
  }

  std::vector<double> floor_impulse(world.body_count(), 0.0);
  std::printf("%zu contacts: bodies, point (m), normal impulse and total impulse on a (N s)\n", world.contacts().size());
  for (const ContactImpulse& c : world.contacts()) {
    const Vec3 j = c.impulse();
    std::printf("  %d-%d  (%8.4f %8.4f %8.4f)  %10.6f  (%9.2e %9.2e %10.6f)\n", c.body_a, c.body_b, c.point.x(),
                c.point.y(), c.point.z(), c.normal_impulse, j.x(), j.y(), j.z());
    if (c.body_b == 0) floor_impulse[c.body_a] += j.z();
  }

  int failures = 0;
  for (int i = 1; i < world.body_count(); ++i) {
    const double weight = world.body_mass(i) * 9.81 * scene.dt;  // m g h
    const bool ok = std::abs(floor_impulse[i] - weight) <= 1e-5 * weight;
    std::printf("%s: floor impulse %.9f N s, m g h %.9f N s%s\n", scene.bodies[i].name.c_str(), floor_impulse[i],
                weight, ok ? "" : "  <- not at rest on the floor");
    failures += !ok;
  }
  return failures == 0 ? 0 : 1;
}
