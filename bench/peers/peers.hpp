// The peers' harness: one scene file, one engine and solver at a time, printing per step the same
// columns as `rbpart simulate --stats` (docs/formats.md), so that bench/peers/run_peers.py reads
// rbpart and its peers with one parser.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace peers {

using Vec3 = std::array<double, 3>;
using Quat = std::array<double, 4>;  // w, x, y, z, as in scene files
using Mat3 = std::array<Vec3, 3>;    // rows

enum class ShapeType { box, sphere, capsule };

struct Shape {
  ShapeType type = ShapeType::box;
  Vec3 half_extents{};      // box
  double radius = 0;        // sphere, capsule
  double half_length = 0;   // capsule: half the cylinder, axis along the frame's z
};

// A body of the scene file. The shapes used here have their centre of mass at the frame's origin
// and their principal axes along the frame's axes, so `inertia` is diagonal in the shape frame.
struct Body {
  std::string name;
  bool is_static = false;
  Shape shape;
  double mass = 0;
  Vec3 inertia{};
  Vec3 position{};
  Quat orientation{1, 0, 0, 0};
  Vec3 velocity{};
  Vec3 angular_velocity{};  // world axes
  double friction = 0.5;
};

struct Joint {  // ball joints only: the anchors coincide
  int a = -1, b = -1;  // b = -1: the world
  Vec3 anchor{};       // world, at the start
};

struct Scene {
  std::string name;
  Vec3 gravity{0, 0, -9.81};
  double dt = 1.0 / 60.0;
  int steps = 500;
  std::vector<Body> bodies;
  std::vector<Joint> joints;
};

// Strict enough for the scenes rbpart exports; throws std::runtime_error naming what it cannot do.
Scene load_scene(const std::string& path);
// The pair friction of rbpart: sqrt(mu_a mu_b).
double pair_friction(const Body& a, const Body& b);

struct BodyState {
  Vec3 position{};
  Quat orientation{1, 0, 0, 0};
  Vec3 velocity{};
  Vec3 angular_velocity{};  // world axes
};

// rbpart's state-file layout (docs/formats.md#state-file), so one reader serves every engine.
void write_state(const std::string& path, const Scene& scene, const std::vector<BodyState>& state,
                 double time);
std::vector<BodyState> read_state(const std::string& path, const Scene& scene);

// One row of an engine's own contact problem as the engine left it: impulse lambda, the row's
// diagonal a_jj of its matrix A, its free term q_j (w = A lambda + q), and the natural map's inner
// point lambda_j - w_j / a_jj, bounds evaluated at the returned normal impulses (docs/design.md,
// contact problem). Nodes are dynamic bodies (or trees), -1 for the static world.
struct Row {
  int node_a = -1, node_b = -1;
  double lambda = 0, a_jj = 0, q = 0, inner = 0, lo = 0, hi = 0;
};
// max over islands of  max_j a_jj |lambda_j - mid(lo_j, inner_j, hi_j)| / max_j |q_j|.
double natural_map_residual(const std::vector<Row>& rows, int nodes);

struct StepReport {
  double total_ms = 0, solve_ms = 0;
  int contacts = 0;
  double max_penetration = 0;  // m, the deepest contact the engine's collision found this step
  double blcp_residual = -1;   // < 0: not measured
};

class Engine {
 public:
  virtual ~Engine() = default;
  virtual StepReport step() = 0;
  virtual std::vector<BodyState> state() const = 0;  // every body of the scene, in scene order
  // Every solver and contact setting the engine runs with, read back from the engine, as one JSON
  // object (written into the results by run_peers.py).
  virtual std::string settings_json() const = 0;
};

std::unique_ptr<Engine> make_ode(const Scene&, const std::string& solver, bool residual);
std::unique_ptr<Engine> make_bullet(const Scene&, const std::string& solver, bool residual);
// memory_gib: what MuJoCo 2.2 may allocate up front for its constraint arrays (it sizes them for
// njmax rows, efc_AR as njmax x njmax).
std::unique_ptr<Engine> make_mujoco(const Scene&, const std::string& solver, bool residual, double memory_gib);

// End-of-run measures, the same for every engine and for rbpart's own state files.
struct EndMeasures {
  double kinetic_energy = 0;      // J
  double max_point_speed = 0;     // m/s: max over bodies of |v| + |omega| * bounding radius
  double penetration = -1;        // m, one detector for every engine (< 0: not available)
};
EndMeasures measure_state(const Scene& scene, const std::vector<BodyState>& state);

// Small vector algebra shared by the adapters.
inline Vec3 add(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline Vec3 scale(const Vec3& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
inline double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Mat3 rotation(const Quat& q);
Vec3 mul(const Mat3& m, const Vec3& v);
Vec3 mul_transposed(const Mat3& m, const Vec3& v);
Quat conjugate_times(const Quat& a, const Quat& b);  // a^-1 b
// R diag(d) R^T applied to v, and its inverse: the world inertia of a body turned by R.
Vec3 world_inertia_times(const Mat3& r, const Vec3& diag, const Vec3& v);
Vec3 world_inverse_inertia_times(const Mat3& r, const Vec3& diag, const Vec3& v);
double bounding_radius(const Shape& s);
// A number for the settings' JSON, which has no infinity: "inf" (a string) for one.
std::string json_number(double value);

}  // namespace peers
