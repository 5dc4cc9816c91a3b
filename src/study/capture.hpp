#pragma once
// Capture: the study's trajectory, recorded once with the direct solver (issue #6).
// Every configuration of `rbpart bench` then solves these very problems (study/replay.hpp), so
// their differences come from partitioning alone, not from trajectories that drift apart.
#include <rbpart/params.hpp>
#include <rbpart/scene.hpp>

#include <cstddef>
#include <functional>
#include <vector>

#include "assembly/rows.hpp"
#include "graph/constraint_graph.hpp"
#include "graph/islands.hpp"
#include "scene/bodies.hpp"

namespace rbpart {

// One step's BLCP as the live World handed it to its solve stage (set_problem_observer, step/world_internals.hpp).
struct StepProblem {
  int step = 0;    // 1-based step number in the trajectory
  Rows rows;       // with the warm start (lambda, state) the live solve started from
  // Only the fields the solvers and the graph read: is_static, mass, inv_mass, inv_inertia (this
  // step's world inverse inertia) and x (which sizes the set); the rest is left empty.
  Bodies bodies;
  Islands islands;
  ConstraintGraph graph;
  std::vector<double> live_lambda;  // the impulses the live direct solve returned
};

struct Trajectory {
  std::vector<StepProblem> steps;  // the recorded steps, in order
  int simulated_steps = 0;
  int dynamic_bodies = 0;
  double capture_ms = 0;           // wall time of the live run, recording included
  std::size_t bytes() const;       // memory held by the recorded problems (approximate)
};

// Runs `scene` for `steps` steps with the direct solver and no partitioner, recording
// the problem of steps every, 2 every, 3 every, ... (1-based). `on_step(done)` after each step.
Trajectory capture_trajectory(const SceneDef& scene, int steps, int every, const StepParams& step_params,
                              const SolverParams& solver_params, const std::function<void(int)>& on_step = {});

}  // namespace rbpart
