// solve_direct, solve_pgs and natural_map_residual on small scenes built by hand: boxes resting
// and sliding on the ground (DESIGN.md §2 rows), with analytic answers where symmetry gives them.
#include "solve/solve.hpp"

#include "graph/islands.hpp"
#include "solve/blcp.hpp"
#include "solve/dense_matrix.hpp"
#include "solve/island_system.hpp"
#include "solve/residual.hpp"
#include "solve/box_scenes.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace rbpart {
namespace {

using namespace rbpart::testing;


SolverParams exact_params() {
  SolverParams p;
  p.friction_passes = 50;
  p.friction_tolerance = 1e-13;
  return p;
}

TEST(SolveDirect, RestingBoxHasTheSymmetricAnalyticImpulses) {
  Scene s;
  add_box(s, 2.0, 0.5, 0.0, 0.5);
  finish(s);
  const SolveReport report = solve_direct(s.rows, s.bodies, s.islands, exact_params());
  EXPECT_EQ(report.failures, 0);
  EXPECT_LE(report.residual, 1e-10);
  // By symmetry each corner carries a quarter: -g h + 4 lambda / m + sigma lambda = 0, no friction.
  const double sigma = s.rows.sigma[0];
  const double expected = kGravity * kStep / (4 / 2.0 + sigma);
  // Twelve rows on six velocities: A is conditioned ~ 1 / sigma_floor = 1e6, so impulses are exact
  // to ~1e-10 relative.
  for (std::size_t j = 0; j < s.rows.size(); ++j) {
    if (s.rows.kind[j] == RowKind::Normal) {
      EXPECT_NEAR(s.rows.lambda[j], expected, 1e-9 * expected);
      EXPECT_EQ(s.rows.state[j], RowState::Free);
    } else {
      EXPECT_NEAR(s.rows.lambda[j], 0.0, 1e-9 * expected);
    }
  }
  EXPECT_LE(velocity_after(s, 0).norm(), 1e-6 * kGravity * kStep);
}

TEST(SolveDirect, SlidingBoxFeelsCoulombFrictionOnEveryContact) {
  Scene s;
  const double m = 3.0, mu = 0.3;
  add_box(s, m, 0.4, 2.0, mu);  // too fast to stop within one step: friction saturates
  finish(s);
  const SolveReport report = solve_direct(s.rows, s.bodies, s.islands, exact_params());
  EXPECT_EQ(report.failures, 0);
  EXPECT_LE(report.residual, 1e-10);
  // From a zero warm start the first pass has closed friction boxes; the coupled pivoting then ties
  // the sliding rows to their normals and finishes without a second pass.
  EXPECT_EQ(report.friction_passes, 1);
  double normal = 0, friction_x = 0;
  for (std::size_t j = 0; j < s.rows.size(); ++j) {
    if (s.rows.kind[j] == RowKind::Normal) {
      normal += s.rows.lambda[j];
      EXPECT_GT(s.rows.lambda[j], 0.0);
    } else if (s.rows.jac[j][0][0] == 1.0) {  // along x: at the lower bound -mu lambda_n
      const double bound = mu * s.rows.lambda[s.rows.normal_of[j]];
      EXPECT_EQ(s.rows.state[j], RowState::Lower);
      EXPECT_NEAR(s.rows.lambda[j], -bound, 1e-12 * bound);
      friction_x += s.rows.lambda[j];
    } else {
      EXPECT_NEAR(s.rows.lambda[j], 0.0, 1e-9);
    }
  }
  // No vertical motion after the step: the normals carry the weight's impulse (up to sigma).
  EXPECT_NEAR(normal, m * kGravity * kStep, 1e-5 * m * kGravity * kStep);
  EXPECT_NEAR(friction_x, -mu * normal, 1e-12 * normal);
  EXPECT_NEAR(velocity_after(s, 0)[0], 2.0 + friction_x / m, 1e-12);
}

// Two independent islands solved together, by the dense and the sparse (body-space) paths, which
// must agree; the report's residual is the one natural_map_residual measures.
TEST(SolveDirect, TwoIslandsDenseAndSparsePathsAgree) {
  Scene s;
  add_box(s, 2.0, 0.5, 0.0, 0.5);
  add_box(s, 5.0, 0.3, 1.0, 0.6);
  finish(s);
  ASSERT_EQ(s.islands.count(), 2u);
  Rows sparse_rows = s.rows;
  SolverParams params = exact_params();
  const SolveReport dense = solve_direct(s.rows, s.bodies, s.islands, params);
  params.dense_max_rows = 0;
  const SolveReport sparse = solve_direct(sparse_rows, s.bodies, s.islands, params);
  EXPECT_EQ(dense.failures + sparse.failures, 0);
  EXPECT_LE(dense.residual, 1e-10);
  EXPECT_LE(sparse.residual, 1e-10);
  EXPECT_NEAR(natural_map_residual(s.rows, s.bodies, s.islands), dense.residual, 1e-14);
  for (std::size_t j = 0; j < s.rows.size(); ++j) {
    EXPECT_NEAR(sparse_rows.lambda[j], s.rows.lambda[j], 1e-9 * std::max(1.0, std::abs(s.rows.lambda[j])));
    EXPECT_EQ(sparse_rows.state[j], s.rows.state[j]);
  }
  // Warm started from its own answer, the solve is one pivoting iteration per pass.
  const SolveReport again = solve_direct(s.rows, s.bodies, s.islands, exact_params());
  EXPECT_LE(again.iterations, 2 * again.friction_passes);
  EXPECT_LE(again.residual, 1e-10);
}

// A heavy box sliding and spinning face-down on a box that rests on the ground: eight redundant
// contact points whose load shares move with the friction's moments. Fed back pass by pass (the
// lagged loop, damped), the per-point friction bounds keep shifting the shares and the loop only
// creeps towards the fixed point: after the default number of passes it is far from it. The
// coupled pivoting (friction tied to its own normal) solves the coupled BLCP exactly at once.
TEST(FrictionPasses, CoupledPivotingSolvesARedundantStackTheLaggedLoopDoesNot) {
  Scene s;
  const double m_top = 10.0, mu_top = 0.4, a = 0.5;
  add_box(s, 5.0, a, 0.0, 0.8);
  add_box_on(s, 0, m_top, a, 1.5, mu_top, 0.0, 1.0);
  finish(s);
  ASSERT_EQ(s.islands.count(), 1u);
  const std::vector<int> local_row = local_row_index(s.rows, s.islands);
  IslandSystem sys;
  sys.gather(s.rows, s.bodies, s.islands, 0, local_row);
  DenseBlcpMatrix matrix;
  build_dense(sys, matrix.matrix());
  matrix.finalize();
  // The scaled residual with the friction bounds of lambda's own normal impulses, w from A itself.
  auto residual = [&](const Eigen::VectorXd& lambda) {
    Eigen::VectorXd lo = sys.lo, hi = sys.hi;
    set_friction_bounds(sys.coupling(), lambda, lo, hi);
    const Eigen::VectorXd w = matrix.matrix() * lambda + sys.q;
    return scaled_natural_map_residual(lambda, w, matrix.matrix().diagonal(), lo, hi, sys.q);
  };
  auto run = [&](bool coupled, int passes, Eigen::VectorXd& lambda) {
    lambda = Eigen::VectorXd::Zero(sys.rows);
    Eigen::VectorXd lo = sys.lo, hi = sys.hi, previous;
    std::vector<RowState> state(sys.rows, RowState::Free);
    BlcpWorkspace ws;
    CoupledWorkspace cw;
    return friction_passes(
        sys.coupling(), sys.diag, lambda, state, lo, hi, passes, 1e-13, previous,
        [&] { return solve_blcp(matrix, sys.q, lo, hi, lambda, state, BlcpSettings{}, ws).converged; },
        [&]() -> const Eigen::VectorXd& { return ws.w; },
        [&] {
          return coupled && coupled_friction_step(matrix, sys.q, lo, hi, sys.coupling(), lambda, state,
                                                  BlcpSettings{}, cw);
        });
  };
  Eigen::VectorXd lagged, exact;
  const int passes = SolverParams{}.friction_passes;
  const FrictionPassResult old_loop = run(false, passes, lagged);
  EXPECT_TRUE(old_loop.solved);
  EXPECT_FALSE(old_loop.settled);
  EXPECT_GT(residual(lagged), 1e-6);
  const FrictionPassResult new_loop = run(true, passes, exact);
  EXPECT_TRUE(new_loop.settled);
  EXPECT_LE(new_loop.passes, 2);
  EXPECT_LE(residual(exact), 1e-10);
  // Every corner of the top box slides relative to the box below (x velocity 1.5 -+ 0.5, y
  // velocity +-0.5 from the spin): x friction is -mu times the corner's own normal impulse, y
  // friction -+mu times it by the sign of the corner's x, and the normals carry the weight's impulse.
  double normal = 0;
  for (int j = 0; j < sys.rows; ++j) {
    const int g = sys.global_rows[j];
    if (s.rows.body[g][0] != 1 || s.rows.kind[g] != RowKind::Friction) continue;
    const double n = exact[sys.normal_of[j]];
    ASSERT_GT(n, 0.0);
    const Vec6& jac = s.rows.jac[g][0];
    // The corner's x is recovered from the y row's yaw arm: (r x e_y)_z = r_x.
    const double sign = jac[0] == 1.0 ? 1.0 : (jac[5] > 0 ? 1.0 : -1.0);
    EXPECT_NEAR(exact[j], -sign * mu_top * n, 1e-12 * n) << j;
    if (jac[0] == 1.0) normal += n;
  }
  EXPECT_NEAR(normal, m_top * kGravity * kStep, 1e-5 * m_top * kGravity * kStep);
}

TEST(NaturalMapResidual, DetectsAPerturbedSolution) {
  Scene s;
  add_box(s, 2.0, 0.5, 0.0, 0.5);
  finish(s);
  solve_direct(s.rows, s.bodies, s.islands, exact_params());
  EXPECT_LE(natural_map_residual(s.rows, s.bodies, s.islands), 1e-10);
  // Doubling one normal impulse: w_j = lambda_j A_jj (the others' share stays), so r_j A_jj / s is
  // lambda_j A_jj / (g h) to first order.
  s.rows.lambda[0] *= 2;
  EXPECT_GT(natural_map_residual(s.rows, s.bodies, s.islands), 0.1);
}

TEST(SolvePgs, ApproachesTheDirectAnswerAsSweepsGrow) {
  Scene s;
  add_box(s, 2.0, 0.5, 0.0, 0.5);
  add_box(s, 5.0, 0.3, 1.0, 0.6);
  finish(s);
  Rows direct_rows = s.rows;
  solve_direct(direct_rows, s.bodies, s.islands, exact_params());
  Scene direct = s;
  direct.rows = direct_rows;

  double previous_error = std::numeric_limits<double>::infinity(), previous_residual = previous_error;
  for (int sweeps : {3, 30, 300, 3000}) {
    Scene pgs = s;
    SolverParams params;
    params.kind = SolverKind::Pgs;
    params.pgs_iterations = sweeps;
    params.pgs_tolerance = 0;
    const SolveReport report = solve_pgs(pgs.rows, pgs.bodies, pgs.islands, params);
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
  const SolveReport report = solve_pgs(pgs.rows, pgs.bodies, pgs.islands, params);
  EXPECT_LT(report.iterations, 2 * 100000);
  EXPECT_GT(report.iterations, 2);
}

}  // namespace
}  // namespace rbpart
