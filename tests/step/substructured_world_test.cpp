// The substructured solver inside the time step (`simulate --solver substructured`): it is the
// direct solver's Newton iteration on the substructured backend, so from the same state it gives the
// direct solver's impulses up to round-off (docs/design.md#substructured), a step from the same state
// leaves both worlds in the same state up to round-off, and the step's stats report the partition
// and the solve's work and critical path.
//
// Only steps from one shared state are compared. A trajectory is chaotic once bodies pile up: two
// runs that differ in the last bit at one step part by about tenfold every five steps, so a
// tolerance on a whole trajectory holds only on the machine (vector width, FMA) it was set on
// (issue #26). The states are taken along the direct solver's trajectory, wherever it leads; from
// each, fresh worlds with either solver take two steps (the second warm-started by the first),
// which amplify round-off at most a step's worth.
#include <gtest/gtest.h>
#include <rbpart/world.hpp>

#include <algorithm>
#include <string>

#include "core/error.hpp"
#include "scene/bodies.hpp"
#include "scenes/scenes.hpp"
#include "step/world_internals.hpp"

namespace rbpart {
namespace {

struct Case {
  const char* scene;
  std::vector<std::pair<std::string, std::string>> overrides;
  int steps;  // steps of the direct trajectory that provide start states, at most
  PartitionerKind partitioner;
  RefinerKind refiner;
  int nmax;
};

// `scene` restarted from the state `now` of its bodies: poses and velocities replaced, and joint
// anchors and hinge axes carried along with their first body from the scene's start.
SceneDef restarted(const SceneDef& scene, const Bodies& now) {
  SceneDef out = scene;
  for (int i = 0; i < now.size(); ++i) {
    BodyDef& b = out.bodies[i];
    b.position = now.frame_position(i);
    b.orientation = now.q[i];
    b.velocity = now.v[i];
    b.angular_velocity = now.w[i];
  }
  for (JointDef& j : out.joints) {
    const BodyDef& start = scene.bodies[j.body_a];
    const Quat turn = now.q[j.body_a] * start.orientation.normalized().conjugate();
    j.anchor = now.frame_position(j.body_a) + turn * (j.anchor - start.position);
    j.axis = turn * j.axis;
  }
  return out;
}

TEST(SubstructuredWorld, StepsLikeTheDirectSolver) {
  const Case cases[] = {
      {"box_stack", {}, 60, PartitionerKind::MinDp, RefinerKind::None, 3},
      {"rock_pile", {{"rocks", "20"}}, 120, PartitionerKind::Mix, RefinerKind::Fm, 6},
      {"log_tower", {{"layers", "5"}, {"drop_height", "0.02"}}, 60, PartitionerKind::Bfs, RefinerKind::Kl, 3},
      {"chain_drop", {{"links", "30"}}, 120, PartitionerKind::Mr, RefinerKind::None, 5},
  };
  constexpr int kEvery = 4;  // start states: every kEvery-th step of the trajectory
  for (const Case& c : cases) {
    SCOPED_TRACE(c.scene);
    const SceneDef scene = make_builtin_scene(c.scene, c.overrides);
    SolverParams sub;
    sub.kind = SolverKind::Substructured;
    PartitionParams partition;
    partition.partitioner = c.partitioner;
    partition.refiner = c.refiner;
    partition.nmax = c.nmax;
    World trajectory(scene);
    int interface_rows = 0, compared = 0;
    for (int step = 0; step < c.steps; ++step) {
      if (step % kEvery == 0) {
        const SceneDef start = restarted(scene, world_bodies(trajectory));
        World direct(start), split(start, StepParams{}, sub, partition);
        bool settled = true;
        for (int k = 1; k <= 2; ++k) {
          SCOPED_TRACE("from step " + std::to_string(step) + ", step " + std::to_string(k));
          const StepStats& d = direct.step();
          const StepStats& s = split.step();
          ASSERT_EQ(s.rows, d.rows);
          EXPECT_LE(s.solve.residual, d.solve.residual + 1e-9);
          EXPECT_GE(s.partition.parts, s.islands);
          // Work sums every part's time, the critical path keeps each parallel phase's slowest.
          EXPECT_GE(s.solve.work_ms, s.solve.critical_path_ms);
          interface_rows += s.partition.interface_rows;
          // An unsettled answer (the budget ran out) depends on the path taken, so the two solvers
          // part there by more than round-off.
          settled = settled && d.solve.residual <= 1e-9;
        }
        if (settled) {
          ++compared;
          // Round-off of two steps: 1e-9 of the speeds, and at least 1e-5 of one step of gravity
          // (g h) - a box face resting on four corners has a null wrench that only the sigma
          // floor tells apart, so normal impulses, and the friction boxes they set, are known
          // only to the piece's condition times the round-off, and a friction row on its box
          // carries that into the velocities (the rock pile from step 76: 3.5e-6 g h, both
          // answers at residual 2e-16). A solver error shows at the scale of g h itself.
          const Bodies& a = world_bodies(direct);
          const Bodies& b = world_bodies(split);
          double v_scale = 0, dv = 0, dx = 0;
          for (int i = 0; i < a.size(); ++i) {
            v_scale = std::max(v_scale, a.v[i].norm());
            dv = std::max({dv, (a.v[i] - b.v[i]).norm(), (a.w[i] - b.w[i]).norm()});
            dx = std::max(dx, (a.x[i] - b.x[i]).norm());
          }
          const double dv_bound = std::max(1e-9 * v_scale, 1e-5 * 9.81 * scene.dt);
          EXPECT_LE(dv, dv_bound) << "from step " << step;
          EXPECT_LE(dx, 2 * scene.dt * dv_bound) << "from step " << step;  // two steps of dv
        }
      }
      trajectory.step();
    }
    // The states had interfaces to solve.
    EXPECT_GE(compared, 3);
    EXPECT_GT(interface_rows, 0);
  }
}

TEST(SubstructuredWorld, NeedsAPartitioner) {
  SolverParams sub;
  sub.kind = SolverKind::Substructured;
  EXPECT_THROW(World(make_builtin_scene("box_pile", {{"boxes", "2"}}), StepParams{}, sub), InputError);
}

}  // namespace
}  // namespace rbpart
