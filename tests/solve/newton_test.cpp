// The Newton solver (solve/newton.hpp) and its monolithic backend (solve/monolithic.hpp), checked
// against mathematics: the backend against a dense solve of the same piece's equations, the solver
// against analytic impulses, its residual, its budget, and the residual's scaling on a 1:10000 pair.
#include "solve/monolithic.hpp"
#include "solve/newton.hpp"
#include "solve/residual.hpp"
#include "solve/solve.hpp"
#include "solve/box_scenes.hpp"
#include "solve/random_piece.hpp"

#include <gtest/gtest.h>

#include <Eigen/LU>

#include <random>

namespace rbpart {
namespace {

using namespace rbpart::testing;

// Three boxes stacked on the ground, masses 1 : 1000 : 1; with `sliding`, the top two slide and the
// top one spins.
Scene stack(bool sliding) {
  Scene s;
  add_box_on(s, -1, 1.0, 0.5, 0.0, 0.5);
  add_box_on(s, 0, 1000.0, 0.5, sliding ? 0.3 : 0.0, 0.4);
  add_box_on(s, 1, 1.0, 0.5, sliding ? -0.2 : 0.0, 0.6, sliding ? 0.1 : 0.0, sliding ? 0.5 : 0.0);
  finish(s);
  return s;
}

// The dense (Cholesky / LU) and sparse (CHOLMOD / KLU) body-space backends solve E x = g as a
// dense LU of E does, to the digits the small regularisation leaves (A's condition ~ 1e6 here).
TEST(MonolithicSystem, SolvesEveryKindOfPieceLikeADenseSolve) {
  Scene scene = stack(true);
  const std::vector<int> local = local_row_index(scene.rows, scene.islands);
  IslandSystem s;
  s.gather(scene.rows, scene.bodies, scene.islands, 0, local);
  std::mt19937 rng(7);
  for (int dense_max_bodies : {0, 100})
    for (bool ties : {false, true})
      for (int trial = 0; trial < 5; ++trial) {
        MonolithicSystem system;
        system.assign(s, dense_max_bodies);
        const Piece piece = random_piece(s, rng, ties);
        ASSERT_TRUE(system.factor(piece));
        const Eigen::VectorXd g = Eigen::VectorXd::Random(s.rows);
        Eigen::VectorXd x;
        system.solve(g, x);
        const Eigen::MatrixXd e = piece_matrix(s, piece);
        const Eigen::VectorXd reference = e.partialPivLu().solve(g);
        EXPECT_LE((x - reference).norm(), 1e-6 * reference.norm())
            << "dense_max_bodies " << dense_max_bodies << " ties " << ties << " trial " << trial;
        // One refinement step against the exact equations recovers the lost digits: what is left
        // is the round-off of the product E x itself.
        Eigen::VectorXd correction;
        system.solve(g - e * x, correction);
        EXPECT_LE((e * (x + correction) - g).norm(), 1e-13 * e.norm() * x.norm());
      }
}

TEST(SolveNewton, RestingBoxHasTheSymmetricAnalyticImpulses) {
  Scene s;
  add_box(s, 2.0, 0.5, 0.0, 0.5);
  finish(s);
  const SolveReport report = solve_newton_direct(s.rows, s.bodies, s.islands, SolverParams{});
  EXPECT_EQ(report.unsettled, 0);
  EXPECT_LE(report.residual, kSettledResidual);
  EXPECT_LE(report.factorizations, SolverParams{}.max_factorizations);
  // Each corner carries a quarter: -g h + 4 lambda / m + sigma lambda = 0, no friction.
  const double expected = kGravity * kStep / (4 / 2.0 + s.rows.sigma[0]);
  for (std::size_t j = 0; j < s.rows.size(); ++j)
    EXPECT_NEAR(s.rows.lambda[j], s.rows.kind[j] == RowKind::Normal ? expected : 0.0, 1e-9 * expected);
}

TEST(SolveNewton, SlidingBoxFeelsCoulombFrictionOnEveryContact) {
  Scene s;
  const double m = 3.0, mu = 0.3, vx = 2.0;
  add_box(s, m, 0.4, vx, mu);  // too fast to stop within one step: friction saturates
  finish(s);
  const SolveReport report = solve_newton_direct(s.rows, s.bodies, s.islands, SolverParams{});
  EXPECT_EQ(report.unsettled, 0);
  EXPECT_LE(report.residual, kSettledResidual);
  for (std::size_t j = 0; j < s.rows.size(); ++j) {
    if (s.rows.kind[j] != RowKind::Friction) continue;
    const double bound = mu * s.rows.lambda[s.rows.normal_of[j]];
    if (s.rows.jac[j][0][0] == 1.0) EXPECT_NEAR(s.rows.lambda[j], -bound, 1e-9 * bound);  // along x: sliding
    else EXPECT_NEAR(s.rows.lambda[j], 0.0, 1e-9 * bound);
  }
  // Coulomb: the box loses mu g h of its speed and comes to rest vertically.
  const Vec6 u = velocity_after(s, 0);
  EXPECT_NEAR(u[0], vx - mu * kGravity * kStep, 1e-6 * vx);
  EXPECT_NEAR(u[2], 0.0, 1e-6 * kGravity * kStep);
}

TEST(SolveNewton, RestingStackWithMassRatio1000SettlesWithinTheBudgetAndStaysSettledWarm) {
  Scene s = stack(false);
  SolverParams p;
  const SolveReport cold = solve_newton_direct(s.rows, s.bodies, s.islands, p);
  EXPECT_EQ(cold.unsettled, 0);
  EXPECT_LE(cold.residual, kSettledResidual);
  EXPECT_LE(cold.factorizations, p.max_factorizations);
  // Its own answer as the warm start: settled at once, with no factorisation.
  const SolveReport warm = solve_newton_direct(s.rows, s.bodies, s.islands, p);
  EXPECT_LE(warm.residual, kSettledResidual);
  EXPECT_EQ(warm.factorizations, 0);
  // A budget of one: at most one factorisation, and the report says whether it settled.
  Scene again = stack(true);
  p.max_factorizations = 1;
  const SolveReport capped = solve_newton_direct(again.rows, again.bodies, again.islands, p);
  EXPECT_LE(capped.factorizations, 1);
  EXPECT_EQ(capped.unsettled, capped.residual > kSettledResidual ? 1 : 0);
}

// Stopped by its budget, even from a warm start outside the bounds, the solver still applies admissible impulses (no pulling normal, friction
// inside the box of its normal), and the residual it reports is that of what it returns.
TEST(SolveNewton, AnUnsettledAnswerIsAdmissible) {
  int unsettled = 0;
  for (int budget = 1; budget <= 6; ++budget) {
    Scene s = stack(true);
    // A warm start far outside the bounds: pulling normals, friction beyond its box.
    for (std::size_t j = 0; j < s.rows.size(); ++j) s.rows.lambda[j] = s.rows.kind[j] == RowKind::Normal ? -100.0 : 50.0;
    SolverParams p;
    p.max_factorizations = budget;
    const SolveReport report = solve_newton_direct(s.rows, s.bodies, s.islands, p);
    if (report.unsettled == 0) continue;
    ++unsettled;
    for (std::size_t j = 0; j < s.rows.size(); ++j) {
      const double lambda = s.rows.lambda[j];
      if (s.rows.kind[j] == RowKind::Normal) EXPECT_GE(lambda, 0.0) << "budget " << budget;
      if (s.rows.kind[j] == RowKind::Friction)
        EXPECT_LE(std::abs(lambda), s.rows.mu[j] * s.rows.lambda[s.rows.normal_of[j]]) << "budget " << budget;
    }
    EXPECT_NEAR(natural_map_residual(s.rows, s.bodies, s.islands), report.residual, 1e-12);
  }
  EXPECT_GT(unsettled, 0);
}

// The residual is in velocity units relative to the island's largest free velocity, so an error in
// a 1 kg box's impulse beside a 10000 kg one shows at its own size: a change d lambda of the light
// box's normal impulse moves its row's velocity by A_jj d lambda, and the residual by that over
// max |q|.
TEST(SolveNewton, ResidualShowsALightBodysErrorBesideAHeavyOne) {
  Scene s;
  add_box_on(s, -1, 10000.0, 0.5, 0.0, 0.5);
  add_box_on(s, 0, 1.0, 0.5, 0.05, 0.5);
  finish(s);
  const SolveReport report = solve_newton_direct(s.rows, s.bodies, s.islands, SolverParams{});
  ASSERT_LE(report.residual, kSettledResidual);
  const std::vector<int> local = local_row_index(s.rows, s.islands);
  IslandSystem system;
  system.gather(s.rows, s.bodies, s.islands, 0, local);
  int light = -1;  // a normal row of the light box on the heavy one
  for (std::size_t j = 0; j < s.rows.size(); ++j)
    if (s.rows.kind[j] == RowKind::Normal && s.rows.body[j][0] == 1) light = static_cast<int>(j);
  ASSERT_GE(light, 0);
  const double change = 1e-6 * s.rows.lambda[light];
  s.rows.lambda[light] += change;
  const double expected = system.diag[local[light]] * change / system.q.cwiseAbs().maxCoeff();
  EXPECT_GT(expected, 10 * kSettledResidual);
  EXPECT_GE(natural_map_residual(s.rows, s.bodies, s.islands), 0.5 * expected);
}

}  // namespace
}  // namespace rbpart
