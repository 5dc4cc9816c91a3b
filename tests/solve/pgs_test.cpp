// PGS (solve/pgs.cpp), the iterative baseline, against the direct solver's answer on two boxes
// resting and sliding on the ground (box_scenes.hpp): it approaches it as its sweeps grow, its
// residual is the one of DESIGN.md §3, and its index sets follow its impulses.
#include "solve/solve.hpp"

#include "solve/box_scenes.hpp"
#include "solve/newton.hpp"

#include <gtest/gtest.h>

#include <limits>

namespace rbpart {
namespace {

using namespace rbpart::testing;

TEST(SolvePgs, ApproachesTheDirectAnswerAsSweepsGrow) {
  Scene s;
  add_box(s, 2.0, 0.5, 0.0, 0.5);
  add_box(s, 5.0, 0.3, 1.0, 0.6);
  finish(s);
  Scene direct = s;
  ASSERT_LE(solve_newton_direct(direct.rows, direct.bodies, direct.islands, SolverParams{}).residual,
            kSettledResidual);

  double previous_error = std::numeric_limits<double>::infinity(), previous_residual = previous_error;
  for (int sweeps : {3, 30, 300, 3000}) {
    Scene pgs = s;
    SolverParams params;
    params.kind = SolverKind::Pgs;
    params.pgs_iterations = sweeps;
    params.pgs_tolerance = 0;
    const SolveStats report = solve_pgs(pgs.rows, pgs.bodies, pgs.islands, params);
    EXPECT_EQ(report.iterations, 2 * sweeps);  // two islands
    double error = 0;
    for (int b = 0; b < 2; ++b) error = std::max(error, (velocity_after(pgs, b) - velocity_after(direct, b)).norm());
    EXPECT_LT(error, previous_error) << sweeps;
    EXPECT_LT(report.residual, previous_residual) << sweeps;
    EXPECT_NEAR(report.residual, natural_map_residual(pgs.rows, pgs.bodies, pgs.islands), 1e-12);
    previous_error = error;
    previous_residual = report.residual;
    // The sets follow lambda: clamped rows sit on their bounds.
    for (std::size_t j = 0; j < pgs.rows.size(); ++j) {
      if (pgs.rows.state[j] == RowState::Lower) EXPECT_EQ(pgs.rows.lambda[j], pgs.rows.lo[j]);
      if (pgs.rows.state[j] == RowState::Upper) EXPECT_EQ(pgs.rows.lambda[j], pgs.rows.hi[j]);
    }
  }
  EXPECT_LT(previous_error, 1e-6);
  // The tolerance stops the sweeps early once the impulses settle.
  Scene pgs = s;
  SolverParams params;
  params.pgs_iterations = 100000;
  params.pgs_tolerance = 1e-6;
  const SolveStats report = solve_pgs(pgs.rows, pgs.bodies, pgs.islands, params);
  EXPECT_LT(report.iterations, 2 * 100000);
  EXPECT_GT(report.iterations, 2);
}

}  // namespace
}  // namespace rbpart
