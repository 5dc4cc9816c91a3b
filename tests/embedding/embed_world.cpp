// A program that embeds rbpart as a user would: the public headers alone, compiled with the
// compiler's default flags, linked against librbpart.a. The scene's Eigen members (Vec3, Quat)
// are laid out by this translation unit and read by the library, so a library built with other
// vector flags (-march=native: Quat aligned to 32 bytes instead of 16) misreads or crashes here
// (issue #26). Exit status 0 when the library steps the scene as physics says.
#include <rbpart/world.hpp>

#include <cmath>
#include <cstdio>

namespace {

int failures = 0;

void check(bool ok, const char* what, double got, double expected) {
  if (ok) return;
  ++failures;
  std::fprintf(stderr, "embed_world: %s: got %.17g, expected %.17g\n", what, got, expected);
}

}  // namespace

int main() {
  using namespace rbpart;
  // A 2 kg ball of radius 0.1 m falling from 1 m onto a static slab whose top is at z = 0.
  SceneDef scene;
  scene.name = "embedded";
  scene.dt = 0.01;
  BodyDef floor;
  floor.name = "floor";
  floor.is_static = true;
  floor.shape.type = ShapeType::Box;
  floor.shape.half_extents = Vec3(2, 2, 0.1);
  floor.position = Vec3(0, 0, -0.1);
  floor.density = 1;
  BodyDef ball;
  ball.name = "ball";
  ball.shape.type = ShapeType::Sphere;
  ball.shape.radius = 0.1;
  ball.mass = 2;
  ball.position = Vec3(0, 0, 1.1);
  // A quarter turn about z: the library must read the orientation this program wrote.
  ball.orientation = Quat(std::cos(M_PI / 4), 0, 0, std::sin(M_PI / 4));
  scene.bodies = {floor, ball};

  World world(scene);
  // 0.21 s of free fall (the ball stays 0.78 m above the floor): semi-implicit Euler gives v = g t
  // up to round-off, so the kinetic energy is m (g t)^2 / 2.
  for (int i = 0; i < 20; ++i) world.step();
  const StepStats& fall = world.step();
  const double v = 9.81 * 0.21, expected = 0.5 * 2 * v * v;
  check(fall.contacts == 0, "contacts in free fall", fall.contacts, 0);
  check(std::abs(fall.kinetic_energy - expected) <= 1e-9 * expected, "kinetic energy at 0.21 s",
        fall.kinetic_energy, expected);
  // The pose read back through the public accessors: semi-implicit Euler's height after n = 21 steps,
  // z0 - g h^2 n (n + 1) / 2, and the quarter turn this program wrote, untouched.
  const BodyState fallen = world.body_state(1);
  const double z = 1.1 - 9.81 * 0.01 * 0.01 * 21 * 22 / 2;
  check(std::abs(fallen.position.z() - z) <= 1e-12, "height at 0.21 s", fallen.position.z(), z);
  check(std::abs(fallen.velocity.z() + v) <= 1e-12, "velocity at 0.21 s", fallen.velocity.z(), -v);
  check(std::abs(fallen.orientation.z() - std::sin(M_PI / 4)) <= 1e-15, "orientation z", fallen.orientation.z(),
        std::sin(M_PI / 4));
  // Landed after 2 s: at rest on the floor, one contact solved exactly.
  for (int i = 0; i < 180; ++i) world.step();
  const StepStats& rest = world.step();
  check(rest.contacts >= 1, "contacts at rest", rest.contacts, 1);
  check(rest.kinetic_energy < 1e-6, "kinetic energy at rest", rest.kinetic_energy, 0);
  check(rest.solve.residual <= 1e-9, "BLCP residual at rest", rest.solve.residual, 0);
  // At rest the floor's contacts carry the weight: their impulses over a step sum to m g h.
  double impulse = 0;
  for (const ContactImpulse& c : world.contacts()) impulse += c.impulse().z();
  const double weight = 2 * 9.81 * 0.01;
  check(std::abs(impulse - weight) <= 1e-5 * weight, "floor impulse at rest", impulse, weight);
  check(world.step_count() == 202, "steps", world.step_count(), 202);
  if (failures == 0) std::printf("embed_world: ok (state hash %016llx)\n", (unsigned long long)world.state_hash());
  return failures == 0 ? 0 : 1;
}
