// Chain Drop (docs/design.md#scenes): capsule links on ball joints released horizontally above the ground,
// falling across a static bar and folding onto the ground; the last link is much heavier.
#include <algorithm>

#include "scenes/scenes.hpp"

namespace rbpart {

namespace {

SceneDef make_chain_drop(const SceneParameters& p) {
  SceneDef scene = scene_base("chain_drop", p);
  const int n = std::max(2, static_cast<int>(p.at("links")));
  const double length = n * 2 * (p.at("half_length") + p.at("radius")), height = p.at("height");
  scene.bodies.push_back(static_box("ground", {0, 0, -0.5}, {length, length, 0.5}));
  // The bar runs across the chain (along y) under the point `bar_at` of the chain's length. The
  // heavy end's side is the shorter one and pulls the chain over the bar, which it can while it
  // outweighs the other side by the capstan factor e^(mu theta) (2.6 at mu 0.3 over a half turn;
  // 4.8 at mu 0.5, where the chain hangs still); both sides fold onto the ground at the bar's foot.
  const double bar_x = -0.5 * length + p.at("bar_at") * length;
  const double bar_r = p.at("bar_radius");
  scene.bodies.push_back(static_box("bar", {bar_x, 0, p.at("bar_height") - bar_r}, {bar_r, 1.0, bar_r}));
  add_capsule_chain(scene, p, Vec3(-0.5 * length, 0, height), Vec3::UnitX(), false);
  return scene;
}

}  // namespace

SceneInfo chain_drop_scene() {
  return {"chain_drop",
          "capsule chain on ball joints released horizontally, falling across a bar; last link heavy",
          {{"links", 100, "number of links"},
           {"radius", 0.025, "link capsule radius (m)"},
           {"half_length", 0.05, "link capsule half length without caps (m)"},
           {"mass", 1, "link mass (kg)"},
           {"end_ratio", 100, "last link's mass / link mass"},
           {"height", 4.5, "release height (m)"},
           {"bar_height", 4.0, "top of the bar (m)"},
           {"bar_radius", 0.05, "half thickness of the bar (m)"},
           {"bar_at", 0.65, "where along the chain the bar sits (0..1)"},
           {"friction", 0.3, "Coulomb coefficient"},
           {"dt", 1.0 / 60.0, "time step (s)"},
           {"steps", 500, "default step count"}},
          make_chain_drop};
}

}  // namespace rbpart
