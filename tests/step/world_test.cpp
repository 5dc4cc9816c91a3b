// What a World refuses to be built with (src/step/world.cpp): parameters its solvers cannot use.
#include <gtest/gtest.h>
#include <rbpart/world.hpp>

#include "core/error.hpp"
#include "scenes/scenes.hpp"

namespace rbpart {
namespace {

// The Newton solver divides by every row's regularisation. It solves the step of the direct and
// the substructured solver, and every position projection, so only PGS without projection runs
// unregularised rows.
TEST(World, NeedsARegularisationFloorWhereTheNewtonSolverRuns) {
  const SceneDef scene = make_builtin_scene("box_stack", {{"boxes", "2"}});
  StepParams unregularised;
  unregularised.sigma_floor = 0;
  SolverParams pgs;
  pgs.kind = SolverKind::Pgs;
  EXPECT_THROW(World(scene, unregularised), InputError);
  EXPECT_THROW(World(scene, unregularised, pgs), InputError);
  unregularised.joint_projection_iterations = 0;
  World plain(scene, unregularised, pgs);
  EXPECT_NO_THROW(plain.step());
}

}  // namespace
}  // namespace rbpart
