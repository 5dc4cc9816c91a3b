// The substructured backend (solve/substructured_system.hpp, DESIGN.md §7) against the monolithic
// one (solve/monolithic.hpp), its reference: on random islands, random pieces and random
// partitions (one part, one part per body, anything between, parts not connected), a solve is the
// monolithic solve and satisfies the piece's exact equations; a part whose rows did not change keeps
// its factor; the Newton solver reaches the monolithic answer (impulses and states) on sliding boxes
// and the monolithic motion on resting towers, per island and through the stage driver
// (solve/newton_substructured.hpp); and the answer is the same bit for bit on 1 and 2 threads.
#include "solve/substructured_system.hpp"

#include "graph/constraint_graph.hpp"
#include "solve/island_system.hpp"
#include "solve/monolithic.hpp"
#include "solve/newton.hpp"
#include "solve/newton_substructured.hpp"
#include "solve/solve.hpp"

#include "tests/solve/box_scenes.hpp"
#include "solve/random_blcp.hpp"
#include "tests/solve/random_piece.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <limits>
#include <numeric>
#include <random>
#include <string>

namespace rbpart {
namespace {

using namespace rbpart::testing;

// --- partitions of an island's bodies (any assignment with no empty part is valid) ---------------

// Every body's part uniform in 0..parts-1, then renumbered so that none is empty.
std::vector<int> random_parts(int bodies, int parts, std::mt19937& rng) {
  std::vector<int> part(bodies);
  std::uniform_int_distribution<int> pick(0, parts - 1);
  for (int& p : part) p = pick(rng);
  std::vector<int> used = part;
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  for (int& p : part) p = static_cast<int>(std::lower_bound(used.begin(), used.end(), p) - used.begin());
  return part;
}

std::vector<int> one_part(int bodies) { return std::vector<int>(bodies, 0); }

std::vector<int> part_per_body(int bodies) {
  std::vector<int> part(bodies);
  std::iota(part.begin(), part.end(), 0);
  return part;
}

// Consecutive bodies in parts of `size`: on the random islands' lattice, connected slabs.
std::vector<int> slabs(int bodies, int size) {
  std::vector<int> part(bodies);
  for (int b = 0; b < bodies; ++b) part[b] = b / size;
  return part;
}

struct NamedParts {
  std::string name;
  std::vector<int> part_of_body;
};

std::vector<NamedParts> partitions(int bodies, std::mt19937& rng) {
  return {{"one part", one_part(bodies)},
          {"part per body", part_per_body(bodies)},
          {"slabs of 4", slabs(bodies, 4)},
          {"random 3", random_parts(bodies, 3, rng)},
          {"random bodies/2", random_parts(bodies, std::max(2, bodies / 2), rng)}};
}

// A random contact island (random_blcp.hpp) of about `rows` rows on `bodies` bodies.
void contact_island(std::mt19937& rng, int rows, int bodies, RandomIsland& island) {
  IslandOptions options;
  options.rows = rows;
  options.bodies = bodies;
  random_contact_island(rng, options, island);
}

constexpr double kEpsilon = std::numeric_limits<double>::epsilon();

double relative_difference(const Eigen::VectorXd& x, const Eigen::VectorXd& reference) {
  return (x - reference).norm() / reference.norm();
}

// --- the backend against the monolithic one -------------------------------------------------------

// Both backends solve E x = g in body space, so both lose the digits the small regularisation costs
// (sigma is a 1e-6 floor of A's diagonal); each is refined once against E, as the Newton solver
// refines, after which E x = g holds to the round-off of E x itself. Two such backward-stable
// answers differ by up to cond(E) eps: the pieces here reach cond_1(E) ~ 7e9, and above ~1e7 the
// monolithic answer is itself that far from an extended-precision solve. So they must agree to
// 1e-10, or to cond_1(E) eps (LU's estimate) where the piece's conditioning allows no better.
void expect_same_solution(const Eigen::MatrixXd& e, const Eigen::VectorXd& g, LinearSystem& monolithic,
                          LinearSystem& sub, const std::string& label) {
  const auto refined = [&](LinearSystem& system) {
    Eigen::VectorXd x, correction;
    system.solve(g, x);
    system.solve(g - e * x, correction);
    return Eigen::VectorXd(x + correction);
  };
  const Eigen::VectorXd reference = refined(monolithic), x = refined(sub);
  const double condition = 1 / e.partialPivLu().rcond();
  EXPECT_LE(relative_difference(x, reference), std::max(1e-10, condition * kEpsilon))
      << label << " cond_1 " << condition;
  EXPECT_LE((e * x - g).norm(), 1e-13 * e.norm() * x.norm()) << label;
}

TEST(SubstructuredSystem, SolvesRandomPiecesAsTheMonolithicBackendDoes) {
  std::mt19937 rng(11);
  int cases = 0;
  for (int seed = 0; seed < 6; ++seed) {
    RandomIsland island;
    contact_island(rng, 60 + 50 * seed, 6 + 4 * seed, island);
    const IslandSystem& s = island.system;
    for (const NamedParts& parts : partitions(s.bodies, rng))
      for (bool ties : {false, true}) {
        const std::string label = "seed " + std::to_string(seed) + " " + parts.name + (ties ? " ties" : "");
        MonolithicSystem monolithic;
        monolithic.assign(s);
        SubstructuredSystem sub;
        sub.assign(s, parts.part_of_body);
        for (int trial = 0; trial < 2; ++trial) {
          const Piece piece = random_piece(s, rng, ties);
          ASSERT_TRUE(monolithic.factor(piece)) << label;
          ASSERT_TRUE(sub.factor(piece)) << label;
          const Eigen::VectorXd g = uniform_matrix(rng, s.rows, 1);
          expect_same_solution(piece_matrix(s, piece), g, monolithic, sub, label);
          ++cases;
        }
      }
  }
  EXPECT_EQ(cases, 6 * 5 * 2 * 2);
}

// One backend assigned island after island, as a cache slot keeps it from step to step: to the same
// partition again (its parts and its interface keep their patterns and analyses), to another
// partition with as many parts (parts kept, patterns rebuilt) and to another island. Every solve
// is the monolithic one.
TEST(SubstructuredSystem, AssignedAgainSolvesAsTheMonolithicBackendDoes) {
  std::mt19937 rng(5);
  SubstructuredSystem sub;
  int cases = 0;
  for (int seed = 0; seed < 3; ++seed) {
    RandomIsland island;
    contact_island(rng, 120 + 40 * seed, 12 + 2 * seed, island);
    const IslandSystem& s = island.system;
    const std::vector<int> fours = slabs(s.bodies, 4), threes = random_parts(s.bodies, 3, rng);
    for (const std::vector<int>* parts : {&fours, &fours, &threes, &threes, &fours}) {
      const std::string label = "seed " + std::to_string(seed) + (parts == &fours ? " slabs of 4" : " random 3");
      MonolithicSystem monolithic;
      monolithic.assign(s);
      sub.assign(s, *parts);
      for (bool ties : {false, true}) {
        const Piece piece = random_piece(s, rng, ties);
        ASSERT_TRUE(monolithic.factor(piece)) << label;
        ASSERT_TRUE(sub.factor(piece)) << label;
        // The first factor() after assign() trusts no factor kept from before.
        if (!ties) EXPECT_EQ(sub.last().parts_refactored, sub.parts()) << label;
        const Eigen::VectorXd g = uniform_matrix(rng, s.rows, 1);
        expect_same_solution(piece_matrix(s, piece), g, monolithic, sub, label);
        ++cases;
      }
    }
  }
  EXPECT_EQ(cases, 3 * 5 * 2);
}

// Unrefined, the two backends agree to the digits the regularisation leaves each of them: both are
// within that of E^-1 g.
TEST(SubstructuredSystem, UnrefinedSolveIsTheMonolithicOneToTheRegularisationsDigits) {
  std::mt19937 rng(5);
  RandomIsland island;
  contact_island(rng, 200, 20, island);
  const IslandSystem& s = island.system;
  for (const NamedParts& parts : partitions(s.bodies, rng)) {
    MonolithicSystem monolithic;
    monolithic.assign(s);
    SubstructuredSystem sub;
    sub.assign(s, parts.part_of_body);
    const Piece piece = random_piece(s, rng, true);
    ASSERT_TRUE(monolithic.factor(piece));
    ASSERT_TRUE(sub.factor(piece));
    const Eigen::VectorXd g = uniform_matrix(rng, s.rows, 1);
    const Eigen::VectorXd exact = piece_matrix(s, piece).partialPivLu().solve(g);
    Eigen::VectorXd x, reference;
    monolithic.solve(g, reference);
    sub.solve(g, x);
    EXPECT_LE(relative_difference(reference, exact), 1e-6) << parts.name;
    EXPECT_LE(relative_difference(x, exact), 1e-6) << parts.name;
  }
}

// The interface bodies cover the rows between parts: every row's bodies off the interface lie in
// the part that holds it, every interface row's bodies are on the interface, and every interface
// body is on a row between two parts (none joins it needlessly).
TEST(SubstructuredSystem, InterfaceBodiesCoverTheRowsBetweenParts) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 20; ++trial) {
    RandomIsland island;
    contact_island(rng, 60 + 20 * trial, 8 + 2 * trial, island);
    const IslandSystem& s = island.system;
    for (const NamedParts& parts : partitions(s.bodies, rng)) {
      SubstructuredSystem sub;
      sub.assign(s, parts.part_of_body);
      std::vector<int> part_of(s.bodies, -1), between(s.bodies, 0);
      for (int j = 0; j < s.rows; ++j) {
        const int a = s.body[j][0], b = s.body[j][1];
        if (b >= 0 && parts.part_of_body[a] != parts.part_of_body[b]) between[a] = between[b] = 1;
        for (const int body : s.body[j]) {
          if (body < 0) continue;
          if (sub.part_of_row(j) < 0) {
            EXPECT_TRUE(sub.on_interface(body)) << parts.name;
          } else if (!sub.on_interface(body)) {
            EXPECT_TRUE(part_of[body] < 0 || part_of[body] == sub.part_of_row(j)) << parts.name;
            part_of[body] = sub.part_of_row(j);
          }
        }
      }
      for (int b = 0; b < s.bodies; ++b)
        if (sub.on_interface(b)) EXPECT_TRUE(between[b]) << parts.name << ", body " << b;
    }
  }
}

// A part is refactored only when its own rows' equations, ties or shifts change; interface rows
// changing re-form S but keep every part's factor. Every solve stays the monolithic one.
TEST(SubstructuredSystem, KeepsTheFactorOfPartsWhoseRowsDidNotChange) {
  std::mt19937 rng(3);
  RandomIsland island;
  contact_island(rng, 300, 60, island);
  const IslandSystem& s = island.system;
  SubstructuredSystem sub;
  sub.assign(s, slabs(s.bodies, 15));
  MonolithicSystem monolithic;
  monolithic.assign(s);
  const int parts = sub.parts();
  ASSERT_GE(parts, 2);
  ASSERT_GT(sub.interface_rows(), 0);
  Piece piece = random_piece(s, rng, true);
  const auto expect_monolithic_solve = [&](const std::string& label) {
    ASSERT_TRUE(monolithic.factor(piece)) << label;
    expect_same_solution(piece_matrix(s, piece), uniform_matrix(rng, s.rows, 1), monolithic, sub, label);
  };
  ASSERT_TRUE(sub.factor(piece));
  EXPECT_EQ(sub.last().parts_refactored, parts);
  expect_monolithic_solve("first");
  ASSERT_TRUE(sub.factor(piece));
  EXPECT_EQ(sub.last().parts_refactored, 0);
  expect_monolithic_solve("same piece");
  // A free row of part 1 gets a shift.
  int row = -1;
  for (int j = 0; j < s.rows && row < 0; ++j)
    if (sub.part_of_row(j) == 1 && piece.equation[j] == RowEquation::Free) row = j;
  ASSERT_GE(row, 0);
  piece.shift[row] += 0.5 * s.diag[row];
  ASSERT_TRUE(sub.factor(piece));
  EXPECT_EQ(sub.last().parts_refactored, 1);
  expect_monolithic_solve("shifted row of a part");
  // An interface normal (and its friction rows) fixed.
  int normal = -1;
  for (int j = 0; j < s.rows && normal < 0; ++j)
    if (sub.part_of_row(j) < 0 && s.normal_of[j] < 0 && piece.equation[j] == RowEquation::Free) normal = j;
  ASSERT_GE(normal, 0);
  for (int j = 0; j < s.rows; ++j)
    if (j == normal || s.normal_of[j] == normal) piece.equation[j] = RowEquation::Fixed;
  ASSERT_TRUE(sub.factor(piece));
  EXPECT_EQ(sub.last().parts_refactored, 0);
  expect_monolithic_solve("fixed interface contact");
  EXPECT_EQ(sub.total().parts_refactored, parts + 1);
}

// --- the Newton solver on either backend ----------------------------------------------------------

// Sets what the constraint graph reads of box_scenes.hpp's bodies.
void add_graph_fields(Scene& s) {
  const int n = static_cast<int>(s.bodies.inv_mass.size());
  s.bodies.is_static.assign(n, 0);
  s.bodies.mass.resize(n);
  for (int b = 0; b < n; ++b) s.bodies.mass[b] = 1 / s.bodies.inv_mass[b];
}

// Islands of sliding boxes (box_scenes.hpp), whose answers Newton reaches as the exact solution of
// their last piece: a pair sliding apart, a tower of four whose upper boxes slide and spin, and a
// tower of four all sliding.
Scene sliding_islands() {
  Scene s;
  add_box_on(s, -1, 2.0, 0.5, 1.0, 0.3);
  add_box_on(s, 0, 1.0, 0.5, -1.0, 0.3);
  add_box_on(s, -1, 5.0, 0.5, 0.0, 0.3);
  add_box_on(s, 2, 1.0, 0.5, 0.5, 0.3);
  add_box_on(s, 3, 3.0, 0.5, -1.0, 0.2, 0.4, 1.0);
  add_box_on(s, 4, 0.5, 0.5, 2.0, 0.8);
  add_box_on(s, -1, 4.0, 0.5, 1.5, 0.3);
  add_box_on(s, 6, 1.0, 0.5, -1.0, 0.3, 0.5);
  add_box_on(s, 7, 2.0, 0.5, 2.0, 0.2, -0.5, 1.0);
  add_box_on(s, 8, 0.5, 0.5, -2.0, 0.4, 1.0, -1.0);
  finish(s);
  add_graph_fields(s);
  return s;
}

// Resting towers of boxes on four corner contacts each: a tower of five, and a 1 : 1000 : 1 stack.
Scene resting_islands() {
  Scene s;
  add_box_on(s, -1, 2.0, 0.4, 0.0, 0.5);
  for (int k = 0; k < 4; ++k) add_box_on(s, k, 1.0 + k, 0.4, 0.0, 0.5);
  add_box_on(s, -1, 1.0, 0.5, 0.0, 0.5);
  add_box_on(s, 5, 1000.0, 0.5, 0.0, 0.4);
  add_box_on(s, 6, 1.0, 0.5, 0.0, 0.6);
  finish(s);
  return s;
}

struct NewtonAnswer {
  NewtonResult result;
  Eigen::VectorXd lambda;
  std::vector<RowState> state;
};

NewtonAnswer solve_cold(const IslandSystem& s, LinearSystem& system) {
  NewtonAnswer a;
  a.lambda.setZero(s.rows);
  a.state.assign(s.rows, RowState::Lower);
  NewtonWorkspace ws;
  a.result = solve_newton(s, system, 40, a.lambda, a.state, ws);
  return a;
}

// Runs `check(s, reference, answer, label)` for every island of `scene`, the monolithic answer
// against the substructured one for every partition and both dense and sparse parts.
template <class Check>
void compare_newton(const Scene& scene, Check&& check) {
  const std::vector<int> local = local_row_index(scene.rows, scene.islands);
  std::mt19937 rng(17);
  for (int i = 0; i < static_cast<int>(scene.islands.count()); ++i) {
    IslandSystem s;
    s.gather(scene.rows, scene.bodies, scene.islands, i, local);
    MonolithicSystem monolithic;
    monolithic.assign(s);
    const NewtonAnswer reference = solve_cold(s, monolithic);
    ASSERT_TRUE(reference.result.settled) << "island " << i;
    for (const NamedParts& parts : partitions(s.bodies, rng)) {
      SubstructuredSystem sub;
      sub.assign(s, parts.part_of_body);
      const NewtonAnswer answer = solve_cold(s, sub);
      EXPECT_TRUE(answer.result.settled);
      check(s, reference, answer, "island " + std::to_string(i) + " " + parts.name);
    }
  }
}

TEST(SubstructuredSystem, NewtonReachesTheMonolithicAnswerOnSlidingBoxes) {
  compare_newton(sliding_islands(), [](const IslandSystem&, const NewtonAnswer& reference, const NewtonAnswer& answer,
                                       const std::string& label) {
    EXPECT_LE((answer.lambda - reference.lambda).cwiseAbs().maxCoeff(), 1e-8 * reference.lambda.cwiseAbs().maxCoeff())
        << label;
    EXPECT_EQ(answer.state, reference.state) << label;
  });
}

// On resting towers the corner contacts are redundant, so the impulses are fixed only by the 1e-6
// regularisation, and Newton's path turns on round-off: perturbing the monolithic backend's own
// solves by 1e-14 relative takes the tower of five from 5 factorisations to 18 and moves its
// impulses by 1e-7 relative, at a settled residual of 1.5e-12. What any backend must reproduce is
// then the motion: settled, with the bodies' velocity changes M^-1 J^T lambda equal to 1e-8.
TEST(SubstructuredSystem, NewtonReachesTheMonolithicMotionOnRestingTowers) {
  compare_newton(resting_islands(), [](const IslandSystem& s, const NewtonAnswer& reference,
                                       const NewtonAnswer& answer, const std::string& label) {
    Eigen::VectorXd du, du_reference;
    apply_mjt(s, answer.lambda, du);
    apply_mjt(s, reference.lambda, du_reference);
    EXPECT_LE((du - du_reference).cwiseAbs().maxCoeff(), 1e-8 * du_reference.cwiseAbs().maxCoeff()) << label;
  });
}

// The stage driver: partition nodes map to island bodies through the graph; its answer is
// solve_newton_direct's.
TEST(SolveNewtonSubstructured, SolvesTheStageAsTheMonolithicBackendDoes) {
  Scene reference = sliding_islands(), scene = sliding_islands();
  ConstraintGraph graph;
  build_constraint_graph(scene.rows, scene.bodies, graph);
  Partition partition;
  partition.part_of.resize(graph.node_count());
  for (int v = 0; v < graph.node_count(); ++v) partition.part_of[v] = (v * 7) % 5;  // parts span islands
  partition.part_count = 5;
  const SolverParams params;
  const SolveStats direct = solve_newton_direct(reference.rows, reference.bodies, reference.islands, params);
  const NewtonSubstructuredReport report =
      solve_newton_substructured(scene.rows, scene.bodies, scene.islands, graph, partition, params);
  EXPECT_EQ(direct.unsettled, 0);
  EXPECT_EQ(report.solve.unsettled, 0);
  EXPECT_GT(report.parts, static_cast<int>(scene.islands.count()));
  EXPECT_GT(report.interface_rows, 0);
  EXPECT_GT(report.interface_bodies, 0);
  EXPECT_GT(report.parts_refactored, 0);
  EXPECT_GE(report.solve.work_ms, report.solve.critical_path_ms);
  double largest = 0, difference = 0;
  for (std::size_t j = 0; j < scene.rows.size(); ++j) {
    largest = std::max(largest, std::abs(reference.rows.lambda[j]));
    difference = std::max(difference, std::abs(scene.rows.lambda[j] - reference.rows.lambda[j]));
    EXPECT_EQ(scene.rows.state[j], reference.rows.state[j]) << "row " << j;
  }
  EXPECT_LE(difference, 1e-8 * largest);
}

// --- determinism ---------------------------------------------------------------------------------

TEST(SubstructuredSystem, OneAndTwoThreadsGiveBitwiseTheSameAnswer) {
  std::mt19937 rng(23);
  RandomIsland island;
  contact_island(rng, 300, 30, island);
  const IslandSystem& s = island.system;
  const std::vector<int> part_of_body = random_parts(s.bodies, 6, rng);
  const Piece piece = random_piece(s, rng, true);
  const Eigen::VectorXd g = uniform_matrix(rng, s.rows, 1);
  const auto run = [&](int threads, NewtonAnswer& newton) {
    const tbb::global_control control(tbb::global_control::max_allowed_parallelism, threads);
    SubstructuredSystem sub;
    sub.assign(s, part_of_body);
    EXPECT_TRUE(sub.factor(piece));
    Eigen::VectorXd x;
    sub.solve(g, x);
    newton = solve_cold(s, sub);
    return x;
  };
  NewtonAnswer one, two;
  const Eigen::VectorXd x1 = run(1, one), x2 = run(2, two);
  EXPECT_TRUE(x1 == x2);
  EXPECT_GT(one.result.factorizations, 0);
  EXPECT_TRUE(one.lambda == two.lambda);
  EXPECT_EQ(one.state, two.state);
}

}  // namespace
}  // namespace rbpart
