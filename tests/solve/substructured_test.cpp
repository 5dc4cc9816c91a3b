// The substructured solver (DESIGN.md §7) against the monolithic direct solver, its reference: on
// random block-arrowhead BLCPs, on steps of real scenes, and on cases built to stress the
// interface/sub-system iteration, for several partitions and 1 and 2 threads, it must give the
// same velocities (max |M^-1 J^T dlambda| <= 1e-8 of its size), impulses to the conditioning of
// redundant contacts (<= 1e-6 max |lambda|), the same index sets and a scaled residual
// <= 1e-9, and bitwise the same answer for any thread count (its sums run in a fixed order).
#include "solve/substructured.hpp"

#include "graph/constraint_graph.hpp"
#include "graph/islands.hpp"
#include "scenes/scenes.hpp"
#include "solve/island_system.hpp"
#include "solve/solve.hpp"
#include "solve/sub_island.hpp"

#include "solve/random_blcp.hpp"
#include "tests/solve/substructured_problems.hpp"

#include <gtest/gtest.h>
#include <rbpart/world.hpp>
#include <tbb/global_control.h>

#include <Eigen/Cholesky>

#include <algorithm>

namespace rbpart {
namespace {

constexpr double kGravity = 9.81, kStep = 1.0 / 60.0;

using testing::bfs_partition;
using Problem = testing::StepProblem;

// --- partitions built here (any assignment of nodes to parts is valid input) ---------------------

// Consecutive node ranges of `size` nodes (parts may be disconnected).
Partition chunk_partition(int nodes, int size) {
  Partition p;
  p.part_of.resize(nodes);
  for (int v = 0; v < nodes; ++v) p.part_of[v] = v / size;
  p.part_count = (nodes + size - 1) / size;
  return p;
}

// Node v in part v mod parts: every part scattered, every edge likely an interface.
Partition round_robin_partition(int nodes, int parts) {
  Partition p;
  p.part_of.resize(nodes);
  for (int v = 0; v < nodes; ++v) p.part_of[v] = v % parts;
  p.part_count = parts;
  return p;
}

Partition explicit_partition(std::vector<int> part_of) {
  Partition p;
  p.part_count = *std::max_element(part_of.begin(), part_of.end()) + 1;
  p.part_of = std::move(part_of);
  return p;
}

// --- comparison with the monolithic solver ------------------------------------------------------

// The exact friction rule (friction_tolerance 0: passes settle only on round-off), so that both
// solvers take the same path; at the default tolerance a pass whose mismatch sits near it may settle
// in one solver and go on to the coupled step in the other. The iteration cap and halving budget
// are far above what any case needs (the defaults are tuned for speed, not for these cold starts):
// the cases check that the iteration itself reaches the answer, so a fallback, counted, is a
// failure of the iteration.
SolverParams default_params() {
  SolverParams params;
  params.friction_tolerance = 0;
  params.substructured_max_iterations = 100;
  params.substructured_max_halvings = 1000;
  return params;
}

struct Outcome {
  Rows rows;
  SubstructuredReport report;
};

Outcome run_substructured(const Problem& problem, const Partition& partition, const SolverParams& params,
                          int threads) {
  const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  Outcome out{problem.rows, {}};
  out.report = solve_substructured(out.rows, problem.bodies, problem.islands, problem.graph, partition, params);
  return out;
}

// Interface rows and bodies of `partition`, counted independently of the solver.
void count_interface(const Problem& problem, const Partition& partition, int& rows, int& bodies) {
  std::vector<char> interface_body(problem.graph.node_count(), 0);
  rows = 0;
  for (std::size_t j = 0; j < problem.rows.size(); ++j) {
    const int a = problem.rows.body[j][0], b = problem.rows.body[j][1];
    if (a < 0 || b < 0) continue;
    const int na = problem.graph.node_of[a], nb = problem.graph.node_of[b];
    if (partition.part_of[na] == partition.part_of[nb]) continue;
    ++rows;
    interface_body[na] = interface_body[nb] = 1;
  }
  bodies = static_cast<int>(std::count(interface_body.begin(), interface_body.end(), 1));
}

// Velocity change M^-1 J^T lambda of every body: what the impulses do to the bodies.
std::vector<Vec6> velocity_change(const Problem& problem, const std::vector<double>& lambda) {
  const Bodies& b = problem.bodies;
  std::vector<Vec6> du(b.inv_mass.size(), Vec6::Zero());
  for (std::size_t j = 0; j < problem.rows.size(); ++j)
    for (int side = 0; side < 2; ++side) {
      const int k = problem.rows.body[j][side];
      if (k < 0) continue;
      const Vec6& jac = problem.rows.jac[j][side];
      du[k].head<3>() += b.inv_mass[k] * lambda[j] * jac.head<3>();
      du[k].tail<3>() += b.inv_inertia[k] * (lambda[j] * jac.tail<3>());
    }
  return du;
}

// Solves `problem` monolithically once and by substructuring with `partition` at 1 and 2 threads;
// checks the answers agree, the sets match, the residual is tiny and the thread counts agree bit
// for bit. Returns the 1-thread report.
SubstructuredReport expect_same_as_direct(const Problem& problem, const Partition& partition,
                                          const SolverParams& params, const std::string& label) {
  Rows direct = problem.rows;
  const SolveReport reference = solve_direct(direct, problem.bodies, problem.islands, params);
  EXPECT_EQ(reference.failures, 0) << label;
  double size = 0;
  for (double l : direct.lambda) size = std::max(size, std::abs(l));

  const Outcome one = run_substructured(problem, partition, params, 1);
  const Outcome two = run_substructured(problem, partition, params, 2);
  for (const Outcome* o : {&one, &two}) {
    EXPECT_EQ(o->report.solve.failures, 0) << label;
    // A friction loop that ends unsettled leaves the same residual in both solvers.
    EXPECT_LE(o->report.solve.residual, std::max(1e-9, 2 * reference.residual)) << label;
    double difference = 0;
    int mismatched = 0;
    for (std::size_t j = 0; j < direct.size(); ++j) {
      difference = std::max(difference, std::abs(o->rows.lambda[j] - direct.lambda[j]));
      mismatched += o->rows.state[j] != direct.state[j];
    }
    // With the same sets both answers solve the same linear system; the impulses agree to its
    // conditioning. Redundant contacts (four corners of a face) are told apart only by the sigma
    // floor (1e-6), and sliding rows tied to their normals make the system unsymmetric, so the
    // impulses can differ by ~1e-7 relative along the corners' null wrench; the velocities, which
    // that wrench does not move, agree to round-off.
    EXPECT_LE(difference, 1e-6 * size) << label;
    EXPECT_EQ(mismatched, 0) << label;
    const std::vector<Vec6> du_direct = velocity_change(problem, direct.lambda);
    const std::vector<Vec6> du = velocity_change(problem, o->rows.lambda);
    double du_size = 0, du_difference = 0;
    for (std::size_t k = 0; k < du.size(); ++k) {
      du_size = std::max(du_size, du_direct[k].norm());
      du_difference = std::max(du_difference, (du[k] - du_direct[k]).norm());
    }
    EXPECT_LE(du_difference, 1e-8 * du_size) << label;
  }
  // Fixed reduction order: the thread count changes nothing, not even round-off.
  for (std::size_t j = 0; j < direct.size(); ++j) {
    EXPECT_EQ(one.rows.lambda[j], two.rows.lambda[j]) << label << " row " << j;
    EXPECT_EQ(one.rows.state[j], two.rows.state[j]) << label << " row " << j;
  }
  int interface_rows = 0, interface_bodies = 0;
  count_interface(problem, partition, interface_rows, interface_bodies);
  if (one.report.fallbacks == 0 && one.report.parts > static_cast<int>(problem.islands.count())) {
    EXPECT_EQ(one.report.interface_rows, interface_rows) << label;
    EXPECT_EQ(one.report.interface_bodies, interface_bodies) << label;
  }
  return one.report;
}

// --- random block-arrowhead BLCPs -----------------------------------------------------------------

Problem random_problem(std::uint32_t seed, int rows, int bodies) {
  std::mt19937 rng(seed);
  testing::IslandOptions opt;
  opt.rows = rows;
  opt.bodies = bodies;
  testing::RandomIsland island;
  testing::random_contact_island(rng, opt, island);
  Problem p;
  p.rows = island.rows;
  // Friction rows keep their fixed boxes: a fixed-bounds BLCP, solved exactly by both solvers (the
  // friction outer loop is exercised by the scenes below).
  std::fill(p.rows.normal_of.begin(), p.rows.normal_of.end(), -1);
  p.bodies = island.bodies;
  const int nb = static_cast<int>(p.bodies.inv_mass.size());
  p.bodies.is_static.assign(nb, 0);
  p.bodies.x.assign(nb, Vec3::Zero());
  p.bodies.mass.resize(nb);
  for (int b = 0; b < nb; ++b) p.bodies.mass[b] = 1 / p.bodies.inv_mass[b];
  p.islands = island.islands;
  build_constraint_graph(p.rows, p.bodies, p.graph);
  return p;
}

TEST(Substructured, RandomArrowheadBlcpsMatchTheDirectSolver) {
  int split = 0, loops = 0;
  for (std::uint32_t seed = 0; seed < 6; ++seed) {
    const Problem problem = random_problem(100 + seed, 120 + 40 * seed, 12 + 3 * seed);
    const int nodes = problem.graph.node_count();
    for (int nmax : {2, 3, 5, 8, nodes / 2, nodes}) {
      const std::string label = "seed " + std::to_string(seed) + " nmax " + std::to_string(nmax);
      const SubstructuredReport bfs = expect_same_as_direct(problem, bfs_partition(problem.graph, nmax), default_params(), "bfs " + label);
      expect_same_as_direct(problem, chunk_partition(nodes, nmax), default_params(), "chunks " + label);
      split += bfs.parts > 1;
      loops += bfs.loop_iterations;
      EXPECT_EQ(bfs.fallbacks, 0) << label;
      if (nmax >= nodes) EXPECT_EQ(bfs.parts, 1) << label;
    }
    expect_same_as_direct(problem, round_robin_partition(nodes, 3), default_params(), "round robin");
  }
  EXPECT_GE(split, 20);
  EXPECT_GT(loops, split);
}

// The island as a BlcpMatrix (the coupled friction step runs on it): its block elimination through
// the parts' body-space factors and S~ solves A_FF x = b, to ~1e-6 before refinement (Woodbury
// cancels the digits 1/sigma costs) and to round-off after two refinements against A.
TEST(SubstructuredMatrix, BlockEliminationSolvesTheFreeBlock) {
  std::mt19937 rng(7);
  for (int nmax : {2, 4, 9}) {
    const Problem problem = random_problem(400 + nmax, 240, 24);
    IslandSystem s;
    s.gather(problem.rows, problem.bodies, problem.islands, 0, local_row_index(problem.rows, problem.islands));
    const Partition partition = bfs_partition(problem.graph, nmax);
    std::vector<int> part_of_body(s.bodies);
    for (int b = 0; b < s.bodies; ++b) part_of_body[b] = partition.part_of[problem.graph.node_of[s.global_bodies[b]]];
    SubstructuredIsland island;
    island.assign(s, part_of_body, partition.part_count);
    ASSERT_GT(island.interface_rows(), 0);
    Eigen::MatrixXd a;
    build_dense(s, a);
    for (double free_fraction : {1.0, 0.6}) {
      std::vector<char> free(s.rows);
      std::vector<int> index;
      for (int j = 0; j < s.rows; ++j) {
        free[j] = std::uniform_real_distribution<double>(0, 1)(rng) < free_fraction;
        if (free[j]) index.push_back(j);
      }
      ASSERT_EQ(island.prepare(free), 1);
      const int nf = static_cast<int>(index.size());
      Eigen::MatrixXd aff(nf, nf);
      for (int r = 0; r < nf; ++r)
        for (int c = 0; c < nf; ++c) aff(r, c) = a(index[r], index[c]);
      const Eigen::VectorXd b = testing::uniform_matrix(rng, s.rows, 1);
      Eigen::VectorXd bf(nf);
      for (int r = 0; r < nf; ++r) bf[r] = b[index[r]];
      const Eigen::VectorXd reference = aff.llt().solve(bf);
      Eigen::VectorXd x = b, ax, correction;
      island.solve(x);
      auto error = [&] {
        double e = 0;
        for (int r = 0; r < nf; ++r) e = std::max(e, std::abs(x[index[r]] - reference[r]));
        return e / reference.cwiseAbs().maxCoeff();
      };
      for (int j = 0; j < s.rows; ++j)
        if (!free[j]) EXPECT_EQ(x[j], b[j]) << "entries outside F are left as they are";
      EXPECT_LE(error(), 1e-6) << nmax;
      for (int k = 0; k < 2; ++k) {
        Eigen::VectorXd masked = x;
        for (int j = 0; j < s.rows; ++j)
          if (!free[j]) masked[j] = 0;
        island.multiply(masked, ax);
        correction = ax - b;
        island.solve(correction);
        for (int j = 0; j < s.rows; ++j)
          if (free[j]) x[j] -= correction[j];
      }
      EXPECT_LE(error(), 1e-9) << nmax;
    }
  }
}

// Cold start (every row at its lower bound, no impulse): the iteration has to find every set.
TEST(Substructured, ColdStartedRandomBlcpsMatchTheDirectSolver) {
  for (std::uint32_t seed = 0; seed < 4; ++seed) {
    Problem problem = random_problem(200 + seed, 200, 20);
    std::fill(problem.rows.lambda.begin(), problem.rows.lambda.end(), 0.0);
    std::fill(problem.rows.state.begin(), problem.rows.state.end(), RowState::Lower);
    for (int nmax : {2, 4, 7})
      expect_same_as_direct(problem, bfs_partition(problem.graph, nmax), default_params(),
                            "seed " + std::to_string(seed) + " nmax " + std::to_string(nmax));
  }
}

// --- real scene steps --------------------------------------------------------------------------------

// Steps a scene with the direct solver and returns the last step's problem, warm started as the
// World warm started it.
Problem scene_problem(const SceneDef& scene, int steps) {
  World world(scene, StepParams{}, default_params(), PartitionParams{});
  for (int i = 1; i < steps; ++i) world.step();
  return testing::capture_step(world);
}

TEST(Substructured, SceneStepsMatchTheDirectSolver) {
  struct Case {
    std::string scene;
    std::vector<std::pair<std::string, std::string>> overrides;
    int steps;
    std::vector<int> nmax;
  };
  const std::vector<Case> cases = {
      {"rock_pile", {{"rocks", "40"}}, 60, {4, 8, 16}},     // rocks landing on each other
      {"rock_pile", {{"rocks", "40"}}, 150, {3, 10, 40}},   // the formed pile
      {"box_stack", {{"mass_odd", "1000"}, {"mass_even", "1"}}, 30, {1, 2, 5}},
      {"chain_drop", {{"links", "24"}}, 70, {2, 6, 12}},    // chain across the bar, joints and contacts
      {"log_tower", {{"layers", "6"}}, 60, {3, 9}},
  };
  for (const Case& c : cases) {
    const Problem problem = scene_problem(make_builtin_scene(c.scene, c.overrides), c.steps);
    ASSERT_GT(problem.rows.size(), 0u) << c.scene;
    for (int nmax : c.nmax) {
      const std::string label = c.scene + " step " + std::to_string(c.steps) + " nmax " + std::to_string(nmax);
      const SubstructuredReport report =
          expect_same_as_direct(problem, bfs_partition(problem.graph, nmax), default_params(), label);
      EXPECT_EQ(report.fallbacks, 0) << label;
    }
  }
}

// --- cases built to stress the iteration -----------------------------------------------------------

// A cube of half extent a and mass m on static ground (below = -1) or face-down on cube `below`,
// four corner contacts (normal and two friction rows each), with velocity `v` (gravity applied)
// before contact.
int add_cube(Problem& p, std::vector<Vec6>& velocity, int below, double m, double a, const Vec3& v, double mu) {
  const int body = static_cast<int>(p.bodies.inv_mass.size());
  const double inertia = m / 3 * (2 * a * a);
  p.bodies.inv_mass.push_back(1 / m);
  p.bodies.mass.push_back(m);
  p.bodies.is_static.push_back(0);
  p.bodies.inv_inertia.push_back(Mat3::Identity() / inertia);
  p.bodies.x.push_back(below < 0 ? Vec3(3.0 * body, 0, a) : Vec3(p.bodies.x[below] + Vec3(0, 0, 2 * a)));
  Vec6 u;
  u << v + Vec3(0, 0, -kGravity * kStep), Vec3::Zero();
  velocity.push_back(u);
  for (double cx : {-a, a})
    for (double cy : {-a, a}) {
      const Vec3 r(cx, cy, -a), r_below(cx, cy, a);
      auto row = [&](RowKind kind, const Vec3& dir) {
        const int j = p.rows.add(kind, body, below, p.rows.size());
        p.rows.jac[j][0] << dir, r.cross(dir);
        double jmj = dir.squaredNorm() / m + r.cross(dir).squaredNorm() / inertia;
        p.rows.q[j] = p.rows.jac[j][0].dot(u);
        if (below >= 0) {
          p.rows.jac[j][1] << -dir, -r_below.cross(dir);
          jmj += p.bodies.inv_mass[below] + r_below.cross(dir).squaredNorm() * p.bodies.inv_inertia[below](0, 0);
          p.rows.q[j] += p.rows.jac[j][1].dot(velocity[below]);
        }
        p.rows.sigma[j] = 1e-6 * jmj;
        return j;
      };
      const int n = row(RowKind::Normal, Vec3::UnitZ());
      for (const Vec3& t : {Vec3(Vec3::UnitX()), Vec3(Vec3::UnitY())}) {
        const int f = row(RowKind::Friction, t);
        p.rows.normal_of[f] = n;
        p.rows.mu[f] = mu;
      }
    }
  return body;
}

void finish(Problem& p) {
  build_islands(p.rows, static_cast<int>(p.bodies.inv_mass.size()), p.islands);
  build_constraint_graph(p.rows, p.bodies, p.graph);
}

// One cube per part: every contact between cubes is an interface row.
Partition one_part_per_body(const Problem& p) {
  std::vector<int> part(p.graph.node_count());
  for (int v = 0; v < p.graph.node_count(); ++v) part[v] = v;
  return explicit_partition(part);
}

// The top cube of a stack of three is pushed along x with speeds from well inside the sticking
// range to well into sliding and back, each solve warm started from the previous answer: the
// interface contacts switch between sticking and sliding, and the iteration must follow.
TEST(Substructured, InterfaceContactsSwitchBetweenStickingAndSliding) {
  const double mu = 0.4;
  int sliding = 0, sticking = 0;
  Rows warm;
  for (double vx : {0.0, 0.02, 0.05, 0.2, 1.0, 3.0, 0.5, 0.1, 0.03, 0.0}) {
    Problem p;
    std::vector<Vec6> velocity;
    const int bottom = add_cube(p, velocity, -1, 4.0, 0.5, Vec3::Zero(), 0.8);
    const int middle = add_cube(p, velocity, bottom, 4.0, 0.5, Vec3::Zero(), 0.8);
    add_cube(p, velocity, middle, 10.0, 0.5, Vec3(vx, 0.3 * vx, 0), mu);
    finish(p);
    if (!warm.lambda.empty()) {
      p.rows.lambda = warm.lambda;
      p.rows.state = warm.state;
    }
    const std::string label = "vx " + std::to_string(vx);
    const SubstructuredReport report = expect_same_as_direct(p, one_part_per_body(p), default_params(), label);
    EXPECT_EQ(report.parts, 3) << label;
    EXPECT_EQ(report.interface_rows, 24) << label;
    warm = run_substructured(p, one_part_per_body(p), default_params(), 1).rows;
    // The top cube's x friction rows (rows 24.. of the third cube): on a bound = sliding.
    for (std::size_t j = 24; j < warm.size(); ++j)
      if (warm.kind[j] == RowKind::Friction && warm.jac[j][0][0] == 1.0)
        (warm.state[j] == RowState::Free ? sticking : sliding) += 1;
  }
  EXPECT_GT(sliding, 0);
  EXPECT_GT(sticking, 0);
}

// A 1000 kg cube between two 1 kg cubes, in a part of its own: the interface carries a 1000:1
// mass ratio on both sides.
TEST(Substructured, HeavyBodyOnTheInterface) {
  for (double vx : {0.0, 0.5}) {
    Problem p;
    std::vector<Vec6> velocity;
    const int a = add_cube(p, velocity, -1, 1.0, 0.25, Vec3::Zero(), 0.5);
    const int heavy = add_cube(p, velocity, a, 1000.0, 0.25, Vec3(vx, 0, 0), 0.5);
    const int c = add_cube(p, velocity, heavy, 1.0, 0.25, Vec3(-vx, 0, 0), 0.5);
    add_cube(p, velocity, c, 1.0, 0.25, Vec3::Zero(), 0.5);
    finish(p);
    expect_same_as_direct(p, explicit_partition({0, 1, 2, 2}), default_params(), "vx " + std::to_string(vx));
    expect_same_as_direct(p, explicit_partition({0, 0, 1, 1}), default_params(), "halves vx " + std::to_string(vx));
  }
}

// The bottom cube is thrown upwards off the ground, carrying the top cube: every row of its part
// (the ground contacts) is clamped at zero, and the top cube's part has no rows of its own.
TEST(Substructured, PartWithEveryRowClampedAndPartWithoutRows) {
  Problem p;
  std::vector<Vec6> velocity;
  const int bottom = add_cube(p, velocity, -1, 2.0, 0.5, Vec3(0, 0, 3.0), 0.5);
  add_cube(p, velocity, bottom, 2.0, 0.5, Vec3(0.2, 0, 0), 0.5);
  finish(p);
  const SubstructuredReport report = expect_same_as_direct(p, one_part_per_body(p), default_params(), "thrown");
  EXPECT_EQ(report.parts, 2);
  Outcome out = run_substructured(p, one_part_per_body(p), default_params(), 1);
  for (int j = 0; j < 12; ++j) {
    EXPECT_EQ(out.rows.state[j], RowState::Lower) << j;
    EXPECT_EQ(out.rows.lambda[j], 0.0) << j;
  }
  double top_normal = 0;
  for (int j = 12; j < 24; ++j)
    if (out.rows.kind[j] == RowKind::Normal) top_normal += out.rows.lambda[j];
  EXPECT_GT(top_normal, 0.0);  // the bottom cube pushes the top one up
}

// Two islands: a stack split into parts beside a stack that is one part (parts with no interface
// rows), and the all-in-one partition, which must take the monolithic path.
TEST(Substructured, IslandsThatAreOnePartAndMixedIslands) {
  Problem p;
  std::vector<Vec6> velocity;
  int below = -1;
  for (int k = 0; k < 4; ++k) below = add_cube(p, velocity, below, 3.0, 0.4, Vec3(0.1 * k, 0, 0), 0.6);
  below = -1;
  for (int k = 0; k < 3; ++k) below = add_cube(p, velocity, below, 2.0, 0.3, Vec3(-0.2 * k, 0, 0), 0.6);
  finish(p);
  ASSERT_EQ(p.islands.count(), 2u);
  const SubstructuredReport mixed =
      expect_same_as_direct(p, explicit_partition({0, 0, 1, 1, 2, 2, 2}), default_params(), "mixed");
  EXPECT_EQ(mixed.parts, 3);
  EXPECT_EQ(mixed.interface_rows, 12);
  EXPECT_GT(mixed.loop_iterations, 0);
  const SubstructuredReport whole =
      expect_same_as_direct(p, explicit_partition({0, 0, 0, 0, 1, 1, 1}), default_params(), "whole");
  EXPECT_EQ(whole.parts, 2);
  EXPECT_EQ(whole.interface_rows, 0);
  EXPECT_EQ(whole.loop_iterations, 0);
}

// With an iteration cap of one, a cold start cannot settle: every split island falls back to the
// monolithic solve, counted, and the answer is still the direct one.
TEST(Substructured, IterationCapFallsBackToTheMonolithicSolve) {
  Problem problem = random_problem(300, 200, 20);
  std::fill(problem.rows.lambda.begin(), problem.rows.lambda.end(), 0.0);
  std::fill(problem.rows.state.begin(), problem.rows.state.end(), RowState::Lower);
  SolverParams params;
  params.substructured_max_iterations = 1;
  const SubstructuredReport capped = expect_same_as_direct(problem, bfs_partition(problem.graph, 3), params, "cap 1");
  EXPECT_EQ(capped.fallbacks, 1);
  const SubstructuredReport free =
      expect_same_as_direct(problem, bfs_partition(problem.graph, 3), default_params(), "cap 100");
  EXPECT_EQ(free.fallbacks, 0);
  EXPECT_GT(free.loop_iterations, free.solve.friction_passes);
}

}  // namespace
}  // namespace rbpart

