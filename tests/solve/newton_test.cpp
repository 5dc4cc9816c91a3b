// The Newton solver (solve/newton.hpp) and its monolithic backend (solve/monolithic.hpp), checked
// against mathematics: the backend against a dense solve of the same piece's equations, the solver
// against analytic impulses (boxes resting, sliding, sliding and spinning on a box), its residual,
// its budget, the residual's scaling on a 1:10000 pair, random contact islands on both backends,
// and every solution of small islands found by enumerating their row states.
#include "solve/bounds.hpp"
#include "solve/monolithic.hpp"
#include "solve/newton.hpp"
#include "solve/random_blcp.hpp"
#include "solve/residual.hpp"
#include "solve/solve.hpp"
#include "solve/substructured_system.hpp"
#include "solve/box_scenes.hpp"
#include "solve/random_piece.hpp"

#include <gtest/gtest.h>

#include <Eigen/LU>

#include <limits>
#include <numeric>
#include <random>
#include <string>

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

// The body-space backend solves E x = g as a dense LU of E does, to the digits the small regularisation leaves (A's condition ~ 1e6 here).
TEST(MonolithicSystem, SolvesEveryKindOfPieceLikeADenseSolve) {
  Scene scene = stack(true);
  const std::vector<int> local = local_row_index(scene.rows, scene.islands);
  IslandSystem s;
  s.gather(scene.rows, scene.bodies, scene.islands, 0, local);
  std::mt19937 rng(7);
  for (bool ties : {false, true})
      for (int trial = 0; trial < 5; ++trial) {
        MonolithicSystem system;
        system.assign(s);
        const Piece piece = random_piece(s, rng, ties);
        ASSERT_TRUE(system.factor(piece));
        const Eigen::VectorXd g = Eigen::VectorXd::Random(s.rows);
        Eigen::VectorXd x;
        system.solve(g, x);
        const Eigen::MatrixXd e = piece_matrix(s, piece);
        const Eigen::VectorXd reference = e.partialPivLu().solve(g);
        EXPECT_LE((x - reference).norm(), 1e-6 * reference.norm())
            << "ties " << ties << " trial " << trial;
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
  const SolveStats report = solve_newton_direct(s.rows, s.bodies, s.islands, SolverParams{});
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
  const SolveStats report = solve_newton_direct(s.rows, s.bodies, s.islands, SolverParams{});
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
  const SolveStats cold = solve_newton_direct(s.rows, s.bodies, s.islands, p);
  EXPECT_EQ(cold.unsettled, 0);
  EXPECT_LE(cold.residual, kSettledResidual);
  EXPECT_LE(cold.factorizations, p.max_factorizations);
  // Its own answer as the warm start: settled at once, with no factorisation.
  const SolveStats warm = solve_newton_direct(s.rows, s.bodies, s.islands, p);
  EXPECT_LE(warm.residual, kSettledResidual);
  EXPECT_EQ(warm.factorizations, 0);
  // A budget of one: at most one factorisation, and the report says whether it settled.
  Scene again = stack(true);
  p.max_factorizations = 1;
  const SolveStats capped = solve_newton_direct(again.rows, again.bodies, again.islands, p);
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
    const SolveStats report = solve_newton_direct(s.rows, s.bodies, s.islands, p);
    EXPECT_LE(report.island_factorizations, budget);
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
  const SolveStats report = solve_newton_direct(s.rows, s.bodies, s.islands, SolverParams{});
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

// Two islands, one resting and one sliding: both settle from a cold start, and the report's residual
// is the one natural_map_residual measures. Warm started from its own answer, the solve settles with
// no factorisation.
TEST(SolveNewton, TwoIslandsSettleAndAWarmStartAtTheAnswerTakesNoFactorisation) {
  Scene s;
  add_box(s, 2.0, 0.5, 0.0, 0.5);
  add_box(s, 5.0, 0.3, 1.0, 0.6);
  finish(s);
  ASSERT_EQ(s.islands.count(), 2u);
  const SolveStats cold = solve_newton_direct(s.rows, s.bodies, s.islands, SolverParams{});
  EXPECT_EQ(cold.unsettled, 0);
  EXPECT_LE(cold.residual, kSettledResidual);
  EXPECT_EQ(natural_map_residual(s.rows, s.bodies, s.islands), cold.residual);
  const SolveStats again = solve_newton_direct(s.rows, s.bodies, s.islands, SolverParams{});
  EXPECT_LE(again.residual, kSettledResidual);
  EXPECT_EQ(again.factorizations, 0);
}

// A heavy box sliding and spinning face-down on a box that rests on the ground: eight redundant
// contact points whose load shares move with the friction's moments, every corner of the top box
// sliding (x velocity 1.5 -+ 0.5, y velocity +-0.5 from the spin). Coulomb at every corner: x
// friction is -mu times the corner's own normal impulse, y friction -+mu times it by the sign of
// the corner's x, and the normals carry the weight's impulse. (A friction loop that lags the
// bounds a pass behind the normals only creeps towards this answer.)
TEST(SolveNewton, BoxSlidingAndSpinningOnABoxFeelsCoulombFrictionAtEveryCorner) {
  Scene s;
  const double m_top = 10.0, mu_top = 0.4, a = 0.5;
  add_box(s, 5.0, a, 0.0, 0.8);
  add_box_on(s, 0, m_top, a, 1.5, mu_top, 0.0, 1.0);
  finish(s);
  ASSERT_EQ(s.islands.count(), 1u);
  const SolveStats report = solve_newton_direct(s.rows, s.bodies, s.islands, SolverParams{});
  EXPECT_EQ(report.unsettled, 0);
  EXPECT_LE(report.residual, kSettledResidual);
  double normal = 0;
  int corners = 0;
  for (std::size_t j = 0; j < s.rows.size(); ++j) {
    if (s.rows.body[j][0] != 1 || s.rows.kind[j] != RowKind::Friction) continue;
    const double n = s.rows.lambda[s.rows.normal_of[j]];
    ASSERT_GT(n, 0.0);
    const Vec6& jac = s.rows.jac[j][0];
    // The corner's x is recovered from the y row's yaw arm: (r x e_y)_z = r_x.
    const double sign = jac[0] == 1.0 ? 1.0 : (jac[5] > 0 ? 1.0 : -1.0);
    EXPECT_NEAR(s.rows.lambda[j], -sign * mu_top * n, 1e-9 * n) << j;
    if (jac[0] == 1.0) {
      normal += n;
      ++corners;
    }
  }
  EXPECT_EQ(corners, 4);
  EXPECT_NEAR(normal, m_top * kGravity * kStep, 1e-5 * m_top * kGravity * kStep);
}

// The residual of DESIGN.md §3 with A assembled densely (build_dense), independent of the products
// the solver computes it with: friction bounds from lambda's own normals.
double dense_residual(const IslandSystem& s, const Eigen::VectorXd& lambda) {
  Eigen::MatrixXd a;
  build_dense(s, a);
  Eigen::VectorXd lo = s.lo, hi = s.hi;
  set_friction_bounds(s.coupling(), lambda, lo, hi);
  const Eigen::VectorXd w = a * lambda + s.q;
  return scaled_natural_map_residual(lambda, w, a.diagonal(), lo, hi, s.q);
}

// The residual cannot be computed finer than the round-off of w = A lambda + q: eps times a row's
// terms, each up to max_j A_jj |lambda_j| (large when redundant rows fight over an inconsistent q,
// lambda ~ q / sigma).
double residual_round_off(const IslandSystem& s, const Eigen::VectorXd& lambda) {
  const double terms = lambda.cwiseAbs().cwiseProduct(s.diag).maxCoeff();
  return 256 * std::numeric_limits<double>::epsilon() * terms / std::max(s.q.cwiseAbs().maxCoeff(), 1e-12);
}

// The answer is admissible (normals and bounded rows in their bounds, friction in the box of its
// normal) and its residual is the one reported.
void expect_admissible_with_residual(const IslandSystem& s, const Eigen::VectorXd& lambda, const NewtonResult& r,
                                     const std::string& where) {
  EXPECT_NEAR(dense_residual(s, lambda), r.residual, residual_round_off(s, lambda)) << where;
  for (int j = 0; j < s.rows; ++j) {
    const int n = s.normal_of[j];
    const double lo = n >= 0 ? -s.mu[j] * std::max(0.0, lambda[n]) : s.lo[j];
    const double hi = n >= 0 ? s.mu[j] * std::max(0.0, lambda[n]) : s.hi[j];
    EXPECT_TRUE(lambda[j] >= lo && lambda[j] <= hi) << where << " row " << j;
  }
}

NewtonResult solve_cold(const IslandSystem& s, LinearSystem& system, Eigen::VectorXd& lambda) {
  lambda = Eigen::VectorXd::Zero(s.rows);
  std::vector<RowState> state(s.rows, RowState::Free);
  NewtonWorkspace ws;
  return solve_newton(s, system, SolverParams{}.max_factorizations, lambda, state, ws);
}

NewtonResult solve_cold(const IslandSystem& s, Eigen::VectorXd& lambda) {
  MonolithicSystem system;
  system.assign(s);
  return solve_cold(s, system, lambda);
}

// The solver's loops over rows and bodies run in chunks (island_chunks.hpp, the substructured
// solver's vector work) give the serial loops' answer bit for bit, with the same counts, on
// islands that run the interior-point phase (cold, coupled friction): chunks run one after another
// (60 and 600 rows) and in parallel (over IslandChunks::kMinParallelItems rows).
TEST(SolveNewton, LoopsInChunksGiveTheSerialAnswerBitForBit) {
  std::mt19937 rng(41);
  RandomIsland island;
  for (int rows : {60, 600, IslandChunks::kMinParallelItems + 600}) {
    IslandOptions opt;
    opt.rows = rows;
    random_contact_island(rng, opt, island);
    const IslandSystem& s = island.system;
    std::vector<Eigen::VectorXd> answers;
    std::vector<NewtonResult> results;
    for (int chunks : {1, 2, 7}) {
      MonolithicSystem system;
      system.assign(s);
      Eigen::VectorXd lambda = Eigen::VectorXd::Zero(s.rows);
      std::vector<RowState> state(s.rows, RowState::Free);
      NewtonWorkspace ws;
      ws.chunks.set_count(chunks);
      results.push_back(solve_newton(s, system, SolverParams{}.max_factorizations, lambda, state, ws));
      answers.push_back(lambda);
      if (chunks > 1) EXPECT_GT(ws.chunks.work_ms, 0.0);
    }
    EXPECT_GT(results[0].factorizations, 1) << rows << " rows: the test should run more than the warm step";
    for (std::size_t k = 1; k < answers.size(); ++k) {
      EXPECT_EQ(results[k].factorizations, results[0].factorizations) << rows << " rows";
      EXPECT_EQ(results[k].residual, results[0].residual) << rows << " rows";
      for (int j = 0; j < s.rows; ++j) ASSERT_EQ(answers[k][j], answers[0][j]) << rows << " rows, row " << j;
    }
  }
}

// A problem with a non-finite coefficient has no iterate of finite residual: the solver still ends
// (unsettled, its answer one impulse per row) instead of returning an answer it never computed.
TEST(SolveNewton, ANonFiniteProblemEndsUnsettledWithAnAnswerPerRow) {
  std::mt19937 rng(3);
  RandomIsland island;
  IslandOptions opt;
  opt.rows = 12;
  opt.bodies = 2;
  random_contact_island(rng, opt, island);
  IslandSystem s = island.system;
  s.q[0] = std::numeric_limits<double>::quiet_NaN();
  Eigen::VectorXd lambda;
  const NewtonResult r = solve_cold(s, lambda);
  EXPECT_FALSE(r.settled);
  EXPECT_FALSE(r.residual <= kSettledResidual);
  EXPECT_EQ(lambda.size(), s.rows);
  EXPECT_LE(r.factorizations, SolverParams{}.max_factorizations);
}

// Random contact islands (random_blcp.hpp: contacts between bodies and against static ones, joint
// and box rows, redundant beyond six rows per body) with fixed friction boxes: a strictly convex box
// QP, whose answer is unique. From a cold start, on the monolithic backend and on the substructured
// one with every body its own part (other factorisations: the interface's Schur complement), the
// solver settles every one, reports the residual of its answer, and both give the same answer.
TEST(SolveNewton, SolvesRandomIslandsWithFixedBoundsOnBothBackends) {
  std::mt19937 rng(777);
  RandomIsland island;
  int islands = 0;
  for (int rows = 3; rows <= 60; rows += 3)
    for (int k = 0; k < 10; ++k, ++islands) {
      IslandOptions opt;
      opt.rows = rows;
      opt.bodies = 1 + static_cast<int>(rng() % std::max(1, rows / 6));
      opt.coupled_friction = false;
      random_contact_island(rng, opt, island);
      const IslandSystem& s = island.system;
      const std::string where = "rows " + std::to_string(s.rows) + " k " + std::to_string(k);
      Eigen::VectorXd whole, split;
      SubstructuredSystem parts;
      std::vector<int> own_part(s.bodies);
      std::iota(own_part.begin(), own_part.end(), 0);
      parts.assign(s, own_part);
      const NewtonResult d = solve_cold(s, whole), c = solve_cold(s, parts, split);
      EXPECT_TRUE(d.settled && c.settled) << where << ": " << d.residual << ", " << c.residual;
      EXPECT_NEAR(dense_residual(s, whole), d.residual, residual_round_off(s, whole)) << where;
      EXPECT_NEAR(dense_residual(s, split), c.residual, residual_round_off(s, split)) << where;
      EXPECT_LE((whole - split).cwiseAbs().maxCoeff(), 1e-9 * std::max(1.0, whole.cwiseAbs().maxCoeff())) << where;
    }
  EXPECT_EQ(islands, 200);
}

// The same islands with friction coupled to the normals (mu from 0.1 to 0.8): whether settled or
// not, every answer is admissible and its residual is the one reported. Most settle; those that do
// not are islands of 20 to 60 rows on one or two bodies, redundant contacts with random normals,
// on which the solver stalls at residuals of 0.1 to 6 (11 of these 200; a budget of 400
// factorisations settles 2 of them): a limit of the solver, not of the problem (docs/pipeline.md).
TEST(SolveNewton, SettlesMostRandomIslandsWithCoupledFriction) {
  std::mt19937 rng(777);
  RandomIsland island;
  int islands = 0, settled = 0;
  for (int rows = 3; rows <= 60; rows += 3)
    for (int k = 0; k < 10; ++k, ++islands) {
      IslandOptions opt;
      opt.rows = rows;
      opt.bodies = 1 + static_cast<int>(rng() % std::max(1, rows / 6));
      random_contact_island(rng, opt, island);
      const IslandSystem& s = island.system;
      const std::string where = "rows " + std::to_string(s.rows) + " k " + std::to_string(k);
      Eigen::VectorXd lambda;
      const NewtonResult r = solve_cold(s, lambda);
      settled += r.settled;
      expect_admissible_with_residual(s, lambda, r, where);
    }
  EXPECT_EQ(islands, 200);
  EXPECT_GE(settled, 180);
}

// An exact answer leaves the bodies no more kinetic energy than their free motion (newton.cpp,
// energy_scale: E(lambda) = lambda^T A lambda / 2 + lambda^T q <= 0), and neither does an answer the
// budget stops short of it: on random coupled islands cut to budgets of 1-4 factorisations, where
// most end unsettled, every answer is admissible, has E <= 0 to round-off and the residual
// reported. (Without the scaling back, 26 of these answers have E > 0.)
TEST(SolveNewton, AnUnsettledAnswerAddsNoKineticEnergy) {
  std::mt19937 rng(778);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  RandomIsland island;
  int unsettled = 0;
  for (int rows = 6; rows <= 60; rows += 6)
    for (int budget = 1; budget <= 4; ++budget) {
      IslandOptions opt;
      opt.rows = rows;
      opt.bodies = 1 + static_cast<int>(rng() % std::max(1, rows / 6));
      opt.box_fraction = 0;  // the engine's boxes hold 0; a box that does not may need work
      random_contact_island(rng, opt, island);
      const IslandSystem& s = island.system;
      const std::string where = "rows " + std::to_string(s.rows) + " budget " + std::to_string(budget);
      MonolithicSystem system;
      system.assign(s);
      // A warm start of normals pushing at up to ten times the island's free velocities' scale,
      // friction anywhere in their boxes: points that add energy (an impact's warm start is the
      // impulses of the step before, on other contacts).
      Eigen::VectorXd lambda(s.rows);
      for (int j = 0; j < s.rows; ++j)
        lambda[j] = s.normal_of[j] < 0 ? 10 * u01(rng) * max_abs(s.q) / s.diag[j] : 0.0;
      for (int j = 0; j < s.rows; ++j)
        if (s.normal_of[j] >= 0) lambda[j] = (2 * u01(rng) - 1) * s.mu[j] * lambda[s.normal_of[j]];
      std::vector<RowState> state(s.rows, RowState::Free);
      NewtonWorkspace ws;
      const NewtonResult r = solve_newton(s, system, budget, lambda, state, ws);
      EXPECT_LE(r.factorizations, budget) << where;
      if (r.settled) continue;
      ++unsettled;
      Eigen::MatrixXd a;
      build_dense(s, a);
      const Eigen::VectorXd a_lambda = a * lambda;
      const double magnitude = lambda.cwiseAbs().dot(a_lambda.cwiseAbs() + s.q.cwiseAbs());
      EXPECT_LE(0.5 * lambda.dot(a_lambda) + lambda.dot(s.q), 1e-12 * magnitude) << where;
      expect_admissible_with_residual(s, lambda, r, where);
    }
  EXPECT_GE(unsettled, 20);
}

// Every solution of a small island's coupled problem, found by trying every combination of row
// states and solving its linear equations with A assembled densely: a row is free (w_j = 0), at a
// finite bound, or - a friction row - tied to its normal (lambda_t = -+mu lambda_n); a combination
// counts when its answer satisfies DESIGN.md §3's conditions (free rows within their bounds, w
// pushing outward at a bound, normals non-negative) to `tolerance` of the island's scale.
std::vector<Eigen::VectorXd> enumerate_solutions(const IslandSystem& s, double tolerance) {
  Eigen::MatrixXd a;
  build_dense(s, a);
  const int n = s.rows;
  int combinations = 1;
  for (int j = 0; j < n; ++j) combinations *= 3;
  const double wtol = tolerance * s.q.cwiseAbs().maxCoeff();
  std::vector<Eigen::VectorXd> out;
  Eigen::MatrixXd e(n, n);
  Eigen::VectorXd r(n);
  std::vector<int> st(n);
  for (int code = 0; code < combinations; ++code) {
    e.setZero();
    r.setZero();
    bool valid = true;
    for (int j = 0, c = code; j < n; ++j, c /= 3) {
      st[j] = c % 3;  // 0 free, 1 lower, 2 upper
      if (st[j] == 0) {
        e.row(j) = a.row(j);
        r[j] = -s.q[j];
      } else if (s.normal_of[j] >= 0) {
        e(j, j) = 1;
        e(j, s.normal_of[j]) = st[j] == 1 ? s.mu[j] : -s.mu[j];
      } else {
        const double bound = st[j] == 1 ? s.lo[j] : s.hi[j];
        valid = valid && std::isfinite(bound);
        e(j, j) = 1;
        r[j] = bound;
      }
    }
    if (!valid) continue;
    const Eigen::FullPivLU<Eigen::MatrixXd> lu(e);
    if (!lu.isInvertible()) continue;
    const Eigen::VectorXd x = lu.solve(r), w = a * x + s.q;
    const double ltol = tolerance * std::max(1.0, x.cwiseAbs().maxCoeff());
    bool ok = true;
    for (int j = 0; j < n && ok; ++j) {
      const int normal = s.normal_of[j];
      const double lo = normal >= 0 ? -s.mu[j] * std::max(0.0, x[normal]) : s.lo[j];
      const double hi = normal >= 0 ? s.mu[j] * std::max(0.0, x[normal]) : s.hi[j];
      if (st[j] == 0) ok = x[j] >= lo - ltol && x[j] <= hi + ltol && std::abs(w[j]) <= wtol;
      else ok = (st[j] == 1 ? w[j] >= -wtol : w[j] <= wtol) && (normal < 0 || x[normal] >= -ltol);
    }
    if (ok) out.push_back(x);
  }
  return out;
}

// On islands of up to nine rows the solver's answer is one of the enumerated solutions: an
// independent check of the solver and of its residual (which calls an answer settled).
TEST(SolveNewton, AnswerIsOneOfTheEnumeratedSolutionsOnSmallIslands) {
  std::mt19937 rng(2024);
  RandomIsland island;
  int checked = 0;
  for (int rows = 3; rows <= 9; rows += 3)
    for (int k = 0; k < 30; ++k) {
      IslandOptions opt;
      opt.rows = rows;
      opt.bodies = 1 + static_cast<int>(rng() % 2);
      random_contact_island(rng, opt, island);
      const IslandSystem& s = island.system;
      if (s.rows > 10) continue;  // joint and box rows may round a contact up
      const std::string where = "rows " + std::to_string(s.rows) + " k " + std::to_string(k);
      Eigen::VectorXd lambda;
      const NewtonResult result = solve_cold(s, lambda);
      ASSERT_TRUE(result.settled) << where << ": " << result.residual;
      const std::vector<Eigen::VectorXd> solutions = enumerate_solutions(s, 1e-9);
      ASSERT_FALSE(solutions.empty()) << where;
      double nearest = std::numeric_limits<double>::infinity();
      for (const Eigen::VectorXd& x : solutions)
        nearest = std::min(nearest, (x - lambda).cwiseAbs().maxCoeff() / std::max(1.0, x.cwiseAbs().maxCoeff()));
      EXPECT_LE(nearest, 1e-6) << where << " (" << solutions.size() << " solutions)";
      ++checked;
    }
  EXPECT_GE(checked, 80);
}

}  // namespace
}  // namespace rbpart
