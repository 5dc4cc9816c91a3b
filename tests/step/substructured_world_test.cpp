// The substructured solver inside the time step (`simulate --solver substructured`): from the same state it
// gives the monolithic direct solver's impulses up to round-off (docs/design.md#substructured), so steps of a
// scene leave both worlds in the same state up to round-off, and the step's stats report the partition and
// the loop it ran. The comparison runs while the direct solver's friction loop converges (residual <= 1e-9):
// a step that ends at the pass cap is an approximate answer whose digits depend on the path taken, so the two
// runs part there by more than round-off.
#include <gtest/gtest.h>
#include <rbpart/world.hpp>

#include <algorithm>
#include <string>

#include "core/error.hpp"
#include "scene/bodies.hpp"
#include "scenes/scenes.hpp"

namespace rbpart {
namespace {

struct Case {
  const char* scene;
  std::vector<std::pair<std::string, std::string>> overrides;
  int steps;  // compared steps, at most
  PartitionerKind partitioner;
  RefinerKind refiner;
  int nmax;
};

TEST(SubstructuredWorld, StepsLikeTheDirectSolver) {
  const Case cases[] = {
      {"box_stack", {}, 60, PartitionerKind::MinDp, RefinerKind::None, 3},
      // A forming pile amplifies round-off about tenfold every five steps once rocks land (both
      // solvers exact, residuals ~1e-15): compared while that growth is still far below 1e-7.
      {"rock_pile", {{"rocks", "20"}}, 40, PartitionerKind::Mix, RefinerKind::Fm, 6},
      {"log_tower", {{"layers", "5"}, {"drop_height", "0.02"}}, 12, PartitionerKind::Bfs, RefinerKind::Kl, 3},
      {"chain_drop", {{"links", "30"}}, 20, PartitionerKind::Mr, RefinerKind::None, 5},
  };
  // Cap 100 (and 1000 halved steps) is far above what these steps need: the iteration itself, not
  // its fallback, must follow. Cap 1 makes split islands fall back, in whichever friction pass the
  // iteration first fails to settle at once: the fallback must follow just as closely.
  for (int cap : {100, 1}) {
    for (const Case& c : cases) {
      SCOPED_TRACE(std::string(c.scene) + " cap " + std::to_string(cap));
      const SceneDef scene = make_builtin_scene(c.scene, c.overrides);
      // The exact friction rule (friction_tolerance 0: passes settle only on round-off), so that
      // both solvers take the same path through the friction loop.
      SolverParams exact;
      exact.friction_tolerance = 0;
      SolverParams sub = exact;
      sub.kind = SolverKind::Substructured;
      sub.substructured_max_iterations = cap;
      if (cap == 100) sub.substructured_max_halvings = 1000;
      PartitionParams partition;
      partition.partitioner = c.partitioner;
      partition.refiner = c.refiner;
      partition.nmax = c.nmax;
      World direct(scene, StepParams{}, exact, PartitionParams{}), split(scene, StepParams{}, sub, partition);
      int interface_rows = 0, loop_iterations = 0, fallbacks = 0, compared = 0;
      for (; compared < c.steps; ++compared) {
        const StepStats& d = direct.step();
        const StepStats& s = split.step();
        ASSERT_EQ(s.rows, d.rows) << "step " << compared + 1;
        EXPECT_LE(s.residual, d.residual + 1e-9) << "step " << compared + 1;
        if (cap == 100) EXPECT_EQ(s.fallbacks, 0) << "step " << compared + 1;
        fallbacks += s.fallbacks;
        EXPECT_GE(s.parts, s.islands);
        interface_rows += s.interface_rows;
        loop_iterations += s.loop_iterations;
        if (d.residual > 1e-9) break;
      }
      // The run had interfaces to solve, and each needed at least one pass of the loop.
      EXPECT_GE(compared, 10);
      EXPECT_GT(interface_rows, 0);
      EXPECT_GT(loop_iterations, 0);
      if (cap == 1) EXPECT_GT(fallbacks, 0);
      // Same state up to the round-off that the steps amplify: 1e-7 of the speeds, and at least 1e-6
      // of one step of gravity (g h) - a box face resting on four corners has a null wrench that only
      // the sigma floor tells apart, so normal impulses, and the friction boxes they set, agree to
      // ~1e-6 relative (as in substructured_test.cpp); a friction row on its box carries that into
      // the velocities (seen: 1.3e-7 m/s on box_stack at step 60, -march=native with AVX-512).
      const Bodies& a = direct.bodies();
      const Bodies& b = split.bodies();
      double v_scale = 0, dv = 0, dx = 0;
      for (int i = 0; i < a.size(); ++i) {
        v_scale = std::max(v_scale, a.v[i].norm());
        dv = std::max({dv, (a.v[i] - b.v[i]).norm(), (a.w[i] - b.w[i]).norm()});
        dx = std::max(dx, (a.x[i] - b.x[i]).norm());
      }
      EXPECT_LE(dv, std::max(1e-7 * v_scale, 1e-6 * 9.81 * scene.dt));
      EXPECT_LE(dx, 1e-7);
    }
  }
}

TEST(SubstructuredWorld, NeedsAPartitioner) {
  SolverParams sub;
  sub.kind = SolverKind::Substructured;
  EXPECT_THROW(World(make_builtin_scene("box_pile", {{"boxes", "2"}}), StepParams{}, sub), InputError);
}

}  // namespace
}  // namespace rbpart
