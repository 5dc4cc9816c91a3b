#pragma once
// Built-in scenes, written once and shared by the CLI, tests, benchmarks and the viewer.
// Every number is a parameter with a default; the same parameters give the same scene.
#include <rbpart/scene.hpp>

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace rbpart {

struct SceneParameter {
  std::string name;
  double value;  // default
  std::string help;
};

// Parameter values by name (all defaults filled in before a generator sees them).
using SceneParameters = std::map<std::string, double>;

struct SceneInfo {
  std::string name;
  std::string description;
  std::vector<SceneParameter> parameters;
  std::function<SceneDef(const SceneParameters&)> make;
};

const std::vector<SceneInfo>& builtin_scenes();

// Throws InputError naming the first parameter outside its domain (a whole number where a count, a
// switch or a seed is meant; counts capped; physical values within src/scene/limits.hpp), or
// min_size > max_size.
void check_scene_parameters(const std::string& scene, const SceneParameters& values);

// Builds a built-in scene with `overrides` ("name" -> value text) applied over its defaults.
// Throws InputError naming an unknown scene, an unknown parameter, a non-numeric value, a value
// outside its domain (check_scene_parameters) or a body that a scene file could not hold.
SceneDef make_builtin_scene(const std::string& name,
                            const std::vector<std::pair<std::string, std::string>>& overrides = {});

// Deterministic random numbers for scene generators, identical on every platform
// (std:: distributions are implementation-defined, so they are not used).
class SceneRandom {
 public:
  explicit SceneRandom(std::uint64_t seed) : state_(seed * 0x9E3779B97F4A7C15ull + 1) {}
  double uniform(double lo, double hi);
  Vec3 unit_vector();
  Quat rotation();

 private:
  std::uint64_t next();
  std::uint64_t state_;
};

// Shared pieces of scene building.
// An empty scene with name, dt, steps and (if the scene has that parameter) friction from `p`.
SceneDef scene_base(const std::string& name, const SceneParameters& p);
// A chain of `links` capsules (parameters links, radius, half_length, mass, end_ratio) laid from
// `start` along the unit `direction`, joined end to end by ball joints; the last link is end_ratio
// times heavier; with `pinned` the first link's start is joined to the world.
void add_capsule_chain(SceneDef& scene, const SceneParameters& p, const Vec3& start, const Vec3& direction,
                       bool pinned);
// Drop position of body i on a jittered grid of cols x cols cells of `spacing`, centred on the
// origin, layers stacked upwards from height z0.
Vec3 drop_grid_position(int i, int cols, double spacing, double z0, double jitter, SceneRandom& rng);
BodyDef static_box(const std::string& name, const Vec3& center, const Vec3& half_extents,
                   const Quat& orientation = Quat::Identity());
// A floor and four walls around [-hx, hx] x [-hy, hy], walls `height` tall.
void add_bin(SceneDef& scene, double hx, double hy, double height);

// Generators (one file each under scenes/).
SceneInfo rock_pile_scene();
SceneInfo large_rock_pile_scene();
SceneInfo chain_drop_scene();
SceneInfo log_tower_scene();
SceneInfo box_pile_scene();
SceneInfo box_stack_scene();
SceneInfo slope_scene();
SceneInfo pendulum_scene();
SceneInfo hanging_chain_scene();

}  // namespace rbpart
