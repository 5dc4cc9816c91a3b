// Convex hulls (geometry/hull.hpp) against the geometry of convex polyhedra: every input point lies
// on or behind every face's plane, the faces close up into a consistently oriented surface whose
// area vectors sum to zero and which obeys Euler's V - E + F = 2, points on a sphere are all
// vertices, interior and edge points are none, and a box has its six quadrilaterals however it is
// turned. Degenerate input gives fewer than 4 faces, as the header promises.
#include "geometry/hull.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <utility>

namespace rbpart {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

std::vector<int> face(const HullFaces& h, int f) {
  return {h.indices.begin() + h.offsets[f], h.indices.begin() + h.offsets[f + 1]};
}

// Twice the area vector of a planar polygon (a fan from its first vertex): its direction is the
// normal the vertex order turns counter-clockwise about.
Vec3 area_vector(const std::vector<Vec3>& p, const std::vector<int>& f) {
  Vec3 a = Vec3::Zero();
  for (std::size_t i = 1; i + 1 < f.size(); ++i) a += (p[f[i]] - p[f[0]]).cross(p[f[i + 1]] - p[f[0]]);
  return a;
}

double extent(const std::vector<Vec3>& p) {
  Vec3 lo = p[0], hi = p[0];
  for (const Vec3& x : p) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  return (hi - lo).maxCoeff();
}

// The properties every hull of `p` has. `tolerance` (m) bounds round-off in a plane test.
void expect_convex_closed_hull(const std::vector<Vec3>& p, const HullFaces& h, double tolerance) {
  ASSERT_GE(h.size(), 4);
  ASSERT_EQ(h.offsets.front(), 0);
  ASSERT_EQ(h.offsets.back(), static_cast<int>(h.indices.size()));
  std::set<int> vertices;
  std::map<std::pair<int, int>, int> directed;  // half-edge -> how often it occurs
  Vec3 area_sum = Vec3::Zero();
  int fan_triangles = 0;
  for (int f = 0; f < h.size(); ++f) {
    const std::vector<int> v = face(h, f);
    ASSERT_GE(v.size(), 3u) << "face " << f;
    const Vec3 a = area_vector(p, v);
    ASSERT_GT(a.norm(), 0) << "face " << f;
    const Vec3 n = a.normalized();
    area_sum += a;
    fan_triangles += static_cast<int>(v.size()) - 2;
    for (std::size_t i = 0; i < v.size(); ++i) {
      vertices.insert(v[i]);
      ++directed[{v[i], v[(i + 1) % v.size()]}];
      // Planar: every vertex of the face on its plane.
      EXPECT_NEAR(n.dot(p[v[i]] - p[v[0]]), 0, tolerance) << "face " << f;
    }
    // Supporting and outward: no input point in front of the plane.
    for (std::size_t i = 0; i < p.size(); ++i) EXPECT_LE(n.dot(p[i] - p[v[0]]), tolerance) << "face " << f << " point " << i;
  }
  // Closed and consistently oriented: each edge is walked once each way.
  for (const auto& [e, count] : directed) {
    EXPECT_EQ(count, 1) << "edge " << e.first << "-" << e.second;
    EXPECT_EQ(directed.count({e.second, e.first}), 1u) << "edge " << e.first << "-" << e.second;
  }
  // A closed surface's area vectors sum to zero (the divergence theorem for a constant field), up
  // to the round-off of each fan triangle's cross product of differences: a few eps (R + D) D for
  // points within R of the origin and D of each other.
  double radius = 0;
  for (const Vec3& x : p) radius = std::max(radius, x.norm());
  const double diameter = std::sqrt(3.0) * extent(p);
  EXPECT_LE(area_sum.norm(), 16 * kEps * fan_triangles * (radius + diameter) * diameter);
  // Euler's formula for a convex polyhedron (a sphere's topology).
  const int V = static_cast<int>(vertices.size()), E = static_cast<int>(directed.size()) / 2, F = h.size();
  EXPECT_EQ(V - E + F, 2);
}

std::vector<Vec3> box_corners(const Vec3& half, const Quat& turn = Quat::Identity(), const Vec3& at = Vec3::Zero()) {
  std::vector<Vec3> p;
  for (int i = 0; i < 8; ++i)
    p.push_back(at + turn * Vec3((i & 1 ? 1 : -1) * half.x(), (i & 2 ? 1 : -1) * half.y(), (i & 4 ? 1 : -1) * half.z()));
  return p;
}

// The box's hull: six quadrilaterals over its corners (indices below 8), one per face, whose outward
// normals are the box's six axis directions.
void expect_box_faces(const std::vector<Vec3>& p, const HullFaces& h, const Quat& turn, double tolerance) {
  expect_convex_closed_hull(p, h, tolerance);
  ASSERT_EQ(h.size(), 6);
  std::set<std::pair<int, int>> axes;  // (axis, sign) seen
  for (int f = 0; f < h.size(); ++f) {
    const std::vector<int> v = face(h, f);
    ASSERT_EQ(v.size(), 4u) << "face " << f;
    for (int i : v) EXPECT_LT(i, 8) << "face " << f;
    const Vec3 n = turn.conjugate() * area_vector(p, v).normalized();
    int axis;
    const double largest = n.cwiseAbs().maxCoeff(&axis);
    EXPECT_NEAR(largest, 1, tolerance) << "face " << f;
    axes.insert({axis, n[axis] > 0 ? 1 : -1});
  }
  EXPECT_EQ(axes.size(), 6u);
}

TEST(Hull, BoxCornersGiveSixOutwardQuadrilaterals) {
  // Axis-aligned (Bullet's rounding grid meets the corners exactly) and turned (it does not, and
  // each face comes back from Bullet as triangles to be merged).
  const Vec3 half(0.3, 0.2, 0.1);
  for (const Quat& turn : {Quat::Identity(), Quat(Eigen::AngleAxisd(0.9, Vec3(1, 2, -1).normalized()))}) {
    SCOPED_TRACE(turn.coeffs().transpose());
    const std::vector<Vec3> p = box_corners(half, turn, Vec3(1, -2, 0.5));
    expect_box_faces(p, convex_hull_faces(p), turn, 1e3 * kEps * extent(p));
  }
}

TEST(Hull, InteriorEdgeAndFacePointsAreNoVertices) {
  // The box's corners, then points strictly inside it, at its edges' midpoints and at its faces'
  // centres: the hull is still the six quadrilaterals of the corners (a face keeps no vertex in
  // line with its neighbours, nor one inside it).
  const Vec3 half(0.3, 0.2, 0.1);
  const Quat turn(Eigen::AngleAxisd(0.4, Vec3(0, 1, 1).normalized()));
  std::vector<Vec3> p = box_corners(half, turn);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.95, 0.95);
  for (int i = 0; i < 30; ++i) p.push_back(turn * Vec3(u(rng), u(rng), u(rng)).cwiseProduct(half));
  for (int i = 0; i < 8; ++i)
    for (int j = i + 1; j < 8; ++j)
      if (((i ^ j) & ((i ^ j) - 1)) == 0) p.push_back(0.5 * (p[i] + p[j]));  // corners differing in one axis
  for (int axis = 0; axis < 3; ++axis)
    for (double s : {-1.0, 1.0}) p.push_back(turn * (s * half[axis] * Vec3::Unit(axis)));
  expect_box_faces(p, convex_hull_faces(p), turn, 1e3 * kEps * extent(p));
}

TEST(Hull, PointsOnASphereAreAllVertices) {
  // Points on a sphere in general position: each is the unique farthest point in its own
  // direction, so each is a hull vertex, and the faces are triangles (coplanar four are a
  // probability-zero event): F = 2V - 4 and E = 3V - 6.
  std::mt19937 rng(17);
  std::normal_distribution<double> g;
  for (int n : {4, 12, 40}) {
    SCOPED_TRACE(n);
    std::vector<Vec3> p;
    for (int i = 0; i < n; ++i) p.push_back(Vec3(0.5, 0.5, 0.5) + 0.2 * Vec3(g(rng), g(rng), g(rng)).normalized());
    const HullFaces h = convex_hull_faces(p);
    expect_convex_closed_hull(p, h, 1e3 * kEps * extent(p));
    std::set<int> used(h.indices.begin(), h.indices.end());
    EXPECT_EQ(static_cast<int>(used.size()), n);
    EXPECT_EQ(h.size(), 2 * n - 4);
    EXPECT_EQ(static_cast<int>(h.indices.size()), 3 * h.size());
  }
}

TEST(Hull, RandomCloudsAreEnclosedAndTheirExtremePointsAreVertices) {
  // Gaussian clouds: the hull encloses every point, and the farthest point in any direction is a
  // hull vertex (or lies on the hull's supporting plane in that direction, when it ties).
  std::mt19937 rng(29);
  std::normal_distribution<double> g;
  for (int trial = 0; trial < 20; ++trial) {
    SCOPED_TRACE(trial);
    std::vector<Vec3> p;
    for (int i = 0; i < 60; ++i) p.push_back(Vec3(g(rng), 0.5 * g(rng), 0.2 * g(rng)));
    const HullFaces h = convex_hull_faces(p);
    const double tolerance = 1e3 * kEps * extent(p);
    expect_convex_closed_hull(p, h, tolerance);
    const std::set<int> used(h.indices.begin(), h.indices.end());
    for (int k = 0; k < 50; ++k) {
      const Vec3 d = Vec3(g(rng), g(rng), g(rng)).normalized();
      double all = -INFINITY, hull = -INFINITY;
      for (std::size_t i = 0; i < p.size(); ++i) all = std::max(all, d.dot(p[i]));
      for (int i : used) hull = std::max(hull, d.dot(p[i]));
      EXPECT_NEAR(hull, all, tolerance);
    }
  }
}

TEST(Hull, DuplicatePointsGiveTheSameBox) {
  const Vec3 half(0.5, 0.5, 0.5);
  std::vector<Vec3> p = box_corners(half);
  const std::vector<Vec3> once = p;
  p.insert(p.end(), once.begin(), once.end());
  const HullFaces h = convex_hull_faces(p);
  expect_convex_closed_hull(p, h, 1e3 * kEps * extent(p));
  ASSERT_EQ(h.size(), 6);
  // Each face has four distinct corners, whichever copy of a corner it names.
  for (int f = 0; f < h.size(); ++f) {
    std::set<int> corners;
    for (int i : face(h, f)) corners.insert(i % 8);
    EXPECT_EQ(corners.size(), 4u) << "face " << f;
  }
}

TEST(Hull, FlatLinearAndCoincidentPointsHaveFewerThanFourFaces) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  const Quat turn(Eigen::AngleAxisd(0.7, Vec3(1, -1, 2).normalized()));
  std::vector<Vec3> flat, line, one(5, Vec3(0.1, 0.2, 0.3));
  for (int i = 0; i < 20; ++i) flat.push_back(turn * Vec3(u(rng), u(rng), 0));
  for (int i = 0; i < 20; ++i) line.push_back(Vec3(1, 2, 3) * u(rng));
  EXPECT_LT(convex_hull_faces(flat).size(), 4);
  EXPECT_LT(convex_hull_faces(line).size(), 4);
  EXPECT_LT(convex_hull_faces(one).size(), 4);
  const HullFaces none = convex_hull_faces({});
  EXPECT_EQ(none.size(), 0);
  EXPECT_TRUE(none.offsets.empty());
}

}  // namespace
}  // namespace rbpart
