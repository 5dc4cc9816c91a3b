// The Newton solver's interior-point phase (solve/interior_point.hpp) and the whole solver from a
// cold start (solve/newton.hpp), checked against mathematics: the residual of DESIGN.md §3 and the
// budget, on coupled problems with mass ratios up to 1:10000, sliding, spinning and frictionless
// contacts; and the monolithic backend on pieces whose free rows are coupled to their normal.
#include "solve/interior_point.hpp"
#include "solve/monolithic.hpp"
#include "solve/newton.hpp"
#include "solve/substructured_system.hpp"
#include "solve/box_scenes.hpp"

#include <gtest/gtest.h>

#include <Eigen/LU>

#include <random>

namespace rbpart {
namespace {

using namespace rbpart::testing;

// Columns of up to four boxes on the ground, masses from {1, 100, 10000} kg, each moving and
// spinning at random before contact; friction mu (0: frictionless).
Scene random_columns(std::mt19937& rng, int columns, double mu) {
  Scene s;
  std::uniform_int_distribution<int> height(1, 4), mass(0, 2);
  std::uniform_real_distribution<double> speed(-1.0, 1.0);
  for (int c = 0; c < columns; ++c) {
    int below = -1;
    for (int k = height(rng); k > 0; --k) {
      const int body = static_cast<int>(s.bodies.inv_mass.size());
      add_box_on(s, below, std::pow(100.0, mass(rng)), 0.5, speed(rng), mu, speed(rng), 2 * speed(rng));
      below = body;
    }
  }
  finish(s);
  return s;
}

IslandSystem gather_island(const Scene& scene, int island) {
  IslandSystem s;
  s.gather(scene.rows, scene.bodies, scene.islands, island, local_row_index(scene.rows, scene.islands));
  return s;
}

double residual(const IslandSystem& s, const Eigen::VectorXd& lambda) {
  Eigen::VectorXd du, w, fw;
  apply_a(s, lambda, du, w);
  w += s.q;
  scaled_natural_map(s, lambda, w, fw);
  return fw.cwiseAbs().maxCoeff() / s.q.cwiseAbs().maxCoeff();
}

// From a cold start (no impulses, every row free) the solver settles every island of random
// columns, frictionless or with mu = 0.3, within its budget. (With mu = 0.5 some of these islands
// end unsettled: the interior-point phase diverges on strongly coupled friction; see
// docs/pipeline.md.)
TEST(SolveNewton, SettlesRandomColumnsFromAColdStartWithinTheBudget) {
  std::mt19937 rng(11);
  int islands = 0;
  for (double mu : {0.0, 0.3})
    for (int trial = 0; trial < 10; ++trial) {
      const Scene scene = random_columns(rng, 3, mu);
      for (int i = 0; i < static_cast<int>(scene.islands.count()); ++i, ++islands) {
        const IslandSystem s = gather_island(scene, i);
        MonolithicSystem system;
        system.assign(s);
        Eigen::VectorXd lambda = Eigen::VectorXd::Zero(s.rows);
        std::vector<RowState> state(s.rows, RowState::Free);
        NewtonWorkspace ws;
        const NewtonResult r = solve_newton(s, system, 40, lambda, state, ws);
        EXPECT_TRUE(r.settled) << "mu " << mu << " trial " << trial << " island " << i << " residual " << r.residual;
        EXPECT_LE(r.factorizations, 40);
        EXPECT_NEAR(residual(s, lambda), r.residual, 1e-12);
        EXPECT_LE(residual(s, lambda), kSettledResidual);
      }
    }
  EXPECT_GE(islands, 60);
}

// The interior-point steps alone approach the answer: on frictionless columns (a monotone
// complementarity problem, where Mehrotra's method converges) the projected iterate's residual
// falls below the criterion within 40 steps.
TEST(InteriorPoint, ConvergesOnFrictionlessColumns) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 5; ++trial) {
    const Scene scene = random_columns(rng, 2, 0.0);
    for (int i = 0; i < static_cast<int>(scene.islands.count()); ++i) {
      const IslandSystem s = gather_island(scene, i);
      MonolithicSystem system;
      system.assign(s);
      InteriorPoint ipm;
      ipm.start(s);
      IslandChunks chunks;
      double best = INFINITY;
      for (int step = 0; step < 40 && best > kSettledResidual; ++step) {
        if (!(ipm.step(system, chunks) > 0)) break;
        Eigen::VectorXd lambda = ipm.lambda();
        for (int j = 0; j < s.rows; ++j) lambda[j] = std::clamp(lambda[j], s.lo[j], std::max(s.lo[j], s.hi[j]));
        best = std::min(best, residual(s, lambda));
      }
      EXPECT_LE(best, kSettledResidual) << "trial " << trial << " island " << i;
    }
  }
}

// Every row Free with a random shift, friction rows coupled to their normal by a random tie: the
// rows of an interior-point step.
Piece coupled_free_piece(const IslandSystem& s, std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Piece piece;
  piece.equation.assign(s.rows, RowEquation::Free);
  piece.tie.setZero(s.rows);
  piece.shift.setZero(s.rows);
  for (int j = 0; j < s.rows; ++j) {
    piece.shift[j] = unit(rng) * s.diag[j];
    if (s.normal_of[j] >= 0) piece.tie[j] = (unit(rng) - 0.5) * s.mu[j] * s.diag[j];
  }
  return piece;
}

// The piece's solution for right-hand side g by the monolithic backend; empty if it did not factor.
Eigen::VectorXd solve_monolithic(const IslandSystem& s, const Piece& piece, const Eigen::VectorXd& g) {
  MonolithicSystem system;
  system.assign(s);
  Eigen::VectorXd x;
  if (system.factor(piece)) system.solve(g, x);
  return x;
}

// A free row coupled to its normal, (A x)_j + shift_j x_j - tie_j x_n = g_j (the interior-point
// steps' rows), is solved by the body-space backend as a dense LU of the same equations does.
TEST(MonolithicSystem, SolvesFreeRowsCoupledToTheirNormalLikeADenseSolve) {
  std::mt19937 rng(3);
  const Scene scene = random_columns(rng, 1, 0.5);
  const IslandSystem s = gather_island(scene, 0);
  Eigen::MatrixXd e;
  build_dense(s, e);
  const Piece piece = coupled_free_piece(s, rng);
  for (int j = 0; j < s.rows; ++j) {
    e(j, j) += piece.shift[j];
    if (s.normal_of[j] >= 0) e(j, s.normal_of[j]) -= piece.tie[j];
  }
  const Eigen::VectorXd g = Eigen::VectorXd::Random(s.rows);
  const Eigen::VectorXd x = solve_monolithic(s, piece, g);
  ASSERT_EQ(x.size(), s.rows) << "the monolithic backend did not factor";
  const Eigen::VectorXd reference = e.partialPivLu().solve(g);
  EXPECT_LE((x - reference).norm(), 1e-8 * reference.norm());
}

// The substructured backend solves the same pieces as the monolithic one, coupled free rows on
// interface rows and inside parts alike (every box its own part, then two boxes a part).
TEST(SubstructuredSystem, SolvesFreeRowsCoupledToTheirNormalLikeTheMonolithicBackend) {
  std::mt19937 rng(9);
  const Scene scene = random_columns(rng, 2, 0.5);
  for (int i = 0; i < static_cast<int>(scene.islands.count()); ++i) {
    const IslandSystem s = gather_island(scene, i);
    if (s.bodies < 2) continue;
    const Piece piece = coupled_free_piece(s, rng);
    const Eigen::VectorXd g = Eigen::VectorXd::Random(s.rows);
    const Eigen::VectorXd reference = solve_monolithic(s, piece, g);
    ASSERT_EQ(reference.size(), s.rows) << "the monolithic backend did not factor";
    for (int per_part : {1, 2}) {
      std::vector<int> part_of_body(s.bodies);
      for (int b = 0; b < s.bodies; ++b) part_of_body[b] = b / per_part;
      SubstructuredSystem substructured;
      substructured.assign(s, part_of_body);
      ASSERT_TRUE(substructured.factor(piece));
      Eigen::VectorXd x;
      substructured.solve(g, x);
      EXPECT_LE((x - reference).norm(), 1e-8 * reference.norm()) << "island " << i << " bodies per part " << per_part;
    }
  }
}

}  // namespace
}  // namespace rbpart
