// Collision stage: contact points, distances, normals and persistent ids against geometry worked
// out by hand (docs/design.md#step "collide").
#include "collision/collide.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <tuple>

#include "core/error.hpp"
#include "geometry/hull.hpp"

namespace rbpart {
namespace {

constexpr double kMargin = 0.01;
constexpr double kPi = 3.14159265358979323846;

BodyDef make_body(ShapeType type, bool is_static = false) {
  BodyDef b;
  b.name = "b";
  b.shape.type = type;
  b.is_static = is_static;
  b.density = 1000;
  return b;
}
BodyDef sphere(double r) {
  BodyDef b = make_body(ShapeType::Sphere);
  b.shape.radius = r;
  return b;
}
BodyDef box(const Vec3& h, bool is_static = false) {
  BodyDef b = make_body(ShapeType::Box, is_static);
  b.shape.half_extents = h;
  return b;
}
BodyDef round_body(ShapeType type, double r, double h) {
  BodyDef b = make_body(type);
  b.shape.radius = r;
  b.shape.half_length = h;
  return b;
}
std::vector<Vec3> cube_corners(double h) {
  std::vector<Vec3> v;
  for (int i = 0; i < 8; ++i) v.emplace_back(i & 1 ? h : -h, i & 2 ? h : -h, i & 4 ? h : -h);
  return v;
}
BodyDef hull(std::vector<Vec3> vertices) {
  BodyDef b = make_body(ShapeType::Convex);
  b.shape.vertices = std::move(vertices);
  return b;
}

// A static ground box whose top face is the plane z = 0, rotated about z so that nothing lines up
// with the world axes by accident.
BodyDef ground() {
  BodyDef g = box(Vec3(5, 4, 0.5), true);
  g.position = Vec3(0.3, -0.2, -0.5);
  g.orientation = Quat(Eigen::AngleAxisd(0.3, Vec3::UnitZ()));
  return g;
}

struct Fixture {
  double margin = kMargin;
  SceneDef scene;
  std::unique_ptr<Collider> collider;
  std::vector<Vec3> x;
  std::vector<Quat> q;
  std::vector<Vec3> v, w;  // velocities for the speculative margin; zero (at rest) unless set
  double h = 1.0 / 60;
  std::vector<Contact> contacts;

  int add(const BodyDef& b) {
    scene.bodies.push_back(b);
    return static_cast<int>(scene.bodies.size()) - 1;
  }
  const std::vector<Contact>& run() {
    if (!collider) collider = std::make_unique<Collider>(scene, margin);
    v.resize(x.size(), Vec3::Zero());
    w.resize(x.size(), Vec3::Zero());
    collider->collide(x, q, v, w, h, contacts);
    return contacts;
  }
  // Runs with the scene's own poses (later calls with run() after editing x and q).
  const std::vector<Contact>& run_scene_poses() {
    x.clear();
    q.clear();
    for (const BodyDef& b : scene.bodies) {
      x.push_back(b.position);
      q.push_back(b.orientation);
    }
    return run();
  }
};

void expect_vec_near(const Vec3& a, const Vec3& b, double tol) {
  EXPECT_LE((a - b).norm(), tol) << "got " << a.transpose() << ", expected " << b.transpose();
}

// The contact whose point is nearest to p.
const Contact& nearest(const std::vector<Contact>& contacts, const Vec3& p) {
  return *std::min_element(contacts.begin(), contacts.end(), [&](const Contact& a, const Contact& b) {
    return (a.point - p).squaredNorm() < (b.point - p).squaredNorm();
  });
}

TEST(Collide, SphereRestingOnGround) {
  for (double gap : {0.004, 0.0, -0.003}) {
    Fixture f;
    f.add(ground());
    BodyDef s = sphere(0.25);
    s.position = Vec3(0.7, 0.4, 0.25 + gap);
    const int ball = f.add(s);
    const auto& c = f.run_scene_poses();
    ASSERT_EQ(c.size(), 1u) << "gap " << gap;
    EXPECT_EQ(c[0].body_a, ball);
    EXPECT_EQ(c[0].body_b, 0);
    expect_vec_near(c[0].normal, Vec3::UnitZ(), 1e-12);
    EXPECT_NEAR(c[0].distance, gap, 1e-12);
    expect_vec_near(c[0].point, Vec3(0.7, 0.4, 0.5 * gap), 1e-12);
  }
}

// Four contacts, one under each bottom corner of a box with half extents h lying flat at height
// `gap` above z = 0, rotated by `yaw` about z and centred at (cx, cy).
void expect_box_corners(const std::vector<Contact>& c, const Vec3& h, double cx, double cy, double yaw, double gap,
                        double tol) {
  ASSERT_EQ(c.size(), 4u);
  const Mat3 R = Eigen::AngleAxisd(yaw, Vec3::UnitZ()).toRotationMatrix();
  for (int i = 0; i < 4; ++i) {
    const Vec3 corner = Vec3(cx, cy, 0.5 * gap) + R * Vec3(i & 1 ? h.x() : -h.x(), i & 2 ? h.y() : -h.y(), 0);
    const Contact& k = nearest(c, corner);
    expect_vec_near(k.point, corner, tol);
    EXPECT_NEAR(k.distance, gap, tol);
    expect_vec_near(k.normal, Vec3::UnitZ(), 1e-9);
  }
}

TEST(Collide, BoxRestingFaceDownGivesFourCornersWithStableIds) {
  const Vec3 h(0.3, 0.2, 0.1);
  Fixture f;
  f.add(ground());
  BodyDef b = box(h);
  b.position = Vec3(0.5, 0.1, 0.1);
  b.orientation = Quat(Eigen::AngleAxisd(0.8, Vec3::UnitZ()));
  const int body = f.add(b);
  const auto& first = f.run_scene_poses();
  expect_box_corners(first, h, 0.5, 0.1, 0.8, 0.0, 1e-9);
  for (const Contact& c : first) EXPECT_EQ(c.body_a, body);
  std::vector<std::uint64_t> ids;
  for (const Contact& c : first) ids.push_back(c.id);

  // Tiny pose changes (resting jitter) keep every id.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1e-5, 1e-5);
  for (int step = 0; step < 5; ++step) {
    f.x[body] = b.position + Vec3(u(rng), u(rng), u(rng));
    f.q[body] = (b.orientation * Quat(Eigen::AngleAxisd(1e-5, Vec3(u(rng), u(rng), 1).normalized()))).normalized();
    const auto& c = f.run();
    ASSERT_EQ(c.size(), 4u);
    for (int i = 0; i < 4; ++i) EXPECT_EQ(c[i].id, ids[i]);
  }
}

TEST(Collide, BoxWithinMarginAndPenetratingGivesExactDistances) {
  const Vec3 h(0.3, 0.2, 0.1);
  for (double gap : {0.009, 1e-7, -1e-7, -0.002}) {
    Fixture f;
    f.add(ground());
    BodyDef b = box(h);
    b.position = Vec3(-0.4, 0.2, h.z() + gap);
    b.orientation = Quat(Eigen::AngleAxisd(-0.2, Vec3::UnitZ()));
    f.add(b);
    SCOPED_TRACE(gap);
    expect_box_corners(f.run_scene_poses(), h, -0.4, 0.2, -0.2, gap, 1e-9);
  }
}

TEST(Collide, ConvexHullCubeOnGroundGivesFourCorners) {
  // The cube's corners in a rotated frame, so Bullet's rounding grid does not meet them exactly.
  const Quat tilt(Eigen::AngleAxisd(0.9, Vec3(1, 2, -1).normalized()));
  std::vector<Vec3> v;
  for (const Vec3& p : cube_corners(0.2)) v.push_back(tilt * p);
  for (double gap : {0.0, 0.005, -0.001}) {
    Fixture f;
    f.add(ground());
    BodyDef b = hull(v);
    b.orientation = Quat(Eigen::AngleAxisd(0.4, Vec3::UnitZ())) * tilt.conjugate();
    b.position = Vec3(0.2, 0.3, 0.2 + gap);
    f.add(b);
    SCOPED_TRACE(gap);
    expect_box_corners(f.run_scene_poses(), Vec3(0.2, 0.2, 0.2), 0.2, 0.3, 0.4, gap, 1e-9);
  }
}

TEST(Collide, HullRestingOnOneOfItsFacesHasExactDistances) {
  // A random rock, turned so that one of its faces lies on the ground: every vertex of that face
  // must be reported at the true distance, not at Bullet's rounded (1e-4 relative) vertices.
  std::mt19937 rng(11);
  std::normal_distribution<double> g;
  std::vector<Vec3> v;
  for (int i = 0; i < 20; ++i) v.push_back(Vec3(g(rng), g(rng), g(rng)).normalized().cwiseProduct(Vec3(0.17, 0.12, 0.09)));
  const HullFaces faces = convex_hull_faces(v);
  ASSERT_GE(faces.size(), 4);
  // The face with the largest area rests on the ground.
  int best = 0;
  double best_area = 0;
  Vec3 best_normal;
  for (int k = 0; k < faces.size(); ++k) {
    Vec3 n = Vec3::Zero();
    const Vec3& p0 = v[faces.indices[faces.offsets[k]]];
    for (int i = faces.offsets[k] + 1; i + 1 < faces.offsets[k + 1]; ++i)
      n += (v[faces.indices[i]] - p0).cross(v[faces.indices[i + 1]] - p0);
    if (n.norm() > best_area) best_area = n.norm(), best = k, best_normal = n.normalized();
  }
  const Vec3 p0 = v[faces.indices[faces.offsets[best]]];
  const Quat turn = Quat::FromTwoVectors(best_normal, -Vec3::UnitZ());
  const double gap = 0.003;
  Fixture f;
  f.add(ground());
  BodyDef b = hull(v);
  b.orientation = turn;
  b.position = Vec3(0.1, 0.1, gap) - turn * p0;
  f.add(b);
  const auto& c = f.run_scene_poses();
  const int corners = faces.offsets[best + 1] - faces.offsets[best];
  EXPECT_EQ(static_cast<int>(c.size()), std::min(corners, 4));
  for (const Contact& k : c) {
    EXPECT_NEAR(k.distance, gap, 1e-12);
    expect_vec_near(k.normal, Vec3::UnitZ(), 1e-12);
    // Each point lies under a vertex of that face.
    double nearest_vertex = INFINITY;
    for (int i = faces.offsets[best]; i < faces.offsets[best + 1]; ++i)
      nearest_vertex = std::min(nearest_vertex, (b.position + turn * v[faces.indices[i]] - k.point).norm());
    EXPECT_NEAR(nearest_vertex, 0.5 * gap, 1e-12);
  }
}

TEST(Collide, TiltedRocksKeepEveryPointInContact) {
  // Random rocks at rest, a random face turned down and tilted by 1-6 degrees, lowered until their
  // lowest vertex is 0.4 mm in: the reduced manifold must guard every vertex in contact (z <= 0).
  // A dropped one is either under a kept point (within 1e-9) or over a triangle of kept points and
  // no more than the allowance (a twentieth of the margin) below its plane, the first-order
  // guarantee that a rigid motion drives it no deeper than them. A rock rocking on two corners kept
  // a footprint point 8 mm up and dropped the other corner, 0.6 mm in.
  std::mt19937 rng(5);
  std::normal_distribution<double> g;
  std::uniform_real_distribution<double> u(0, 1);
  const double allowance = 0.05 * kMargin;
  int spread = 0;
  for (int trial = 0; trial < 400; ++trial) {
    std::vector<Vec3> v;
    for (int i = 0; i < 24; ++i) v.push_back(Vec3(g(rng), g(rng), g(rng)).normalized().cwiseProduct(Vec3(0.17, 0.12, 0.09)));
    const HullFaces faces = convex_hull_faces(v);
    ASSERT_GE(faces.size(), 4);
    const int k = static_cast<int>(u(rng) * faces.size());
    const Vec3& p0 = v[faces.indices[faces.offsets[k]]];
    const Vec3 n = (v[faces.indices[faces.offsets[k] + 1]] - p0).cross(v[faces.indices[faces.offsets[k] + 2]] - p0).normalized();
    const double tilt = (1 + 5 * u(rng)) * kPi / 180, about = 2 * kPi * u(rng);
    const Quat turn = Quat(Eigen::AngleAxisd(tilt, Vec3(std::cos(about), std::sin(about), 0))) *
                      Quat::FromTwoVectors(n, -Vec3::UnitZ());
    double lowest = INFINITY;
    for (const Vec3& p : v) lowest = std::min(lowest, (turn * p).z());
    Fixture f;
    f.add(ground());
    BodyDef b = hull(v);
    b.orientation = turn;
    b.position = Vec3(0.1, 0.1, -4e-4 - lowest);
    f.add(b);
    const auto& c = f.run_scene_poses();
    std::vector<Vec3> kept;  // on the rock
    for (const Contact& x : c) kept.push_back(x.point + 0.5 * x.distance * x.normal);
    int touching = 0;
    for (const Vec3& p : v) {
      const Vec3 w = b.position + turn * p;
      touching += w.z() <= -4e-4 + allowance;
      if (w.z() > 0) continue;
      bool held = false;
      for (const Vec3& q : kept) held = held || (q - w).norm() <= 1e-9;
      for (std::size_t i = 0; i < kept.size() && !held; ++i)
        for (std::size_t j = i + 1; j < kept.size() && !held; ++j)
          for (std::size_t l = j + 1; l < kept.size() && !held; ++l) {
            const Vec3 &c0 = kept[i], &c1 = kept[j], &c2 = kept[l];
            const double area = (c1 - c0).cross(c2 - c0).z();
            if (std::abs(area) < 1e-12) continue;
            const double s = (c1 - w).cross(c2 - w).z() / area, t = (c2 - w).cross(c0 - w).z() / area;
            if (s < -1e-9 || t < -1e-9 || s + t > 1 + 1e-9) continue;
            held = s * c0.z() + t * c1.z() + (1 - s - t) * c2.z() - w.z() <= allowance;
          }
      EXPECT_TRUE(held) << "trial " << trial << ": a vertex " << -1000 * w.z() << " mm in is not guarded";
    }
    spread += touching < 3;
  }
  EXPECT_GT(spread, 50);  // the footprints drawn from all points, not from three as deep
}

TEST(Collide, BoxOnBoxGivesCornersOfTheOverlap) {
  // Upper box overhangs the lower one in x and y; the overlap of the two faces is the rectangle
  // [0.1, 0.4] x [-0.2, 0.3] at z = 0.2.
  Fixture f;
  f.add(ground());
  BodyDef lower = box(Vec3(0.4, 0.35, 0.1));
  lower.position = Vec3(0.0, 0.0, 0.1);
  BodyDef upper = box(Vec3(0.3, 0.25, 0.05));
  const double gap = 0.002;
  upper.position = Vec3(0.4, 0.05, 0.25 + gap);
  const int lo = f.add(lower), up = f.add(upper);
  const auto& all = f.run_scene_poses();
  std::vector<Contact> c;
  for (const Contact& k : all)
    if (k.body_b == up || k.body_a == up) c.push_back(k);
  ASSERT_EQ(c.size(), 4u);
  for (double x : {0.1, 0.4})
    for (double y : {-0.2, 0.3}) {
      const Contact& k = nearest(c, Vec3(x, y, 0.2 + 0.5 * gap));
      expect_vec_near(k.point, Vec3(x, y, 0.2 + 0.5 * gap), 1e-9);
      EXPECT_NEAR(k.distance, gap, 1e-9);
      // Both dynamic: a is the lower index, the normal points from b (upper) into a (lower).
      EXPECT_EQ(k.body_a, lo);
      EXPECT_EQ(k.body_b, up);
      expect_vec_near(k.normal, -Vec3::UnitZ(), 1e-9);
    }
}

TEST(Collide, CapsuleLyingOnGroundTouchesAtBothEnds) {
  const double r = 0.1, h = 0.4;
  for (double tilt : {0.0, 0.01}) {
    Fixture f;
    f.add(ground());
    BodyDef cap = round_body(ShapeType::Capsule, r, h);
    const double gap = 0.002;
    // Axis along x, tilted up by `tilt` at the +x end; the low end rests `gap` above the ground.
    cap.orientation = Quat(Eigen::AngleAxisd(-tilt, Vec3::UnitY())) * Quat(Eigen::AngleAxisd(kPi / 2, Vec3::UnitY()));
    const Vec3 axis = cap.orientation * Vec3::UnitZ();
    cap.position = Vec3(0.2, 0.1, r + gap + h * std::sin(tilt));
    f.add(cap);
    const auto& c = f.run_scene_poses();
    SCOPED_TRACE(tilt);
    ASSERT_EQ(c.size(), 2u);
    for (double s : {-1.0, 1.0}) {
      const Vec3 end = cap.position + s * h * axis;
      // Under the low end its hemisphere's lowest point; under the raised end the side of the
      // capsule, r / cos(tilt) below the axis (the hemisphere's lowest point is inside).
      const double d = end.z() - (s < 0 ? r : r / std::cos(tilt));
      const Contact& k = nearest(c, Vec3(end.x(), end.y(), 0.5 * d));
      EXPECT_NEAR(k.distance, d, 1e-12);
      expect_vec_near(k.point, Vec3(end.x(), end.y(), 0.5 * d), 1e-12);
      expect_vec_near(k.normal, Vec3::UnitZ(), 1e-12);
    }
  }
}

TEST(Collide, ParallelCapsulesTouchAtBothEndsOfTheirOverlap) {
  // Two capsules (radius 0.03, half length 0.1) along y, side by side along x with a gap g and B
  // shifted by 0.04 along y: the lines touch over y in [-0.06, 0.1], a contact at each end.
  const double r = 0.03, hl = 0.1;
  for (double gap : {0.004, -0.002}) {
    Fixture f;
    const Quat along_y(Eigen::AngleAxisd(kPi / 2, Vec3::UnitX()));
    BodyDef a = round_body(ShapeType::Capsule, r, hl), b = a;
    a.orientation = b.orientation = along_y;
    a.position = Vec3(0.3, 0.2, 0.5);
    b.position = a.position + Vec3(2 * r + gap, 0.04, 0);
    f.add(a);
    f.add(b);
    const auto& c = f.run_scene_poses();
    SCOPED_TRACE(gap);
    ASSERT_EQ(c.size(), 2u);
    for (double y : {-0.06, 0.1}) {
      const Contact& k = nearest(c, a.position + Vec3(r + 0.5 * gap, y, 0));
      expect_vec_near(k.point, a.position + Vec3(r + 0.5 * gap, y, 0), 1e-9);
      expect_vec_near(k.normal, -Vec3::UnitX(), 1e-9);
      EXPECT_NEAR(k.distance, gap, 1e-9);
    }
  }
}

TEST(Collide, CylinderStandingOnGroundTouchesOnTheRim) {
  const double r = 0.15, h = 0.3, gap = 0.001;
  Fixture f;
  f.add(ground());
  BodyDef cyl = round_body(ShapeType::Cylinder, r, h);
  cyl.position = Vec3(-0.3, 0.6, h + gap);
  cyl.orientation = Quat(Eigen::AngleAxisd(1.3, Vec3::UnitZ()));
  f.add(cyl);
  const auto& c = f.run_scene_poses();
  ASSERT_EQ(c.size(), 4u);
  for (const Contact& k : c) {
    EXPECT_NEAR(k.distance, gap, 1e-12);
    EXPECT_NEAR((k.point - Vec3(-0.3, 0.6, 0.5 * gap)).norm(), r, 1e-12);  // on the rim
    expect_vec_near(k.normal, Vec3::UnitZ(), 1e-12);
  }
  // They span the rim: opposite points are a diameter apart.
  double widest = 0;
  for (const Contact& a : c)
    for (const Contact& b : c) widest = std::max(widest, (a.point - b.point).norm());
  EXPECT_NEAR(widest, 2 * r, 1e-12);
}

TEST(Collide, TiltedCylinderReportsItsLowestRimPoint) {
  // Tilted by 0.1 rad the cylinder stands on one rim point, which need not be a corner of the
  // polygon that stands for its cap: the GJK point supplies it.
  const double r = 0.15, h = 0.3, gap = 0.0005, tilt = 0.1;
  Fixture f;
  f.add(ground());
  BodyDef cyl = round_body(ShapeType::Cylinder, r, h);
  cyl.orientation = Quat(Eigen::AngleAxisd(tilt, Vec3(1, 1, 0).normalized())) * Quat(Eigen::AngleAxisd(0.2, Vec3::UnitZ()));
  const Vec3 axis = cyl.orientation * Vec3::UnitZ();
  const Vec3 down = (-Vec3::UnitZ() - (-Vec3::UnitZ()).dot(axis) * axis).normalized();
  const Vec3 lowest_local = -h * axis + r * down;  // lowest rim point relative to the centre
  cyl.position = Vec3(0.1, 0.2, gap - lowest_local.z());
  f.add(cyl);
  const auto& c = f.run_scene_poses();
  ASSERT_GE(c.size(), 1u);
  double deepest = INFINITY;
  for (const Contact& k : c) deepest = std::min(deepest, k.distance);
  EXPECT_NEAR(deepest, gap, 1e-9);
  // The point's position along the ground carries the cylinder's rounding radius (1e-6 of its size).
  const Vec3 lowest = cyl.position + lowest_local;
  expect_vec_near(nearest(c, lowest).point, Vec3(lowest.x(), lowest.y(), 0.5 * gap), 1e-6 * std::hypot(r, h));
}

TEST(Collide, CylinderLyingOnGroundTouchesAlongALine) {
  const double r = 0.15, h = 0.3, gap = 0.0;
  Fixture f;
  f.add(ground());
  BodyDef cyl = round_body(ShapeType::Cylinder, r, h);
  cyl.orientation = Quat(Eigen::AngleAxisd(kPi / 2, Vec3::UnitX()));  // axis along -y
  cyl.position = Vec3(0.1, 0.0, r + gap);
  f.add(cyl);
  const auto& c = f.run_scene_poses();
  ASSERT_EQ(c.size(), 2u);
  for (double y : {-h, h}) {
    const Contact& k = nearest(c, Vec3(0.1, y, 0));
    expect_vec_near(k.point, Vec3(0.1, y, 0.5 * gap), 1e-12);
    EXPECT_NEAR(k.distance, gap, 1e-12);
  }
}

TEST(Collide, CrossedBoxEdgesGiveOnePointAlongTheEdgeNormal) {
  // Box A rests on an edge along x, box B above it stands on an edge along y: they meet at a
  // single point and the normal is the cross product of the edges (z).
  const double hs = 0.1, gap = 0.003;
  Fixture f;
  BodyDef a = box(Vec3(0.3, hs, hs));
  a.orientation = Quat(Eigen::AngleAxisd(kPi / 4, Vec3::UnitX()));
  a.position = Vec3(0, 0, 0);
  BodyDef b = box(Vec3(hs, 0.3, hs));
  b.orientation = Quat(Eigen::AngleAxisd(kPi / 4, Vec3::UnitY()));
  b.position = Vec3(0.05, -0.02, 2 * hs * std::sqrt(2.0) + gap);
  f.add(a);
  f.add(b);
  const auto& c = f.run_scene_poses();
  ASSERT_EQ(c.size(), 1u);
  EXPECT_NEAR(c[0].distance, gap, 1e-9);
  expect_vec_near(c[0].normal, -Vec3::UnitZ(), 1e-9);  // from b (above) into a (below)
  expect_vec_near(c[0].point, Vec3(0.05, 0, hs * std::sqrt(2.0) + 0.5 * gap), 1e-9);
}

TEST(Collide, CrossedBoxEdgesClosingFastAlsoGiveTheFacesBeyond) {
  // The boxes of the test above, B falling at 6 m/s (0.1 m per step): within the step its lower
  // faces can reach A's upper faces, so besides the edge-on-edge point the faces, though not
  // aligned with the normal, give their clipped points (each an exact distance, as the random
  // test checks). At rest, with a contact margin as large as the moving pair's margin, the edges
  // alone.
  const double hs = 0.1, gap = 0.003, speed = 6, h = 1.0 / 60;
  for (bool moving : {false, true}) {
    Fixture f;
    f.margin = moving ? kMargin : kMargin + h * speed;
    BodyDef a = box(Vec3(0.3, hs, hs));
    a.orientation = Quat(Eigen::AngleAxisd(kPi / 4, Vec3::UnitX()));
    BodyDef b = box(Vec3(hs, 0.3, hs));
    b.orientation = Quat(Eigen::AngleAxisd(kPi / 4, Vec3::UnitY()));
    b.position = Vec3(0.05, -0.02, 2 * hs * std::sqrt(2.0) + gap);
    f.add(a);
    f.add(b);
    f.run_scene_poses();
    if (moving) f.v[1] = Vec3(0, 0, -speed);
    const auto& c = f.run();
    SCOPED_TRACE(moving ? "moving" : "at rest");
    if (!moving) ASSERT_EQ(c.size(), 1u);
    EXPECT_GT(c.size(), moving ? 1u : 0u);
    const Contact& edge = nearest(c, Vec3(0.05, 0, hs * std::sqrt(2.0) + 0.5 * gap));
    EXPECT_NEAR(edge.distance, gap, 1e-9);
    for (const Contact& k : c) EXPECT_GE(k.distance, gap - 1e-9);
  }
}

TEST(Collide, SphereOverABoxEdgeTouchesTheEdge) {
  // Round on edge: the closest pair itself, along the line from the edge to the centre.
  const double r = 0.1, gap = 0.004;
  Fixture f;
  f.add(box(Vec3(0.3, 0.2, 0.1)));
  BodyDef s = sphere(r);
  const Vec3 edge(0.3, 0.05, 0.1), out = Vec3(1, 0, 1).normalized();
  s.position = edge + (r + gap) * out;
  f.add(s);
  const auto& c = f.run_scene_poses();
  ASSERT_EQ(c.size(), 1u);
  EXPECT_NEAR(c[0].distance, gap, 1e-12);
  expect_vec_near(c[0].normal, -out, 1e-9);  // from b (the sphere) into a (the box)
  expect_vec_near(c[0].point, edge + 0.5 * gap * out, 1e-9);
}

TEST(Collide, PenetrationDepthIsReportedNegative) {
  // A sphere whose centre is inside the ground (the cores overlap: EPA) and one that only dips in.
  for (double depth : {0.03, 0.15}) {
    Fixture f;
    f.add(ground());
    BodyDef s = sphere(0.1);
    s.position = Vec3(0.2, 0.2, 0.1 - depth);
    f.add(s);
    const auto& c = f.run_scene_poses();
    ASSERT_EQ(c.size(), 1u);
    EXPECT_NEAR(c[0].distance, -depth, 1e-9);
    expect_vec_near(c[0].normal, Vec3::UnitZ(), 1e-9);
  }
  // Two boxes overlapping by 0.02 across their facing x faces.
  Fixture f;
  BodyDef a = box(Vec3(0.2, 0.2, 0.2)), b = box(Vec3(0.1, 0.1, 0.1));
  b.position = Vec3(0.28, 0.03, -0.02);
  f.add(a);
  f.add(b);
  const auto& c = f.run_scene_poses();
  ASSERT_EQ(c.size(), 4u);
  for (const Contact& k : c) {
    EXPECT_NEAR(k.distance, -0.02, 1e-9);
    expect_vec_near(k.normal, -Vec3::UnitX(), 1e-9);
  }
}

TEST(Collide, StackedCubesSinkingIntoEachOtherKeepTheFaceNormal) {
  // Equal cubes exactly one on the other, sinking by more than the rounding (so EPA runs, on a
  // Minkowski difference whose nearest face is 1000 times closer than the others).
  for (double depth : {1e-3, 5e-3}) {
    Fixture f;
    BodyDef lower = box(Vec3(0.25, 0.25, 0.25)), upper = lower;
    upper.position = Vec3(0, 0, 0.5 - depth);
    f.add(lower);
    f.add(upper);
    const auto& c = f.run_scene_poses();
    SCOPED_TRACE(depth);
    ASSERT_EQ(c.size(), 4u);
    for (const Contact& k : c) {
      EXPECT_NEAR(k.distance, -depth, 1e-12);
      expect_vec_near(k.normal, -Vec3::UnitZ(), 1e-12);
      EXPECT_NEAR(std::abs(k.point.x()), 0.25, 1e-12);
      EXPECT_NEAR(std::abs(k.point.y()), 0.25, 1e-12);
    }
  }
}

TEST(Collide, EpaGivingUpFallsBackToTheBestFaceAxis) {
  // A pose found by search in which btGjkEpaSolver2's EPA gives up on the thin overlap of two
  // cubes and returns its guess as the normal at depth 0 (with no margin the cores are rounded by
  // 1e-6 of their size only). The overlap along that normal is a whole cube: the result must
  // instead come from the cubes' face normals, about z.
  Fixture f;
  f.margin = 0;
  BodyDef lower = box(Vec3(0.25, 0.25, 0.25)), upper = lower;
  lower.orientation = Quat(0.9999999440042171, 0.0002742986752424219, 0.00019170758816626835, 0);
  upper.orientation = Quat(0.99658672943049464, 0.00044330963283359945, -0.010168925722737953, -0.081922445942763586);
  upper.position = Vec3(-0.042767936977899129, 0.049617810584171279, 0.49228912703216898);
  f.add(lower);
  f.add(upper);
  const auto& c = f.run_scene_poses();
  ASSERT_FALSE(c.empty());
  for (const Contact& k : c) {
    EXPECT_GT(-k.normal.z(), std::cos(0.03));
    EXPECT_GT(k.distance, -0.02);
    EXPECT_LE(k.distance, 0.0);
  }
}

TEST(Collide, GjkStoppingShortFallsBackToTheBestFaceAxis) {
  // Two boxes of the 200-box pile at rest side by side (step 203), 4.3e-7 m apart across A's face
  // (separating axes by hand: that face's normal is the only one with a gap). btGjkEpaSolver2's GJK
  // stops short here at 1 cm along (1, 0.002, 0), an axis on which the boxes' support planes
  // overlap by 0.22 m; that overlap used to become a contact 0.22 m deep.
  Fixture f;
  BodyDef a = box(Vec3(0.17333104735985932, 0.17163214792820555, 0.23209116182278028));
  BodyDef b = box(Vec3(0.11291485535884477, 0.1894615704015534, 0.2057517919568597));
  a.position = Vec3(-0.54513022454801, 0.44991970374213364, 0.1716315583369852);
  a.orientation = Quat(0.682699156796549, 0.6826989548305665, -0.18417928812898518, -0.18417922848908239);
  b.position = Vec3(-0.7932994283187336, 0.8307355872231955, 0.22375679512654398);
  b.orientation = Quat(0.05447495188818628, 0.7577211539273059, -0.6486153923010214, 0.04678894504094001);
  f.add(a);
  f.add(b);
  const Vec3 face = a.orientation.normalized() * Vec3::UnitX();  // A's face normal, towards -B
  const auto& c = f.run_scene_poses();
  ASSERT_FALSE(c.empty());
  for (const Contact& k : c) {
    EXPECT_NEAR(k.normal.dot(face), 1.0, 1e-6);
    EXPECT_GT(k.distance, 0.0);
    EXPECT_LT(k.distance, 1e-6);
  }
}

TEST(Collide, NothingBeyondTheMargin) {
  Fixture f;
  f.add(ground());
  BodyDef s = sphere(0.2), b = box(Vec3(0.1, 0.1, 0.1));
  s.position = Vec3(0, 0, 0.2 + kMargin + 1e-6);
  b.position = Vec3(1, 0, 0.1 + kMargin + 1e-6);
  f.add(s);
  f.add(b);
  EXPECT_TRUE(f.run_scene_poses().empty());
  f.x[1].z() -= 2e-6;  // now within the margin
  f.x[2].z() -= 2e-6;
  EXPECT_EQ(f.run().size(), 5u);
}

TEST(Collide, JoinedBodiesCollideOnlyWithCollideConnected) {
  for (bool connected : {false, true}) {
    Fixture f;
    BodyDef a = sphere(0.2), b = sphere(0.2), c = sphere(0.2);
    b.position = Vec3(0.3, 0, 0);
    c.position = Vec3(0.6, 0, 0);
    f.add(a);
    f.add(b);
    f.add(c);
    JointDef j;
    j.body_a = 0;
    j.body_b = 1;
    j.collide_connected = connected;
    f.scene.joints.push_back(j);
    JointDef world;  // a joint to the world filters nothing
    world.body_a = 2;
    world.body_b = -1;
    f.scene.joints.push_back(world);
    const auto& contacts = f.run_scene_poses();
    std::set<std::pair<int, int>> pairs;
    for (const Contact& k : contacts) pairs.insert({k.body_a, k.body_b});
    EXPECT_EQ(pairs.count({0, 1}), connected ? 1u : 0u);
    EXPECT_EQ(pairs.count({1, 2}), 1u);
  }
}

TEST(Collide, StaticPairsAreNeverReported) {
  Fixture f;
  f.add(ground());
  BodyDef wall = box(Vec3(0.1, 1, 1), true);
  wall.position = Vec3(0, 0, 0.5);  // overlaps the ground
  f.add(wall);
  EXPECT_TRUE(f.run_scene_poses().empty());
}

TEST(Collide, IdsAreFreshForNewContactsAndRunsAreDeterministic) {
  auto scene = [] {
    Fixture f;
    f.add(ground());
    BodyDef a = box(Vec3(0.2, 0.2, 0.2));
    a.position = Vec3(0, 0, 0.2);
    f.add(a);
    BodyDef s = sphere(0.1);
    s.position = Vec3(1, 0, 0.3);
    f.add(s);
    return f;
  };
  Fixture f = scene(), g = scene();
  std::set<std::uint64_t> seen;
  for (int step = 0; step < 12; ++step) {
    const auto& cf = step == 0 ? f.run_scene_poses() : f.run();
    const auto& cg = step == 0 ? g.run_scene_poses() : g.run();
    ASSERT_EQ(cf.size(), cg.size());
    for (std::size_t i = 0; i < cf.size(); ++i) {
      EXPECT_EQ(cf[i].id, cg[i].id);
      EXPECT_EQ(cf[i].point, cg[i].point);
      EXPECT_EQ(cf[i].distance, cg[i].distance);
      if (i > 0)
        EXPECT_TRUE(std::tie(cf[i - 1].body_a, cf[i - 1].body_b, cf[i - 1].id) <
                    std::tie(cf[i].body_a, cf[i].body_b, cf[i].id));
    }
    std::set<std::uint64_t> now;
    for (const Contact& k : cf) now.insert(k.id);
    EXPECT_EQ(now.size(), cf.size());
    // The sphere falls onto the ground at step 4 and lifts off again at step 8: its contact is new
    // each time it appears.
    const double z = step < 4 || step >= 8 ? 0.3 : 0.1;
    f.x[2].z() = g.x[2].z() = z;
    for (const Contact& k : cf)
      if (k.body_a == 2 && step == 4) EXPECT_EQ(seen.count(k.id), 0u);
    seen.insert(now.begin(), now.end());
  }
}

// Independent geometry of the test shapes: outward facet planes of a point set by brute force
// over all triples, support points and a surface function that is zero exactly on the surface.
struct Plane {
  Vec3 n;
  double d;
};
std::vector<Plane> facets(const std::vector<Vec3>& v) {
  std::vector<Plane> planes;
  const int n = static_cast<int>(v.size());
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      for (int k = j + 1; k < n; ++k) {
        Vec3 normal = (v[j] - v[i]).cross(v[k] - v[i]);
        if (normal.norm() < 1e-12) continue;
        normal.normalize();
        double lo = INFINITY, hi = -INFINITY;
        for (const Vec3& p : v) lo = std::min(lo, normal.dot(p - v[i])), hi = std::max(hi, normal.dot(p - v[i]));
        if (hi <= 1e-12) planes.push_back({normal, normal.dot(v[i])});
        if (lo >= -1e-12) planes.push_back({-normal, -normal.dot(v[i])});
      }
  return planes;
}

std::vector<Vec3> corners_of(const BodyDef& b) {
  if (b.shape.type == ShapeType::Convex) return b.shape.vertices;
  std::vector<Vec3> v;
  const Vec3& h = b.shape.half_extents;
  for (int i = 0; i < 8; ++i) v.emplace_back(i & 1 ? h.x() : -h.x(), i & 2 ? h.y() : -h.y(), i & 4 ? h.z() : -h.z());
  return v;
}

// Support point in world direction d of body b at pose (x, q).
Vec3 support_of(const BodyDef& b, const Vec3& x, const Quat& q, const Vec3& d) {
  const Vec3 l = q.conjugate() * d;
  const double r = b.shape.radius, h = b.shape.half_length;
  switch (b.shape.type) {
    case ShapeType::Sphere: return x + r * d;
    case ShapeType::Capsule: return x + q * Vec3(0, 0, l.z() >= 0 ? h : -h) + r * d;
    case ShapeType::Cylinder: {
      const double across = std::hypot(l.x(), l.y());
      return x + q * (Vec3(0, 0, l.z() >= 0 ? h : -h) + (across > 0 ? Vec3(Vec3(l.x(), l.y(), 0) * (r / across)) : Vec3(Vec3::Zero())));
    }
    default: {
      Vec3 best = Vec3::Zero();
      double top = -INFINITY;
      for (const Vec3& v : corners_of(b))
        if (v.dot(l) > top) top = v.dot(l), best = v;
      return x + q * best;
    }
  }
}

// Zero on the surface of b, negative inside, positive outside.
double surface_of(const BodyDef& b, const std::vector<Plane>& planes, const Vec3& x, const Quat& q, const Vec3& p) {
  const Vec3 l = q.conjugate() * (p - x);
  const double r = b.shape.radius, h = b.shape.half_length;
  switch (b.shape.type) {
    case ShapeType::Sphere: return l.norm() - r;
    case ShapeType::Capsule: return (l - Vec3(0, 0, std::clamp(l.z(), -h, h))).norm() - r;
    case ShapeType::Cylinder: return std::max(std::abs(l.z()) - h, std::hypot(l.x(), l.y()) - r);
    default: {
      double worst = -INFINITY;
      for (const Plane& f : planes) worst = std::max(worst, f.n.dot(l) - f.d);
      return worst;
    }
  }
}

// The ground and 40 bodies, each shape type in turn (a rock hull of 16 random points among them), run
// once at the scene's poses; returns each box's and hull's facet planes (empty for the others).
std::vector<std::vector<Plane>> add_every_shape(Fixture& f, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  f.add(ground());
  std::vector<Vec3> rock;
  for (int i = 0; i < 16; ++i) rock.push_back(Vec3(u(rng), u(rng), u(rng)).normalized().cwiseProduct(Vec3(0.15, 0.1, 0.12)));
  const BodyDef shapes[] = {sphere(0.1), box(Vec3(0.1, 0.05, 0.15)), round_body(ShapeType::Capsule, 0.05, 0.1),
                            round_body(ShapeType::Cylinder, 0.08, 0.1), hull(rock)};
  for (int i = 0; i < 40; ++i) f.add(shapes[i % 5]);
  std::vector<std::vector<Plane>> planes(f.scene.bodies.size());
  for (std::size_t i = 0; i < planes.size(); ++i)
    if (f.scene.bodies[i].shape.type == ShapeType::Box || f.scene.bodies[i].shape.type == ShapeType::Convex)
      planes[i] = facets(corners_of(f.scene.bodies[i]));
  f.run_scene_poses();
  return planes;
}

TEST(Collide, RandomPosesGiveCertifiedContacts) {
  // Every shape type against every other at random poses, some far away, many deep inside each
  // other. Every contact is finite, with a unit normal, within the margin, a dynamic. The deepest
  // contact of each pair is checked against independent geometry: the plane through one of its
  // points, normal to its normal, bounds that body (a face contact's reference face, or both
  // bodies for a closest pair: then the distance is the true one), and at resting depths both
  // points lie on the exact surfaces.
  std::mt19937 rng(2024);
  std::uniform_real_distribution<double> u(-1, 1);
  Fixture f;
  const std::vector<std::vector<Plane>> planes = add_every_shape(f, rng);
  const int n = static_cast<int>(f.scene.bodies.size());
  int certified = 0, separated = 0;
  for (int trial = 0; trial < 60; ++trial) {
    for (int i = 1; i < n; ++i) {
      const double spread = trial % 3 == 0 ? 0.05 : 0.6;  // sometimes all piled into each other
      f.x[i] = Vec3(u(rng), u(rng), 0.5 * (u(rng) + 1)) * spread;
      if (trial == 7 && i == 3) f.x[i] = Vec3(1e7, -3e6, 2e5);
      f.q[i] = Quat(Eigen::AngleAxisd(kPi * u(rng), Vec3(u(rng), u(rng), u(rng)).normalized()));
    }
    const auto& contacts = f.run();
    for (std::size_t i = 0; i < contacts.size(); ++i) {
      const Contact& k = contacts[i];
      ASSERT_TRUE(k.point.allFinite());
      ASSERT_TRUE(std::isfinite(k.distance));
      EXPECT_NEAR(k.normal.norm(), 1.0, 1e-12);
      EXPECT_LE(k.distance, kMargin);
      EXPECT_FALSE(f.scene.bodies[k.body_a].is_static);
      if (i + 1 < contacts.size() && contacts[i + 1].body_a == k.body_a && contacts[i + 1].body_b == k.body_b) continue;
      // k is the last contact of its pair: certify the pair's deepest.
      const Contact* deepest = &k;
      for (std::size_t j = i; j-- > 0 && contacts[j].body_a == k.body_a && contacts[j].body_b == k.body_b;)
        if (contacts[j].distance < deepest->distance) deepest = &contacts[j];
      const int a = deepest->body_a, b = deepest->body_b;
      const BodyDef &da = f.scene.bodies[a], &db = f.scene.bodies[b];
      const Vec3& nrm = deepest->normal;
      const Vec3 on_a = deepest->point + 0.5 * deepest->distance * nrm;
      const Vec3 on_b = deepest->point - 0.5 * deepest->distance * nrm;
      // A support line counts as flat within the rounding (1e-6 of the size) of its ends.
      const double plane_tol = 2e-6 * 0.3;
      const bool bounds_a = std::abs(nrm.dot(support_of(da, f.x[a], f.q[a], -nrm) - on_a)) <= plane_tol;
      const bool bounds_b = std::abs(nrm.dot(support_of(db, f.x[b], f.q[b], nrm) - on_b)) <= plane_tol;
      EXPECT_TRUE(bounds_a || bounds_b);
      // Deep inside each other (the piled trials) the normal is EPA's best and the two support
      // points need not face each other; resting contacts are shallow. Across the normal a point
      // may be off by a little more than the rounding where a cylinder rim supports on an almost
      // flat cap (its support point turns fast with the normal) or a tilted capsule is clipped.
      if (deepest->distance < -kMargin) continue;
      // Across the normal a contact may sit up to the rounding radius (a twentieth of the margin)
      // off where the sharp shapes touch: where a cylinder rim or a vertex meets an edge.
      const double tol = 0.05 * kMargin;
      EXPECT_NEAR(surface_of(da, planes[a], f.x[a], f.q[a], on_a), 0, tol) << "a " << static_cast<int>(da.shape.type);
      EXPECT_NEAR(surface_of(db, planes[b], f.x[b], f.q[b], on_b), 0, tol) << "b " << static_cast<int>(db.shape.type);
      ++certified;
      separated += deepest->distance > 0;
    }
  }
  EXPECT_GT(certified, 300);
  EXPECT_GT(separated, 100);
}

TEST(Collide, SpeculativeContactsAreExactDistances) {
  // Every shape type against every other at random poses and speeds of up to 10 m/s and 20 rad/s,
  // so that pairs report contacts far beyond the contact margin, from faces along the normal and
  // along the relative motion. Every separated contact must be a true distance: both its points on
  // their bodies' surfaces, and one of the two bodies wholly behind the plane through its point
  // normal to the normal (the foot of the other point is then its closest point on that body).
  std::mt19937 rng(77);
  std::uniform_real_distribution<double> u(-1, 1);
  Fixture f;
  const std::vector<std::vector<Plane>> planes = add_every_shape(f, rng);
  const int n = static_cast<int>(f.scene.bodies.size());
  int certified = 0, far = 0;
  for (int trial = 0; trial < 30; ++trial) {
    for (int i = 1; i < n; ++i) {
      f.x[i] = Vec3(u(rng), u(rng), 0.5 * (u(rng) + 1)) * 1.2;
      f.q[i] = Quat(Eigen::AngleAxisd(kPi * u(rng), Vec3(u(rng), u(rng), u(rng)).normalized()));
      f.v[i] = 10 * Vec3(u(rng), u(rng), u(rng)) / std::sqrt(3.0);
      f.w[i] = 20 * Vec3(u(rng), u(rng), u(rng)) / std::sqrt(3.0);
    }
    for (const Contact& k : f.run()) {
      if (k.distance < 0) continue;
      const int a = k.body_a, b = k.body_b;
      const BodyDef &da = f.scene.bodies[a], &db = f.scene.bodies[b];
      const Vec3& nrm = k.normal;
      const Vec3 on_a = k.point + 0.5 * k.distance * nrm;
      const Vec3 on_b = k.point - 0.5 * k.distance * nrm;
      const double plane_tol = 2e-6 * 0.3;
      const bool bounds_a = std::abs(nrm.dot(support_of(da, f.x[a], f.q[a], -nrm) - on_a)) <= plane_tol;
      const bool bounds_b = std::abs(nrm.dot(support_of(db, f.x[b], f.q[b], nrm) - on_b)) <= plane_tol;
      EXPECT_TRUE(bounds_a || bounds_b) << "distance " << k.distance;
      // Where a cylinder rim or a vertex meets an edge, a point may sit about the rounding radius
      // (a twentieth of the margin) off along the surface (see above): twice that is allowed.
      const double tol = 0.1 * kMargin;
      EXPECT_NEAR(surface_of(da, planes[a], f.x[a], f.q[a], on_a), 0, tol)
          << "a " << static_cast<int>(da.shape.type) << ", distance " << k.distance;
      EXPECT_NEAR(surface_of(db, planes[b], f.x[b], f.q[b], on_b), 0, tol)
          << "b " << static_cast<int>(db.shape.type) << ", distance " << k.distance;
      ++certified;
      far += k.distance > 5 * kMargin;
    }
  }
  EXPECT_GT(certified, 500);
  EXPECT_GT(far, 200);
}

TEST(Collide, SphereDistancesMatchCentreDistances) {
  // Round shapes are exact: sphere-sphere distances equal |c1 - c2| - r1 - r2 wherever reported.
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> u(0, 1);
  Fixture f;
  for (int i = 0; i < 30; ++i) f.add(sphere(0.05 + 0.1 * u(rng)));
  f.run_scene_poses();
  for (int trial = 0; trial < 20; ++trial) {
    for (int i = 0; i < 30; ++i) f.x[i] = Vec3(u(rng), u(rng), u(rng)) * 0.8;
    int expected = 0;
    for (int i = 0; i < 30; ++i)
      for (int j = i + 1; j < 30; ++j)
        expected += (f.x[i] - f.x[j]).norm() - f.scene.bodies[i].shape.radius - f.scene.bodies[j].shape.radius <= kMargin;
    const auto& c = f.run();
    EXPECT_EQ(static_cast<int>(c.size()), expected);
    for (const Contact& k : c) {
      const Vec3 d = f.x[k.body_a] - f.x[k.body_b];
      EXPECT_NEAR(k.distance, d.norm() - f.scene.bodies[k.body_a].shape.radius - f.scene.bodies[k.body_b].shape.radius,
                  1e-9);
      if (d.norm() > 1e-6) expect_vec_near(k.normal, d.normalized(), 1e-9);
    }
  }
}

// Speculative margin (collide.hpp): a pair reports contacts up to margin + sweep_a + sweep_b,
// sweep = min(h (|v| + |w| reach), kMaxSweep), reach = farthest surface point from the centre of
// mass (a sphere's radius); static bodies never sweep.
TEST(Collide, SpeculativeMarginFollowsEachPairsSpeed) {
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> u(0, 1);
  Fixture f;
  constexpr int kSpheres = 30;
  for (int i = 0; i < kSpheres; ++i) {
    BodyDef s = sphere(0.05 + 0.1 * u(rng));
    s.is_static = i % 5 == 0;
    f.add(s);
  }
  f.run_scene_poses();
  auto unit = [&] { return Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5).normalized(); };
  int far_pairs = 0;
  for (int trial = 0; trial < 20; ++trial) {
    for (int i = 0; i < kSpheres; ++i) {
      f.x[i] = Vec3(u(rng), u(rng), u(rng)) * 2.0;
      f.v[i] = 25 * u(rng) * unit();  // up to 0.42 m per step
      f.w[i] = 40 * u(rng) * unit();
    }
    f.v[trial] = 500 * unit();  // capped at kMaxSweep
    std::vector<double> sweep(kSpheres);
    for (int i = 0; i < kSpheres; ++i)
      sweep[i] = f.scene.bodies[i].is_static
                     ? 0.0
                     : std::min(f.h * (f.v[i].norm() + f.w[i].norm() * f.scene.bodies[i].shape.radius), Collider::kMaxSweep);
    int expected = 0;
    for (int i = 0; i < kSpheres; ++i)
      for (int j = i + 1; j < kSpheres; ++j) {
        if (f.scene.bodies[i].is_static && f.scene.bodies[j].is_static) continue;
        const double gap = (f.x[i] - f.x[j]).norm() - f.scene.bodies[i].shape.radius - f.scene.bodies[j].shape.radius;
        expected += gap <= kMargin + sweep[i] + sweep[j];
        far_pairs += gap > 0.1 && gap <= kMargin + sweep[i] + sweep[j];
      }
    const auto& c = f.run();
    EXPECT_EQ(static_cast<int>(c.size()), expected);
    for (const Contact& k : c) {
      const Vec3 d = f.x[k.body_a] - f.x[k.body_b];
      EXPECT_NEAR(k.distance, d.norm() - f.scene.bodies[k.body_a].shape.radius - f.scene.bodies[k.body_b].shape.radius,
                  1e-9);
      expect_vec_near(k.normal, d.normalized(), 1e-9);
    }
  }
  EXPECT_GT(far_pairs, 50);  // the speeds matter: many pairs are reported far beyond the contact margin
}

TEST(Collide, SweepTurnsAboutTheCentreOfMass) {
  // A cube hull whose shape frame lies 2 m from its centre: spinning at w, its points move at most
  // h w sqrt(3) 0.1 per step, not h w 2.1.
  std::vector<Vec3> v;
  for (const Vec3& p : cube_corners(0.1)) v.push_back(p + Vec3(2, 0, 0));
  const double w = 10, sweep = (1.0 / 60) * w * std::sqrt(3.0) * 0.1;
  for (double gap : {kMargin + sweep - 1e-4, kMargin + sweep + 1e-4}) {
    Fixture f;
    f.add(ground());
    BodyDef b = hull(v);
    b.position = Vec3(-2, 0, 0.1 + gap);
    f.add(b);
    f.run_scene_poses();
    f.w[1] = Vec3(0, w, 0);
    EXPECT_EQ(f.run().size(), gap < kMargin + sweep ? 4u : 0u) << "gap " << gap;
  }
}

TEST(Collide, FastApproachGivesContactsAtTheirExactDistances) {
  // A box falling face down at 20 m/s, 0.3 m above the ground: its four corners at 0.3 m, which
  // it would cover within the step (0.33 m); at rest the same pose reports nothing.
  const Vec3 h(0.3, 0.2, 0.1);
  Fixture f;
  f.add(ground());
  BodyDef b = box(h);
  b.position = Vec3(0.4, -0.1, h.z() + 0.3);
  b.orientation = Quat(Eigen::AngleAxisd(0.5, Vec3::UnitZ()));
  f.add(b);
  EXPECT_TRUE(f.run_scene_poses().empty());
  f.v[1] = Vec3(0, 0, -20);
  expect_box_corners(f.run(), h, 0.4, -0.1, 0.5, 0.3, 1e-9);
  f.v[1] = Vec3(0, 0, -17);  // 0.283 m per step: out of reach
  EXPECT_TRUE(f.run().empty());
}

TEST(Collide, FallingBoxGetsContactsAlongItsMotion) {
  // A static cube (half side 0.2) turned about x by asin 0.6: its upper-left face rises from the
  // edge at (y, z) = (-0.28, 0.04) to the top edge at (0.04, 0.28), slope 3/4, outward normal
  // (0, -0.6, 0.8). Over it a level box (half extents 0.2, 0.25, 0.08) whose bottom-right edge,
  // at y = -0.08, is 0.25 above that face (which is at z = 0.19 there), 0.8 * 0.25 = 0.2 from its
  // plane. Falling at 20 m/s the box closes 0.33 m per step: besides the closest pair along the
  // face's normal, the faces facing the motion give that edge's ends along the bottom face's
  // normal, at their vertical distance 0.25. At rest, with the same margin, only the former.
  const double gap = 0.25, speed = 20, h = 1.0 / 60;
  for (bool moving : {true, false}) {
    Fixture f;
    f.margin = moving ? kMargin : kMargin + h * speed;
    BodyDef cube = box(Vec3(0.2, 0.2, 0.2), true);
    cube.orientation = Quat(Eigen::AngleAxisd(std::asin(0.6), Vec3::UnitX()));
    f.add(cube);
    BodyDef lid = box(Vec3(0.2, 0.25, 0.08));
    lid.position = Vec3(0, -0.33, 0.19 + gap + 0.08);
    f.add(lid);
    f.run_scene_poses();
    if (moving) f.v[1] = Vec3(0, 0, -speed);
    const auto& c = f.run();
    SCOPED_TRACE(moving ? "moving" : "at rest");
    int along_motion = 0;
    for (const Contact& k : c) {
      if (k.normal.z() < 0.9999) {
        expect_vec_near(k.normal, Vec3(0, -0.6, 0.8), 1e-9);
        continue;
      }
      ++along_motion;
      expect_vec_near(k.point, Vec3(k.point.x() > 0 ? 0.2 : -0.2, -0.08, 0.19 + 0.5 * gap), 1e-9);
      EXPECT_NEAR(k.distance, gap, 1e-9);
    }
    EXPECT_EQ(along_motion, moving ? 2 : 0);
  }
}

TEST(Collide, RollingSphereKeepsItsContactId) {
  // Rolling at 6 m/s, the contact point moves 0.1 m per step along the ground and as far around
  // the sphere: beyond the contact margin in both bodies' frames, within the pair's margin.
  const double r = 0.2, speed = 6, h = 1.0 / 60;
  Fixture f;
  f.add(ground());
  BodyDef s = sphere(r);
  s.position = Vec3(-1, 0.3, r);
  f.add(s);
  f.run_scene_poses();
  f.v[1] = Vec3(speed, 0, 0);
  f.w[1] = Vec3(0, speed / r, 0);
  std::uint64_t id = 0;
  for (int step = 0; step < 10; ++step) {
    f.x[1] += h * f.v[1];
    f.q[1] = (Quat(Eigen::AngleAxisd(h * speed / r, Vec3::UnitY())) * f.q[1]).normalized();
    const auto& c = f.run();
    ASSERT_EQ(c.size(), 1u);
    EXPECT_NEAR(c[0].distance, 0, 1e-12);
    if (step > 0) EXPECT_EQ(c[0].id, id) << "step " << step;
    id = c[0].id;
  }
}

TEST(Collide, RejectsBadVelocitiesAndStep) {
  Fixture f;
  f.add(sphere(0.1));
  f.run_scene_poses();
  f.v[0].x() = std::nan("");
  EXPECT_THROW(f.run(), std::invalid_argument);
  f.v[0].x() = 0;
  f.h = -1;
  EXPECT_THROW(f.run(), std::invalid_argument);
  f.h = 1.0 / 60;
  f.w.push_back(Vec3::Zero());
  EXPECT_THROW(f.collider->collide(f.x, f.q, f.v, f.w, f.h, f.contacts), std::invalid_argument);
}

TEST(Collide, RejectsBadMarginAndDegenerateHull) {
  SceneDef scene;
  scene.bodies.push_back(sphere(1));
  EXPECT_THROW(Collider(scene, -1.0), InputError);
  EXPECT_THROW(Collider(scene, std::nan("")), InputError);
  JointDef j;
  j.body_a = 0;
  j.body_b = 1;
  scene.joints.push_back(j);
  EXPECT_THROW(Collider(scene, kMargin), InputError);  // body 1 does not exist
  scene.joints.clear();
  scene.bodies.push_back(hull({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0)}));
  EXPECT_THROW(Collider(scene, kMargin), InputError);
}

}  // namespace
}  // namespace rbpart
