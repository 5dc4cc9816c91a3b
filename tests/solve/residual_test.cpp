// The quality measure of DESIGN.md §3 (solve/residual.hpp), max_j A_jj |F_j| / max_j |q_j|:
// values worked out by hand, and its sensitivity on a solved island.
#include "solve/residual.hpp"

#include "solve/box_scenes.hpp"
#include "solve/newton.hpp"
#include "solve/solve.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace rbpart {
namespace {

using namespace rbpart::testing;

constexpr double kInf = std::numeric_limits<double>::infinity();

TEST(NaturalMapResidual, HandWorkedValues) {
  Eigen::MatrixXd a(2, 2);
  a << 2, 0, 0, 4;
  const Eigen::Vector2d q(-2, 4), lo(0, 0), hi(kInf, kInf);
  const auto residual = [&](const Eigen::Vector2d& lambda) {
    const Eigen::VectorXd w = a * lambda + q;
    return scaled_natural_map_residual(lambda, w, a.diagonal(), lo, hi, q);
  };
  // The solution: lambda = (1, 0), w = (0, 4).
  EXPECT_EQ(residual(Eigen::Vector2d(1, 0)), 0.0);
  // lambda = (0.5, 0): w_0 = -1, clamp(0.5 + 0.5) = 1, |r_0| A_00 / s = 0.5 * 2 / 4.
  EXPECT_DOUBLE_EQ(residual(Eigen::Vector2d(0.5, 0)), 0.25);
  // lambda = (1, 1): w_1 = 8, clamp(1 - 2) = 0, |r_1| A_11 / s = 1 * 4 / 4.
  EXPECT_DOUBLE_EQ(residual(Eigen::Vector2d(1, 1)), 1.0);
  // A NaN anywhere shows as an infinite residual.
  EXPECT_EQ(residual(Eigen::Vector2d(1, std::nan(""))), kInf);
}

TEST(NaturalMapResidual, DetectsAPerturbedSolution) {
  Scene s;
  add_box(s, 2.0, 0.5, 0.0, 0.5);
  finish(s);
  const SolveStats report = solve_newton_direct(s.rows, s.bodies, s.islands, SolverParams{});
  ASSERT_LE(report.residual, kSettledResidual);
  EXPECT_EQ(natural_map_residual(s.rows, s.bodies, s.islands), report.residual);
  // Doubling one normal impulse: w_j = lambda_j A_jj (the others' share stays), so r_j A_jj / s is
  // lambda_j A_jj / (g h) to first order.
  s.rows.lambda[0] *= 2;
  EXPECT_GT(natural_map_residual(s.rows, s.bodies, s.islands), 0.1);
}

}  // namespace
}  // namespace rbpart
