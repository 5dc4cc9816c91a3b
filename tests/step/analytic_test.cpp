// Whole-step tests against closed-form mechanics: friction on a slope, a pendulum's period,
// resting stacks (also at 1000:1 mass ratio) and a heavy-ended chain's joints, for the direct and
// the substructured solver (two bodies per part, so that the stacks and the chain have interfaces).
// Both must also settle every step (residual at most 1e-9, the one criterion) within the budget of
// factorisations per island.
#include <gtest/gtest.h>
#include <rbpart/world.hpp>

#include <cmath>

#include "scene/bodies.hpp"
#include "solve/newton.hpp"
#include "scenes/scenes.hpp"
#include "step/world_internals.hpp"
#include "support/joint_gap.hpp"

namespace rbpart {
namespace {

constexpr double kG = 9.81;

SceneDef scene(const std::string& name, std::vector<std::pair<std::string, std::string>> sets) {
  return make_builtin_scene(name, sets);
}

class Analytic : public ::testing::TestWithParam<SolverKind> {
 public:
  World world(const SceneDef& def) const {
    SolverParams solver;
    solver.kind = GetParam();
    PartitionParams partition;
    if (solver.kind == SolverKind::Substructured) {
      partition.partitioner = PartitionerKind::Bfs;
      partition.nmax = 2;
    }
    return World(def, StepParams{}, solver, partition);
  }
  // One step, checked to have settled within the budget.
  static const StepStats& step(World& w) {
    const StepStats& s = w.step();
    EXPECT_LE(s.solve.residual, kSettledResidual) << "step " << s.step;
    EXPECT_LE(s.solve.island_factorizations, w.solver_params().max_factorizations) << "step " << s.step;
    EXPECT_LE(s.solve.island_factorizations, s.solve.factorizations) << "step " << s.step;
    EXPECT_LE(s.solve.factorizations, s.islands * s.solve.island_factorizations) << "step " << s.step;
    return s;
  }
};

// Position of the block along the downhill direction of the slope scene.
double downhill(const World& w, double theta) {
  const Vec3 d(std::cos(theta), 0, -std::sin(theta));
  return world_bodies(w).x[1].dot(d);
}

TEST_P(Analytic, SlopeBlockBelowFrictionAngleStaysPut) {
  // tan(20 deg) = 0.36 < mu = 0.5.
  World w = world(scene("slope", {{"angle", "20"}, {"friction", "0.5"}}));
  const Vec3 start = world_bodies(w).x[1];
  for (int i = 0; i < 120; ++i) step(w);  // 2 s
  EXPECT_LT((world_bodies(w).x[1] - start).norm(), 1e-3);
}

TEST_P(Analytic, SlopeBlockBelowFrictionAngleDoesNotCreep) {
  // A sticking friction row obeys J_t u = -sigma_t lambda_t: under a plain regularisation of
  // contact_prox's size (1e-3 of the row's diagonal) the block creeps downhill at ~1e-4 m/s. The
  // contacts' proximal term yields only while the impulses change, so once the block rests it creeps
  // only at the floor's rate (1e-6 of the diagonal, ~1e-7 m/s).
  const double theta = 20 * M_PI / 180;
  const auto creep = [&](const StepParams& params) {
    SolverParams solver;
    solver.kind = GetParam();
    PartitionParams partition;
    if (solver.kind == SolverKind::Substructured) partition.partitioner = PartitionerKind::Bfs;
    World w(scene("slope", {{"angle", "20"}, {"friction", "0.5"}}), params, solver, partition);
    for (int i = 0; i < 60; ++i) step(w);
    const double start = downhill(w, theta);
    for (int i = 0; i < 120; ++i) step(w);  // 2 s
    return downhill(w, theta) - start;
  };
  StepParams plain;
  plain.contact_prox = 0;
  plain.sigma_floor = StepParams{}.contact_prox;
  EXPECT_GT(creep(plain), 1e-4);
  EXPECT_LT(std::abs(creep(StepParams{})), 1e-5);
}

TEST_P(Analytic, SlopeBlockAboveFrictionAngleSlidesWithCoulombAcceleration) {
  const double theta = 35 * M_PI / 180, mu = 0.3;
  World w = world(scene("slope", {{"angle", "35"}, {"friction", "0.3"}}));
  const double expected = kG * (std::sin(theta) - mu * std::cos(theta));
  for (int i = 0; i < 60; ++i) step(w);
  const double s1 = downhill(w, theta);
  const double t1 = w.time();
  for (int i = 0; i < 60; ++i) step(w);
  const double s2 = downhill(w, theta);
  for (int i = 0; i < 60; ++i) step(w);
  const double s3 = downhill(w, theta);
  const double T = w.time() - t1;
  // Second difference of equally spaced positions: a = (s3 - 2 s2 + s1) / (T/2)^2.
  const double a = (s3 - 2 * s2 + s1) / std::pow(T / 2, 2);
  EXPECT_NEAR(a, expected, 0.02 * expected);
}

TEST_P(Analytic, PendulumSmallAnglePeriod) {
  const double L = 1, r = 0.05, theta0 = 5 * M_PI / 180;
  World w = world(scene("pendulum", {{"length", "1"}, {"angle", "5"}, {"radius", "0.05"}}));
  // Physical pendulum (a sphere, not a point): T = 2 pi sqrt(I_pivot / (m g L)), with the first
  // finite-amplitude correction (1 + theta0^2 / 16).
  const double I_pivot = 0.4 * r * r + L * L;
  const double expected = 2 * M_PI * std::sqrt(I_pivot / (kG * L)) * (1 + theta0 * theta0 / 16);
  // Upward zero crossings of x (linearly interpolated) over several periods.
  std::vector<double> crossings;
  double prev = world_bodies(w).x[0].x(), prev_t = 0;
  while (w.time() < 10) {
    step(w);
    const double x = world_bodies(w).x[0].x();
    if (prev < 0 && x >= 0) crossings.push_back(prev_t + (w.time() - prev_t) * (-prev) / (x - prev));
    prev = x;
    prev_t = w.time();
  }
  ASSERT_GE(crossings.size(), 3u);
  const double period = (crossings.back() - crossings.front()) / (crossings.size() - 1);
  EXPECT_NEAR(period, expected, 0.01 * expected);
}

// Runs a stack for 10 s; every box must stay within 2 mm of where it started and no contact may
// sink deeper than the slop plus 1 mm.
void expect_stack_rests(World w) {
  const std::vector<Vec3> start = world_bodies(w).x;
  double deepest = 0;
  while (w.time() < 10 - 1e-9) deepest = std::max(deepest, Analytic::step(w).max_penetration);
  for (int i = 0; i < world_bodies(w).size(); ++i)
    EXPECT_LT((world_bodies(w).x[i] - start[i]).norm(), 2e-3) << "box " << i;
  EXPECT_LE(deepest, w.step_params().slop + 1e-3);
}

TEST_P(Analytic, StackOfTenBoxesRests) { expect_stack_rests(world(scene("box_stack", {{"boxes", "10"}}))); }

TEST_P(Analytic, StackOfLightAndThousandTimesHeavierBoxesRests) {
  expect_stack_rests(world(scene("box_stack", {{"boxes", "10"}, {"mass_even", "1"}, {"mass_odd", "1000"}})));
}

TEST_P(Analytic, HeavyEndedChainJointsStayTogether) {
  const SceneDef def = scene("hanging_chain", {{"links", "20"}, {"end_ratio", "100"}});
  World w = world(def);
  const test::JointGapMeter gaps(w);
  double worst = 0;
  for (int i = 0; i < 600; ++i) {
    step(w);
    worst = std::max(worst, gaps.max_gap(w));
  }
  EXPECT_LT(worst, 1e-3);
}

INSTANTIATE_TEST_SUITE_P(Solvers, Analytic, ::testing::Values(SolverKind::Direct, SolverKind::Substructured),
                         [](const ::testing::TestParamInfo<SolverKind>& info) {
                           return info.param == SolverKind::Direct ? "Direct" : "Substructured";
                         });

}  // namespace
}  // namespace rbpart
