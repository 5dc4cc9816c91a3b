// Rock Pile (docs/design.md#scenes): convex rocks dropped from a jittered grid into a static bin.
#include <algorithm>
#include <cmath>

#include "scenes/scenes.hpp"

namespace rbpart {

namespace {

// A rock: the hull of random points on a perturbed ellipsoid whose largest diameter is `size`.
std::vector<Vec3> rock_vertices(SceneRandom& rng, double size, int points) {
  const Vec3 semi_axes(0.5 * size, rng.uniform(0.6, 1.0) * 0.5 * size, rng.uniform(0.5, 0.9) * 0.5 * size);
  std::vector<Vec3> v(points);
  for (Vec3& p : v) p = semi_axes.cwiseProduct(rng.unit_vector()) * rng.uniform(0.85, 1.0);
  return v;
}

SceneDef make_rock_pile(const SceneParameters& p) {
  const int rocks = std::max(1, static_cast<int>(p.at("rocks")));
  SceneRandom rng(static_cast<std::uint64_t>(p.at("seed")));
  SceneDef scene = scene_base("rock_pile", p);

  // Grid columns so that about `layers` layers hold every rock; the bin is as wide as the grid.
  const double max_size = p.at("max_size"), spacing = 1.3 * max_size;
  const int cols = std::max(2, static_cast<int>(std::ceil(std::sqrt(rocks / p.at("layers")))));
  const double half = 0.5 * cols * spacing;
  add_bin(scene, half, half, 1.0);

  const double heavy = p.at("mass_ratio_set");
  static const double kMassSet[3] = {10, 100, 1000};
  for (int i = 0; i < rocks; ++i) {
    BodyDef b;
    b.name = "rock" + std::to_string(i);
    b.shape.type = ShapeType::Convex;
    b.shape.vertices = rock_vertices(rng, rng.uniform(p.at("min_size"), max_size), static_cast<int>(p.at("points")));
    if (heavy > 0)
      b.mass = kMassSet[std::min(2, static_cast<int>(rng.uniform(0, 3)))];
    else
      b.density = p.at("density");
    b.position = drop_grid_position(i, cols, spacing, 0.5 * max_size + 0.05, 0.1 * max_size, rng);
    b.orientation = rng.rotation();
    scene.bodies.push_back(std::move(b));
  }
  return scene;
}

std::vector<SceneParameter> rock_pile_parameters(int rocks, double mass_ratio_set) {
  return {{"rocks", static_cast<double>(rocks), "number of rocks"},
          {"seed", 1, "random seed"},
          {"min_size", 0.15, "smallest rock diameter (m)"},
          {"max_size", 0.35, "largest rock diameter (m)"},
          {"points", 20, "random points per rock hull"},
          {"density", 2500, "kg/m^3"},
          {"mass_ratio_set", mass_ratio_set, "1: masses drawn from {10, 100, 1000} kg instead of density"},
          {"layers", 8, "grid layers the rocks start in (sets the bin width)"},
          {"friction", 0.5, "Coulomb coefficient"},
          {"dt", 1.0 / 60.0, "time step (s)"},
          {"steps", 500, "default step count"}};
}

}  // namespace

SceneInfo rock_pile_scene() {
  return {"rock_pile", "convex rocks (perturbed ellipsoid hulls) dropped into a static bin, forming a pile",
          rock_pile_parameters(200, 0), make_rock_pile};
}

SceneInfo large_rock_pile_scene() {
  return {"large_rock_pile", "3x the rocks of rock_pile, masses drawn from {10, 100, 1000} kg",
          rock_pile_parameters(600, 1), [](const SceneParameters& p) {
            SceneDef s = make_rock_pile(p);
            s.name = "large_rock_pile";
            return s;
          }};
}

}  // namespace rbpart
