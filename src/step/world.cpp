// The step function: collide -> assemble -> graph -> (partition -> refine) -> solve -> integrate,
// one call per stage, each timed into the profile field of the same name (DESIGN.md §1).
#include <rbpart/world.hpp>

#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

#include "assembly/assemble.hpp"
#include "collision/collide.hpp"
#include "core/error.hpp"
#include "core/memory.hpp"
#include "core/timer.hpp"
#include "graph/constraint_graph.hpp"
#include "graph/islands.hpp"
#include "integrate/integrate.hpp"
#include "project/project.hpp"
#include "partition/partition.hpp"
#include "scene/bodies.hpp"
#include "scene/mass_properties.hpp"
#include "solve/island_cache.hpp"
#include "solve/newton_substructured.hpp"
#include "solve/solve.hpp"
#include "step/world_internals.hpp"

namespace rbpart {

struct World::Impl {
  SceneDef scene;
  StepParams step_params;
  SolverParams solver_params;
  PartitionParams partition_params;
  // The World's own threads, only when a count is asked for: an arena, so that another World (or
  // the embedding program) keeps its own (a tbb::global_control would cap the whole process).
  std::unique_ptr<tbb::task_arena> arena;
  Bodies bodies;
  std::vector<JointFrame> joints;
  Collider collider;
  // Per-step scratch, reused across steps.
  std::vector<Vec3> frame_position, sliding_v, sliding_w;
  std::vector<Contact> contacts;
  Rows rows;
  WarmStart warm;
  ProjectStage project;
  Islands islands;
  // The solvers' per-island analyses and buffers, step to step.
  DirectCache direct_cache;
  SubstructuredCache substructured_cache;
  ConstraintGraph graph_;
  Partition partition_;
  // The graph partition_ was made of, and whether the last step kept partition_ (its graph was that).
  ConstraintGraph partitioned_graph_;
  bool have_partitioned_graph = false, partition_kept = false;
  StepStats stats;
  int steps = 0;
  // time() - steps dt: 0 unless a restart's time is not a whole number of steps (restart).
  double time_offset = 0;
  ProblemObserver observer;  // sees each step's problem before the solve (set_problem_observer)
  // Forces and torques for the next step (World::apply_force), per body; `forced` while any is set.
  std::vector<Vec3> force, torque;
  bool forced = false;

  Impl(SceneDef s, StepParams sp, SolverParams so, PartitionParams pp)
      : scene(std::move(s)), step_params(sp), solver_params(so), partition_params(pp),
        collider(scene, sp.contact_margin), project(scene, sp.contact_margin) {
    if (solver_params.kind == SolverKind::Substructured && partition_params.partitioner == PartitionerKind::None)
      throw InputError("the substructured solver needs a partitioner (bfs, mindp, maxdp, mr, mix or metis)");
    // The Newton solver's body-space systems divide by every row's regularisation; it solves the
    // step of every solver but PGS, and every position projection.
    const bool newton_runs = solver_params.kind != SolverKind::Pgs || step_params.joint_projection_iterations > 0;
    if (newton_runs && !(step_params.sigma_floor > 0))
      throw InputError("sigma_floor must be positive: the direct solver, which also solves the position projection, "
                       "divides by every row's regularisation");
    if (solver_params.threads > 0)
      arena = std::make_unique<tbb::task_arena>(solver_params.threads);
    init_bodies();
    joints = make_joint_frames(scene, bodies);
    force.assign(bodies.size(), Vec3::Zero());
    torque.assign(bodies.size(), Vec3::Zero());
  }

  void init_bodies() {
    const std::size_t n = scene.bodies.size();
    Bodies& b = bodies;
    b.is_static.resize(n);
    b.mass.resize(n);
    b.inv_mass.resize(n);
    b.inertia_body.resize(n);
    b.inv_inertia_body.resize(n);
    b.com_local.resize(n);
    b.friction.resize(n);
    b.x.resize(n);
    b.q.resize(n);
    b.v.resize(n);
    b.w.resize(n);
    b.inv_inertia.resize(n);
    b.geometric_stiffness.assign(n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
      const BodyDef& d = scene.bodies[i];
      const MassProperties mp = mass_properties(d);
      b.is_static[i] = d.is_static;
      b.com_local[i] = mp.com;
      b.q[i] = d.orientation.normalized();
      b.x[i] = d.position + b.q[i] * mp.com;
      b.friction[i] = d.friction >= 0 ? d.friction : scene.friction;
      if (d.is_static) {
        b.mass[i] = b.inv_mass[i] = 0;
        b.inertia_body[i] = b.inv_inertia_body[i] = Mat3::Zero();
        b.v[i] = b.w[i] = Vec3::Zero();
      } else {
        b.mass[i] = mp.mass;
        b.inv_mass[i] = 1.0 / mp.mass;
        b.inertia_body[i] = mp.inertia;
        b.inv_inertia_body[i] = mp.inertia.inverse();
        b.v[i] = d.velocity;
        b.w[i] = d.angular_velocity;
      }
    }
    update_world_inertia(b);
  }

  void collide() {
    frame_position.resize(bodies.size());
    for (int i = 0; i < bodies.size(); ++i) frame_position[i] = bodies.frame_position(i);
    collider.collide(frame_position, bodies.q, bodies.v, bodies.w, scene.dt, contacts);
  }

  void assemble() {
    update_world_inertia(bodies);
    sliding_v = bodies.v;
    sliding_w = bodies.w;
    apply_external_forces(bodies, scene.gravity, scene.dt);
    if (forced) apply_applied_forces();
    assemble_rows(contacts, joints, bodies, sliding_v, sliding_w, step_params, scene.dt, warm, rows);
  }

  // The forces of World::apply_force join gravity in u*, once; then they are cleared.
  void apply_applied_forces() {
    apply_body_forces(bodies, force, torque, scene.dt);
    std::fill(force.begin(), force.end(), Vec3::Zero());
    std::fill(torque.begin(), torque.end(), Vec3::Zero());
    forced = false;
  }

  // Index `body` checked for the public accessors.
  int checked(int body) const {
    if (body < 0 || body >= bodies.size())
      throw std::out_of_range("body " + std::to_string(body) + " is not in 0.." + std::to_string(bodies.size() - 1));
    return body;
  }

  // The index of a dynamic body for apply_force and apply_torque.
  int forceable(int body) {
    if (bodies.is_static[checked(body)])
      throw std::invalid_argument("body " + std::to_string(body) + " (" + scene.bodies[body].name +
                                  ") is static and takes no force");
    forced = true;
    return body;
  }

  void graph() {
    build_islands(rows, bodies.size(), islands);
    build_constraint_graph(rows, bodies, graph_);
    if (partition_params.partitioner == PartitionerKind::None) partition_by_islands(graph_, islands, partition_);
  }

  void partition() {
    partition_graph(graph_, partition_params, partition_);
    check("partition");
  }

  void refine() {
    refine_partition(graph_, partition_params, partition_);
    check("refine");
  }

  // The partition and refine stages, skipped when the step's graph is the one partition_ was made
  // of (same_partition_input: the parts would be the same); the check and keeping the graph count
  // as partition time.
  void partition_stages(StepProfile& p) {
    {
      const Timer t;
      partition_kept = have_partitioned_graph && same_partition_input(graph_, partitioned_graph_);
      if (!partition_kept) partition();
      p.partition_ms = t.ms();
    }
    if (partition_kept) return;
    { const Timer t; refine(); p.refine_ms = t.ms(); }
    const Timer t;
    partitioned_graph_ = graph_;
    have_partitioned_graph = true;
    p.partition_ms += t.ms();
  }

  // --debug-checks: a partition breaking DESIGN.md §5's properties is an internal failure.
  void check(const char* stage) const {
    if (!partition_params.debug_checks) return;
    const std::string violation = check_partition(graph_, partition_, partition_params.nmax);
    if (!violation.empty())
      throw std::logic_error(std::string(stage) + " stage at step " + std::to_string(steps + 1) + ": " + violation);
  }

  // Solves the step's contact problem; the solver fills the stage's statistics.
  SolveStats solve() {
    switch (solver_params.kind) {
      case SolverKind::Pgs: return solve_pgs(rows, bodies, islands, solver_params);
      case SolverKind::Substructured:
        return solve_newton_substructured(rows, bodies, islands, graph_, partition_, solver_params,
                                          &substructured_cache).solve;
      case SolverKind::Direct: break;
    }
    return solve_newton_direct(rows, bodies, islands, solver_params, &direct_cache);
  }

  void integrate() {
    apply_impulses(rows, bodies);
    integrate_positions(bodies, scene.dt);
  }

  void project_positions() {
    project.run(joints, stats.solve.unsettled > 0, scene.dt, bodies, step_params, solver_params);
  }

  // The project stage runs after a step only on a turn, joints or an unsettled solve; a settled
  // step can still bring a corner its contact points did not guard (a box spun up by an impact
  // within the step) deeper than projection_depth. The step after finds it, projects it out before
  // its solve and collides again; returns whether it did. PGS, never settled, stays the plain
  // baseline, as after its steps.
  bool project_deep_contacts() {
    if (solver_params.kind == SolverKind::Pgs || !(deepest_penetration(contacts) > step_params.projection_depth))
      return false;
    if (!project.run(joints, true, scene.dt, bodies, step_params, solver_params)) return false;
    collide();
    return true;
  }

  // What the next step takes from this one: the joints' geometric stiffness (after the project
  // stage, whose mass metric has this step's) and the warm starts.
  void keep_for_next_step() {
    update_geometric_stiffness(rows, bodies, scene.dt);
    warm.store(rows);
  }

  void restart(double time, const std::vector<BodyState>& states) {
    if (stats.step > 0) throw std::logic_error("World::restart after the first step");
    if (states.size() != scene.bodies.size())
      throw std::invalid_argument("World::restart: " + std::to_string(states.size()) + " body states for " +
                                  std::to_string(scene.bodies.size()) + " bodies");
    const double whole = std::round(time / scene.dt);
    if (!(time >= 0) || !(whole <= std::numeric_limits<int>::max()))
      throw std::invalid_argument("World::restart: time " + std::to_string(time) + " is not in [0, INT_MAX dt]");
    for (std::size_t i = 0; i < states.size(); ++i) {
      const BodyState& s = states[i];
      const double norm = s.orientation.norm();
      if (!s.position.allFinite() || !s.velocity.allFinite() || !s.angular_velocity.allFinite() ||
          !(std::abs(norm - 1) <= 1e-6))
        throw std::invalid_argument("World::restart: body " + std::to_string(i) + " (" + scene.bodies[i].name +
                                    "): a non-finite value or a quaternion that is not unit");
    }
    for (int i = 0; i < bodies.size(); ++i) {
      if (bodies.is_static[i]) continue;
      const BodyState& s = states[i];
      bodies.q[i] = std::abs(s.orientation.norm() - 1) <= 1e-12 ? s.orientation : s.orientation.normalized();
      bodies.x[i] = s.position + bodies.q[i] * bodies.com_local[i];
      bodies.v[i] = s.velocity;
      bodies.w[i] = s.angular_velocity;
    }
    update_world_inertia(bodies);
    steps = static_cast<int>(whole);
    time_offset = time - steps * scene.dt;
  }

  double kinetic_energy() const {
    double e = 0;
    for (int i = 0; i < bodies.size(); ++i) {
      if (bodies.is_static[i]) continue;
      const Mat3 R = bodies.q[i].toRotationMatrix();
      const Vec3 wb = R.transpose() * bodies.w[i];
      e += 0.5 * bodies.mass[i] * bodies.v[i].squaredNorm() + 0.5 * wb.dot(bodies.inertia_body[i] * wb);
    }
    return e;
  }

  const StepStats& step() {
    StepStats& s = stats;
    StepProfile& p = s.profile;
    const Timer total;
    { const Timer t; collide(); p.collide_ms = t.ms(); }
    { const Timer t; p.project_ms = project_deep_contacts() ? t.ms() : 0; }
    { const Timer t; assemble(); p.assemble_ms = t.ms(); }
    { const Timer t; graph(); p.graph_ms = t.ms(); }
    p.partition_ms = p.refine_ms = 0;  // without a partitioner the parts are the islands (graph stage)
    const bool partitioned = partition_params.partitioner != PartitionerKind::None;
    if (partitioned) partition_stages(p);
    if (observer) observer(rows, bodies, islands, graph_);
    { const Timer t; s.solve = solve(); p.solve_ms = t.ms(); }
    { const Timer t; integrate(); p.integrate_ms = t.ms(); }
    { const Timer t; project_positions(); p.project_ms += t.ms(); }
    { const Timer t; keep_for_next_step(); p.integrate_ms += t.ms(); }
    p.total_ms = total.ms();

    ++steps;
    // A non-finite state is an internal failure: stop rather than write NaN anywhere.
    for (int i = 0; i < bodies.size(); ++i)
      if (!bodies.x[i].allFinite() || !bodies.v[i].allFinite() || !bodies.w[i].allFinite() ||
          !bodies.q[i].coeffs().allFinite())
        throw std::runtime_error("non-finite state of body " + std::to_string(i) + " at step " +
                                 std::to_string(steps));
    s.step = steps;
    s.bodies = static_cast<int>(std::count(bodies.is_static.begin(), bodies.is_static.end(), 0));
    s.contacts = static_cast<int>(contacts.size());
    s.rows = static_cast<int>(rows.size());
    s.islands = static_cast<int>(islands.count());
    // Without a partitioner the parts are the islands, with no interface.
    s.partition = partitioned ? measure_partition(graph_, partition_) : PartitionStats{s.islands};
    s.max_penetration = deepest_penetration(contacts);
    s.kinetic_energy = kinetic_energy();
    // Nor is a step that ends finite but with a non-finite residual or energy a success to report.
    if (!std::isfinite(s.solve.residual) || !std::isfinite(s.kinetic_energy))
      throw std::runtime_error("non-finite BLCP residual or kinetic energy at step " + std::to_string(steps));
    return s;
  }
};

World::World(SceneDef scene, StepParams step_params, SolverParams solver_params, PartitionParams partition_params)
    : impl_(std::make_unique<Impl>(std::move(scene), step_params, solver_params, partition_params)) {
  keep_freed_memory();
}
World::~World() = default;

const StepStats& World::step() {
  if (!impl_->arena) return impl_->step();
  const StepStats* stats = nullptr;
  impl_->arena->execute([&] { stats = &impl_->step(); });
  return *stats;
}
void World::restart(double time, const std::vector<BodyState>& bodies) { impl_->restart(time, bodies); }
double World::time() const { return impl_->steps * impl_->scene.dt + impl_->time_offset; }
int World::step_count() const { return impl_->steps; }
const SceneDef& World::scene() const { return impl_->scene; }
const StepParams& World::step_params() const { return impl_->step_params; }
const SolverParams& World::solver_params() const { return impl_->solver_params; }
const PartitionParams& World::partition_params() const { return impl_->partition_params; }

int World::body_count() const { return impl_->bodies.size(); }
double World::body_mass(int body) const { return impl_->bodies.mass[impl_->checked(body)]; }

BodyState World::body_state(int body) const {
  const Bodies& b = impl_->bodies;
  const int i = impl_->checked(body);
  return {b.frame_position(i), b.q[i], b.v[i], b.w[i]};
}

// A contact's rows are three consecutive rows from 3k (assemble_rows: normal, then two friction); the
// impulse each row puts on body a is lambda times its Jacobian's linear block for a (slot 0).
void World::contacts(std::vector<ContactImpulse>& out) const {
  const Rows& rows = impl_->rows;
  out.clear();
  for (std::size_t k = 0; k < impl_->contacts.size(); ++k) {
    const Contact& c = impl_->contacts[k];
    const std::size_t r = 3 * k;
    if (r + 2 >= rows.size() || rows.key[r] != contact_row_key(c.id, 0))
      throw std::logic_error("contact " + std::to_string(k) + " has no rows of its own");
    ContactImpulse& ci = out.emplace_back();
    ci.body_a = c.body_a;
    ci.body_b = c.body_b;
    ci.point = c.point;
    ci.normal = c.normal;
    ci.distance = c.distance;
    ci.normal_impulse = rows.lambda[r];
    ci.friction_impulse =
        rows.lambda[r + 1] * rows.jac[r + 1][0].head<3>() + rows.lambda[r + 2] * rows.jac[r + 2][0].head<3>();
  }
}

std::vector<ContactImpulse> World::contacts() const {
  std::vector<ContactImpulse> out;
  contacts(out);
  return out;
}

void World::apply_force(int body, const Vec3& force) { impl_->force[impl_->forceable(body)] += force; }

void World::apply_force(int body, const Vec3& force, const Vec3& point) {
  const int i = impl_->forceable(body);
  impl_->force[i] += force;
  impl_->torque[i] += (point - impl_->bodies.x[i]).cross(force);
}

void World::apply_torque(int body, const Vec3& torque) { impl_->torque[impl_->forceable(body)] += torque; }

// The internal accessors (world_internals.hpp) reach the Impl through this friend of World.
struct WorldAccess {
  static World::Impl& impl(const World& world) { return *world.impl_; }
};

const Bodies& world_bodies(const World& world) { return WorldAccess::impl(world).bodies; }
const Rows& world_rows(const World& world) { return WorldAccess::impl(world).rows; }
const Islands& world_islands(const World& world) { return WorldAccess::impl(world).islands; }
const ConstraintGraph& world_graph(const World& world) { return WorldAccess::impl(world).graph_; }
const Partition& world_partition(const World& world) { return WorldAccess::impl(world).partition_; }
bool world_partition_kept(const World& world) { return WorldAccess::impl(world).partition_kept; }
void set_problem_observer(World& world, ProblemObserver observer) {
  WorldAccess::impl(world).observer = std::move(observer);
}

std::uint64_t World::state_hash() const {
  std::uint64_t h = 1469598103934665603ull;
  auto mix = [&h](const double* p, int n) {
    for (int i = 0; i < n; ++i) {
      std::uint64_t bits;
      std::memcpy(&bits, p + i, sizeof bits);
      for (int byte = 0; byte < 8; ++byte) {
        h ^= (bits >> (8 * byte)) & 0xff;
        h *= 1099511628211ull;
      }
    }
  };
  const Bodies& b = impl_->bodies;
  for (int i = 0; i < b.size(); ++i) {
    mix(b.x[i].data(), 3);
    mix(b.q[i].coeffs().data(), 4);
    mix(b.v[i].data(), 3);
    mix(b.w[i].data(), 3);
  }
  return h;
}

}  // namespace rbpart
