#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <stdexcept>
#include <string>

#include "core/error.hpp"
#include "io/scene_json.hpp"
#include "io/text_format.hpp"
#include "scene/limits.hpp"
#include "scene/mass_properties.hpp"
#include "scenes/scenes.hpp"

namespace rbpart {

namespace {

// What a parameter may be, by name: a name means the same in every scene. Counts and switches are
// whole numbers (a seed of 1.5 or boxes=-5 would otherwise be truncated or clamped silently), counts
// are capped so that a scene fits in memory, and physical values are kept where the scene-file
// checks keep them (limits.hpp).
struct Domain {
  double lo, hi;
  bool lo_open;  // (lo, hi] rather than [lo, hi]
  bool whole;
};

const Domain* domain_of(const std::string& name) {
  using namespace limits;
  static const Domain count{1, kMaxCount, false, true}, small_count{1, 100, false, true},
      points{4, 100, false, true}, flag{0, 1, false, true}, seed{0, 9007199254740992.0, false, true},
      steps{1, 2147483647.0, false, true}, dt{0, kMaxDt, true, false}, length{0, kMaxLength, true, false},
      height{0, kMaxLength, false, false}, mass{kMinMass, kMaxMass, false, false},
      density{0, kMaxMass, true, false}, ratio{0, kMaxMass, true, false}, friction{0, 1e3, false, false},
      angle{-360, 360, false, false}, fraction{0, 1, false, false};
  static const std::map<std::string, const Domain*> table = {
      {"rocks", &count}, {"boxes", &count}, {"links", &count}, {"layers", &small_count}, {"logs", &small_count},
      {"points", &points}, {"seed", &seed}, {"steps", &steps}, {"mass_ratio_set", &flag}, {"round", &flag},
      {"dt", &dt}, {"friction", &friction}, {"min_size", &length}, {"max_size", &length}, {"size", &length},
      {"radius", &length}, {"half_length", &length}, {"bar_radius", &length}, {"block_size", &length},
      {"length", &length}, {"height", &height}, {"bar_height", &height}, {"drop_height", &height},
      {"mass", &mass}, {"mass_even", &mass}, {"mass_odd", &mass}, {"density", &density},
      {"end_ratio", &ratio}, {"block_ratio", &ratio}, {"angle", &angle}, {"bar_at", &fraction}};
  const auto it = table.find(name);
  return it == table.end() ? nullptr : it->second;
}

// Throws InputError "scene <scene>: parameter '<name>' must ..." unless `value` lies in its domain.
void check_parameter(const std::string& scene, const std::string& name, double value, const std::string& text) {
  const Domain* d = domain_of(name);
  if (!d) throw std::logic_error("scene " + scene + ": parameter '" + name + "' has no domain in scenes.cpp");
  const bool inside = (d->lo_open ? value > d->lo : value >= d->lo) && value <= d->hi &&
                      (!d->whole || value == std::floor(value));
  if (inside) return;
  throw InputError("scene " + scene + ": parameter '" + name + "' must be " + (d->whole ? "a whole number " : "") +
                   "in " + (d->lo_open ? "(" : "[") + round_trip(d->lo) + ", " + round_trip(d->hi) + "] (got " + text + ")");
}

}  // namespace

void check_scene_parameters(const std::string& scene, const SceneParameters& values) {
  for (const auto& [name, value] : values) check_parameter(scene, name, value, round_trip(value));
  if (values.count("min_size") && values.count("max_size") && values.at("min_size") > values.at("max_size"))
    throw InputError("scene " + scene + ": parameter 'min_size' (" + round_trip(values.at("min_size")) +
                     ") must not exceed 'max_size' (" + round_trip(values.at("max_size")) + ")");
}

const std::vector<SceneInfo>& builtin_scenes() {
  static const std::vector<SceneInfo> scenes = {
      // The paper's scenes (docs/design.md#scenes).
      chain_drop_scene(), log_tower_scene(), rock_pile_scene(), large_rock_pile_scene(),
      // Benchmark and analytic scenes.
      box_pile_scene(), box_stack_scene(), slope_scene(), pendulum_scene(), hanging_chain_scene()};
  return scenes;
}

SceneDef make_builtin_scene(const std::string& name,
                            const std::vector<std::pair<std::string, std::string>>& overrides) {
  for (const SceneInfo& info : builtin_scenes()) {
    if (info.name != name) continue;
    SceneParameters values;
    for (const SceneParameter& p : info.parameters) values[p.name] = p.value;
    for (const auto& [key, text] : overrides) {
      if (!values.count(key)) throw InputError("scene " + name + ": unknown parameter '" + key + "'");
      char* end = nullptr;
      const double v = std::strtod(text.c_str(), &end);
      if (text.empty() || *end != '\0' || !std::isfinite(v))
        throw InputError("scene " + name + ": parameter '" + key + "' needs a finite number (got '" + text + "')");
      check_parameter(name, key, v, text);
      values[key] = v;
    }
    check_scene_parameters(name, values);
    SceneDef scene = info.make(values);
    // The bodies pass the checks a scene file's bodies pass (sizes, masses, hull volume).
    for (const BodyDef& body : scene.bodies) {
      try {
        mass_properties(body);
      } catch (const InputError& error) {
        throw InputError("scene " + name + ": " + error.what());
      }
    }
    return scene;
  }
  throw InputError("unknown scene '" + name + "' (rbpart scenes lists the built-ins)");
}

std::vector<std::string> builtin_scene_names() {
  std::vector<std::string> names;
  for (const SceneInfo& info : builtin_scenes()) names.push_back(info.name);
  return names;
}

SceneDef load_scene(const std::string& scene, const std::vector<std::pair<std::string, std::string>>& parameters) {
  for (const SceneInfo& info : builtin_scenes())
    if (info.name == scene) return make_builtin_scene(scene, parameters);
  if (!parameters.empty())
    throw InputError("scene parameters apply to built-in scenes only, not to the file '" + scene + "'");
  if (!std::ifstream(scene))
    throw InputError("scene '" + scene + "': neither a built-in scene (rbpart scenes) nor a readable file");
  return load_scene_file(scene);
}

std::uint64_t SceneRandom::next() {
  // splitmix64: tiny, fast and good enough for scene jitter.
  std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

double SceneRandom::uniform(double lo, double hi) {
  return lo + (hi - lo) * (static_cast<double>(next() >> 11) * 0x1.0p-53);
}

Vec3 SceneRandom::unit_vector() {
  const double z = uniform(-1, 1), phi = uniform(0, 2 * M_PI), s = std::sqrt(1 - z * z);
  return {s * std::cos(phi), s * std::sin(phi), z};
}

Quat SceneRandom::rotation() {
  Quat q(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
  while (q.squaredNorm() < 1e-6 || q.squaredNorm() > 1) q = Quat(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
  return q.normalized();
}

BodyDef static_box(const std::string& name, const Vec3& center, const Vec3& half_extents, const Quat& orientation) {
  BodyDef b;
  b.name = name;
  b.is_static = true;
  b.shape.type = ShapeType::Box;
  b.shape.half_extents = half_extents;
  b.position = center;
  b.orientation = orientation;
  b.density = 1;  // unused for static bodies, keeps the definition valid
  return b;
}

SceneDef scene_base(const std::string& name, const SceneParameters& p) {
  SceneDef scene;
  scene.name = name;
  scene.dt = p.at("dt");
  scene.steps = static_cast<int>(p.at("steps"));
  if (p.count("friction")) scene.friction = p.at("friction");
  return scene;
}

void add_capsule_chain(SceneDef& scene, const SceneParameters& p, const Vec3& start, const Vec3& direction,
                       bool pinned) {
  const int n = std::max(1, static_cast<int>(p.at("links")));
  const double r = p.at("radius"), half = p.at("half_length"), pitch = 2 * (half + r);
  const Quat along = Quat::FromTwoVectors(Vec3::UnitZ(), direction);
  const int first = static_cast<int>(scene.bodies.size());
  for (int i = 0; i < n; ++i) {
    BodyDef b;
    b.name = "link" + std::to_string(i);
    b.shape.type = ShapeType::Capsule;
    b.shape.radius = r;
    b.shape.half_length = half;
    b.mass = i == n - 1 ? p.at("mass") * p.at("end_ratio") : p.at("mass");
    b.position = start + (i + 0.5) * pitch * direction;
    b.orientation = along;
    scene.bodies.push_back(std::move(b));
    if (i == 0 && !pinned) continue;
    JointDef j;
    j.type = JointType::Ball;
    j.body_a = first + i;
    j.body_b = i == 0 ? -1 : first + i - 1;
    j.anchor = start + i * pitch * direction;
    scene.joints.push_back(j);
  }
}

Vec3 drop_grid_position(int i, int cols, double spacing, double z0, double jitter, SceneRandom& rng) {
  const int layer = i / (cols * cols), cell = i % (cols * cols);
  const double half = 0.5 * cols * spacing;
  const double x = -half + (cell % cols + 0.5) * spacing + rng.uniform(-jitter, jitter);
  const double y = -half + (cell / cols + 0.5) * spacing + rng.uniform(-jitter, jitter);
  return {x, y, z0 + layer * spacing};
}

void add_bin(SceneDef& scene, double hx, double hy, double height) {
  const double t = 0.1;      // wall thickness
  const double apron = 2.0;  // floor beyond the walls: a body thrown over a wall lands and stays
  scene.bodies.push_back(static_box("floor", {0, 0, -t}, {hx + 2 * t + apron, hy + 2 * t + apron, t}));
  scene.bodies.push_back(static_box("wall_x-", {-hx - t, 0, height / 2}, {t, hy + 2 * t, height / 2}));
  scene.bodies.push_back(static_box("wall_x+", {hx + t, 0, height / 2}, {t, hy + 2 * t, height / 2}));
  scene.bodies.push_back(static_box("wall_y-", {0, -hy - t, height / 2}, {hx, t, height / 2}));
  scene.bodies.push_back(static_box("wall_y+", {0, hy + t, height / 2}, {hx, t, height / 2}));
}

}  // namespace rbpart
