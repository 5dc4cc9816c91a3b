// The manifold's reduction (collision/manifold.hpp): which points a pair keeps.
#include "collision/manifold.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

namespace rbpart::collision {
namespace {

// The octagon where two unit squares, one turned by 45 degrees, overlap face on face: eight
// points in the plane z = 0 with the normal along z, each at depth `depth[i]`.
std::vector<PairPoint> octagon(const std::vector<double>& depth) {
  std::vector<PairPoint> pts;
  for (int i = 0; i < 8; ++i) {
    const double angle = (i + 0.5) * M_PI / 4;
    const Vec3 p(0.5 * std::cos(angle), 0.5 * std::sin(angle), 0);
    pts.push_back({p, p, Vec3::UnitZ(), depth[i], depth[i]});
  }
  return pts;
}

// The kept points' positions, sorted.
std::vector<std::array<double, 2>> kept(std::vector<PairPoint> pts) {
  const int count = reduce(pts, Vec3::UnitZ(), 1.0, 5e-4);
  std::vector<std::array<double, 2>> out;
  for (int i = 0; i < count; ++i) out.push_back({pts[i].on_a.x(), pts[i].on_a.y()});
  std::sort(out.begin(), out.end());
  return out;
}

TEST(Manifold, FaceOnFaceKeepsTheSameFootprintWhateverTheRoundOffInDepth) {
  // Depths that differ by round-off (1e-8, far below the allowance) decide nothing: a resting
  // pair keeps the same four points from step to step, so their contacts keep their ids and warm
  // starts. (Started from the deepest point, the footprint took one of two sets of four.)
  const std::vector<std::array<double, 2>> reference = kept(octagon(std::vector<double>(8, -1e-8)));
  ASSERT_EQ(reference.size(), 4u);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> noise(-5e-8, 0);
  for (int trial = 0; trial < 50; ++trial) {
    std::vector<double> depth(8);
    for (double& d : depth) d = noise(rng);
    EXPECT_EQ(kept(octagon(depth)), reference) << "trial " << trial;
  }
}

TEST(Manifold, FaceOnFaceFootprintSpansThePatch) {
  // The four points kept of the octagon bound at least half its area (a square on every other
  // vertex bounds 1 / sqrt 2 of it).
  const std::vector<std::array<double, 2>> k = kept(octagon(std::vector<double>(8, 0.0)));
  ASSERT_EQ(k.size(), 4u);
  // Area of the convex hull of the four points (shoelace over their angular order).
  std::vector<std::array<double, 2>> hull = k;
  std::sort(hull.begin(), hull.end(), [](const auto& p, const auto& q) {
    return std::atan2(p[1], p[0]) < std::atan2(q[1], q[0]);
  });
  double area = 0;
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const auto& p = hull[i];
    const auto& q = hull[(i + 1) % hull.size()];
    area += 0.5 * (p[0] * q[1] - q[0] * p[1]);
  }
  const double octagon_area = 2 * std::sqrt(2.0) * 0.25;
  EXPECT_GT(std::abs(area), 0.5 * octagon_area);
}

}  // namespace
}  // namespace rbpart::collision
