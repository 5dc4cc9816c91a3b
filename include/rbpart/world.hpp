#pragma once
// A World advances a scene in time: collide -> assemble -> graph -> (partition -> refine) -> solve
// -> integrate -> project (docs/design.md#step), each stage timed into the step's profile.
#include <rbpart/params.hpp>
#include <rbpart/scene.hpp>
#include <rbpart/stats.hpp>

#include <cstdint>
#include <memory>
#include <vector>

namespace rbpart {

// Wall time of each stage of one step, named after the stage (ms).
struct StepProfile {
  double collide_ms = 0, assemble_ms = 0, graph_ms = 0, partition_ms = 0, refine_ms = 0, solve_ms = 0,
         integrate_ms = 0, project_ms = 0, total_ms = 0;
};

// Per-step statistics (docs/design.md#contracts: one CSV line per step); a stage that reports more
// than a count or two reports it in its own record (stats.hpp), held here whole.
struct StepStats {
  int step = 0;
  int bodies = 0;            // dynamic bodies
  int contacts = 0;
  int rows = 0;
  int islands = 0;
  PartitionStats partition;  // the refined partition's quality (parts = islands without a partitioner)
  SolveStats solve;
  double max_penetration = 0;  // m, deepest contact after collision
  double kinetic_energy = 0;   // J, after the step
  StepProfile profile;
};

// One body's state (docs/formats.md#state-file): the pose of its shape frame, as a BodyDef gives it,
// and the velocities of its centre of mass, all in world coordinates.
struct BodyState {
  Vec3 position = Vec3::Zero();            // of the shape frame (m)
  Quat orientation = Quat::Identity();     // unit; Eigen stores (x, y, z, w), w() is the scalar part
  Vec3 velocity = Vec3::Zero();            // of the centre of mass (m/s)
  Vec3 angular_velocity = Vec3::Zero();    // rad/s
};

// A contact point of the last step and the impulse its rows (one normal, two friction) applied
// over the step (docs/design.md#dynamics). Body b receives the opposite impulse.
struct ContactImpulse {
  int body_a = -1;             // scene body index, always dynamic
  int body_b = -1;             // scene body index, may be static
  Vec3 point = Vec3::Zero();   // world, midway between the surfaces, at the start of the step
  Vec3 normal = Vec3::UnitZ(); // world, unit, from body b into body a
  double distance = 0;         // signed separation at the start of the step (< 0: penetration, m)
  double normal_impulse = 0;   // N s along `normal` on body a, >= 0
  Vec3 friction_impulse = Vec3::Zero();  // N s on body a, tangent to the contact
  Vec3 impulse() const { return normal_impulse * normal + friction_impulse; }
};

class World {
 public:
  // With a partitioner in `partition_params` every step partitions and refines the constraint graph
  // (docs/design.md#partition, #refine) and reports the partition's quality in its stats.
  World(SceneDef scene, StepParams step_params = {}, SolverParams solver_params = {},
        PartitionParams partition_params = {});
  ~World();
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  // Advances one time step of the scene's dt.
  const StepStats& step();

  // Continues from a state instead of the scene's initial one (`rbpart simulate --initial-state`,
  // docs/formats.md#state-file): `bodies` in scene order give the dynamic bodies' states (a static
  // body's entry is not read: it keeps the scene's pose); time() becomes `time`, and step_count()
  // the number of whole steps of dt in it, round(time / dt), from which the steps' numbers continue.
  // Before the first step only (std::logic_error after). A state holds no impulses: the first step's
  // solve starts cold (no contact warm start) and without the joints' geometric stiffness, both of
  // which the step before would have left. Throws std::invalid_argument for the wrong body count,
  // a negative or non-finite time, a non-finite value or a quaternion not unit to 1e-6 (one unit to
  // 1e-12 is kept bit for bit, so that a run resumed from its own state file continues exactly).
  void restart(double time, const std::vector<BodyState>& bodies);

  double time() const;
  int step_count() const;
  const SceneDef& scene() const;
  const StepParams& step_params() const;
  const SolverParams& solver_params() const;
  const PartitionParams& partition_params() const;

  // Bodies in scene order (static ones included); `body` below is a scene index, and an index
  // outside [0, body_count()) throws std::out_of_range.
  int body_count() const;
  BodyState body_state(int body) const;
  // kg: the BodyDef's mass, or density times volume; 0 for a static body.
  double body_mass(int body) const;
  // The contacts the last step solved, sorted by (body_a, body_b, persistent id), with their
  // impulses; `out` is cleared first (reuse it to read every step without allocating).
  void contacts(std::vector<ContactImpulse>& out) const;
  std::vector<ContactImpulse> contacts() const;

  // External force (N) and torque (N m) for the next step only, added to gravity as
  // u* = u + h M^-1 (f_gravity + f) (docs/design.md#dynamics); calls add up until that step, which
  // clears them. A force at a world point also gives the torque (point - centre of mass) x force.
  // A static body takes none: std::invalid_argument.
  void apply_force(int body, const Vec3& force);
  void apply_force(int body, const Vec3& force, const Vec3& point);
  void apply_torque(int body, const Vec3& torque);

  // FNV-1a over the bit patterns of every body's state: equal hashes = identical runs.
  std::uint64_t state_hash() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  // The stages' data (bodies, rows, islands, constraint graph, partition) for the CLI, the study and
  // the tests: src/step/world_internals.hpp, not public since their types are internal.
  friend struct WorldAccess;
};

}  // namespace rbpart
