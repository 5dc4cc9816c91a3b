#include "study/capture.hpp"

#include <rbpart/world.hpp>

#include <algorithm>

#include "core/timer.hpp"
#include "step/world_internals.hpp"

namespace rbpart {

namespace {

template <class T>
std::size_t bytes_of(const std::vector<T>& v) {
  return v.capacity() * sizeof(T);
}

// The bodies as the solvers see them; positions only size the set (Bodies::size()).
void copy_solver_fields(const Bodies& from, Bodies& to) {
  to.is_static = from.is_static;
  to.mass = from.mass;
  to.inv_mass = from.inv_mass;
  to.inv_inertia = from.inv_inertia;
  to.x = from.x;
}

}  // namespace

std::size_t Trajectory::bytes() const {
  std::size_t total = 0;
  for (const StepProblem& p : steps) {
    const Rows& r = p.rows;
    total += bytes_of(r.body) + bytes_of(r.jac) + bytes_of(r.q) + bytes_of(r.lo) + bytes_of(r.hi) +
             bytes_of(r.sigma) + bytes_of(r.kind) + bytes_of(r.normal_of) + bytes_of(r.mu) + bytes_of(r.key) +
             bytes_of(r.lambda) + bytes_of(r.state);
    const Bodies& b = p.bodies;
    total += bytes_of(b.is_static) + bytes_of(b.mass) + bytes_of(b.inv_mass) + bytes_of(b.inv_inertia) + bytes_of(b.x);
    total += bytes_of(p.islands.body_offset) + bytes_of(p.islands.bodies) + bytes_of(p.islands.row_offset) +
             bytes_of(p.islands.rows);
    const ConstraintGraph& g = p.graph;
    total += bytes_of(g.body_of) + bytes_of(g.node_of) + bytes_of(g.mass) + bytes_of(g.offset) +
             bytes_of(g.adjacency) + bytes_of(g.weight) + bytes_of(g.rows);
    total += bytes_of(p.live_lambda) + sizeof(StepProblem);
  }
  return total;
}

Trajectory capture_trajectory(const SceneDef& scene, int steps, int every, const StepParams& step_params,
                              const SolverParams& solver_params, const std::function<void(int)>& on_step) {
  SolverParams direct = solver_params;
  direct.kind = SolverKind::Direct;
  Trajectory trajectory;
  const Timer timer;
  {
    // The World lives only for the capture.
    World world(scene, step_params, direct, PartitionParams{});
    bool record = false;
    set_problem_observer(world, [&](const Rows& rows, const Bodies& bodies, const Islands& islands,
                                    const ConstraintGraph& graph) {
      if (!record) return;
      StepProblem& p = trajectory.steps.emplace_back();
      p.rows = rows;
      copy_solver_fields(bodies, p.bodies);
      p.islands = islands;
      p.graph = graph;
    });
    for (int s = 1; s <= steps; ++s) {
      record = s % every == 0;
      world.step();
      if (record) {
        trajectory.steps.back().step = s;
        trajectory.steps.back().live_lambda = world_rows(world).lambda;
      }
      if (on_step) on_step(s);
    }
    trajectory.simulated_steps = steps;
    trajectory.dynamic_bodies =
        static_cast<int>(std::count(world_bodies(world).is_static.begin(), world_bodies(world).is_static.end(), 0));
  }
  trajectory.capture_ms = timer.ms();
  return trajectory;
}

}  // namespace rbpart
