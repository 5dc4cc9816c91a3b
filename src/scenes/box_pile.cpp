// Box pile: the monolithic solver's benchmark scene (issue #2): random boxes 0.2-0.5 m dropped into
// a bin, density 1000 kg/m^3 or masses drawn from {10, 100, 1000} kg.
#include <algorithm>
#include <cmath>

#include "scenes/scenes.hpp"

namespace rbpart {

namespace {

SceneDef make_box_pile(const SceneParameters& p) {
  const int boxes = std::max(1, static_cast<int>(p.at("boxes")));
  SceneRandom rng(static_cast<std::uint64_t>(p.at("seed")));
  SceneDef scene = scene_base("box_pile", p);
  const double max_size = p.at("max_size"), spacing = 1.25 * max_size * std::sqrt(3.0);
  const int cols = std::max(2, static_cast<int>(std::ceil(std::sqrt(boxes / p.at("layers")))));
  const double half = 0.5 * cols * spacing;
  add_bin(scene, half, half, 1.0);
  static const double kMassSet[3] = {10, 100, 1000};
  for (int i = 0; i < boxes; ++i) {
    BodyDef b;
    b.name = "box" + std::to_string(i);
    b.shape.type = ShapeType::Box;
    b.shape.half_extents = 0.5 * Vec3(rng.uniform(p.at("min_size"), max_size), rng.uniform(p.at("min_size"), max_size),
                                      rng.uniform(p.at("min_size"), max_size));
    if (p.at("mass_ratio_set") > 0)
      b.mass = kMassSet[std::min(2, static_cast<int>(rng.uniform(0, 3)))];
    else
      b.density = p.at("density");
    b.position = drop_grid_position(i, cols, spacing, 0.5 * spacing, 0.1 * max_size, rng);
    b.orientation = rng.rotation();
    scene.bodies.push_back(std::move(b));
  }
  return scene;
}

}  // namespace

SceneInfo box_pile_scene() {
  return {"box_pile",
          "random boxes dropped into a static bin (the direct solver's benchmark pile)",
          {{"boxes", 200, "number of boxes"},
           {"seed", 1, "random seed"},
           {"min_size", 0.2, "smallest box side (m)"},
           {"max_size", 0.5, "largest box side (m)"},
           {"density", 1000, "kg/m^3"},
           {"mass_ratio_set", 0, "1: masses drawn from {10, 100, 1000} kg instead of density"},
           {"layers", 6, "grid layers the boxes start in (sets the bin width)"},
           {"friction", 0.5, "Coulomb coefficient"},
           {"dt", 1.0 / 60.0, "time step (s)"},
           {"steps", 300, "default step count (the pile has formed by then)"}},
          make_box_pile};
}

}  // namespace rbpart
