// Mass properties against closed forms and independent integrals (docs/design.md#dynamics).
#include "scene/mass_properties.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "core/error.hpp"

namespace rbpart {
namespace {

constexpr double kPi = 3.14159265358979323846;

Shape sphere(double r) {
  Shape s;
  s.type = ShapeType::Sphere;
  s.radius = r;
  return s;
}
Shape box(const Vec3& h) {
  Shape s;
  s.type = ShapeType::Box;
  s.half_extents = h;
  return s;
}
Shape round_shape(ShapeType type, double r, double h) {
  Shape s;
  s.type = type;
  s.radius = r;
  s.half_length = h;
  return s;
}
Shape convex(std::vector<Vec3> v) {
  Shape s;
  s.type = ShapeType::Convex;
  s.vertices = std::move(v);
  return s;
}

BodyDef body(Shape shape, double mass, double density) {
  BodyDef b;
  b.name = "probe";
  b.shape = std::move(shape);
  b.mass = mass;
  b.density = density;
  return b;
}

void expect_matrix_near(const Mat3& a, const Mat3& b, double tol) {
  EXPECT_LE((a - b).cwiseAbs().maxCoeff(), tol) << "got\n" << a << "\nexpected\n" << b;
}

// Volume and inertia (unit density) of a solid of revolution about z with radius rho(z), by
// 5-point Gauss-Legendre on each piece: the integrands are polynomials of degree <= 4 on a
// cylinder or a spherical cap, so the rule is exact. Independent of the closed forms.
struct Revolution {
  double volume = 0, izz = 0, ixx = 0;
  template <class Rho2>
  void add(double z0, double z1, Rho2 rho2) {
    static const double x[5] = {0, -0.5384693101056831, 0.5384693101056831, -0.9061798459386640, 0.9061798459386640};
    static const double w[5] = {0.5688888888888889, 0.4786286704993665, 0.4786286704993665, 0.2369268850561891,
                                0.2369268850561891};
    const double half = 0.5 * (z1 - z0), mid = 0.5 * (z0 + z1);
    for (int k = 0; k < 5; ++k) {
      const double z = mid + half * x[k], r2 = rho2(z), wk = w[k] * half;
      volume += wk * kPi * r2;                       // disc area
      izz += wk * kPi * r2 * r2 / 2;                 // disc polar moment
      ixx += wk * (kPi * r2 * r2 / 4 + kPi * r2 * z * z);  // disc diameter moment + parallel axis
    }
  }
};

TEST(MassProperties, SphereMatchesClosedForm) {
  const double r = 0.37, m = 3.0;
  const MassProperties p = mass_properties(body(sphere(r), m, 0));
  EXPECT_NEAR(p.volume, 4.0 / 3.0 * kPi * r * r * r, 1e-15);
  EXPECT_DOUBLE_EQ(p.mass, m);
  EXPECT_LE(p.com.norm(), 0.0);
  expect_matrix_near(p.inertia, Mat3::Identity() * 0.4 * m * r * r, 1e-15);
}

TEST(MassProperties, BoxMatchesClosedFormWithDensity) {
  const Vec3 h(0.5, 0.2, 0.1);
  const double rho = 2500;
  const MassProperties p = mass_properties(body(box(h), 0, rho));
  const double m = rho * 8 * h.prod();
  EXPECT_NEAR(p.mass, m, 1e-12 * m);
  // (m/12)(b^2 + c^2) with full side lengths b = 2 h_y, c = 2 h_z.
  const Vec3 s = 2 * h;
  const Mat3 expected = Vec3(s.y() * s.y() + s.z() * s.z(), s.x() * s.x() + s.z() * s.z(),
                             s.x() * s.x() + s.y() * s.y()).asDiagonal() * (m / 12);
  expect_matrix_near(p.inertia, expected, 1e-12 * m);
}

TEST(MassProperties, CylinderMatchesSliceIntegral) {
  const double r = 0.3, h = 0.8;
  const MassProperties p = unit_density_properties(round_shape(ShapeType::Cylinder, r, h));
  Revolution ref;
  ref.add(-h, h, [&](double) { return r * r; });
  EXPECT_NEAR(p.volume, ref.volume, 1e-14);
  expect_matrix_near(p.inertia, Vec3(ref.ixx, ref.ixx, ref.izz).asDiagonal(), 1e-14);
  EXPECT_NEAR(ref.izz, 0.5 * p.volume * r * r, 1e-14);  // the textbook m r^2 / 2
}

TEST(MassProperties, CapsuleMatchesSliceIntegral) {
  for (const auto& [r, h] : {std::pair{0.1, 0.3}, std::pair{0.5, 0.05}, std::pair{0.2, 2.0}}) {
    const MassProperties p = unit_density_properties(round_shape(ShapeType::Capsule, r, h));
    Revolution ref;
    ref.add(-h, h, [&](double) { return r * r; });
    ref.add(h, h + r, [&](double z) { return r * r - (z - h) * (z - h); });
    ref.add(-h - r, -h, [&](double z) { return r * r - (z + h) * (z + h); });
    EXPECT_NEAR(p.volume, ref.volume, 1e-13);
    EXPECT_LE(p.com.norm(), 0.0);
    expect_matrix_near(p.inertia, Vec3(ref.ixx, ref.ixx, ref.izz).asDiagonal(), 1e-13);
  }
}

std::vector<Vec3> box_corners(const Vec3& h) {
  std::vector<Vec3> v;
  for (int i = 0; i < 8; ++i) v.emplace_back(i & 1 ? h.x() : -h.x(), i & 2 ? h.y() : -h.y(), i & 4 ? h.z() : -h.z());
  return v;
}

TEST(MassProperties, HullOfBoxCornersAndInteriorPointsIsTheBox) {
  const Vec3 h(0.31, 0.123456789, 0.7777);
  const MassProperties ref = unit_density_properties(box(h));
  std::vector<Vec3> v = box_corners(h);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.99, 0.99);
  for (int i = 0; i < 50; ++i) v.push_back(Vec3(u(rng), u(rng), u(rng)).cwiseProduct(h));  // inside: no effect
  v.push_back(Vec3(h.x(), 0.2 * h.y(), -0.5 * h.z()));  // on a face: no effect either
  std::shuffle(v.begin(), v.end(), rng);
  const MassProperties p = unit_density_properties(convex(v));
  EXPECT_NEAR(p.volume, ref.volume, 1e-14);
  EXPECT_LE(p.com.norm(), 1e-15);
  expect_matrix_near(p.inertia, ref.inertia, 1e-15);
}

TEST(MassProperties, TetrahedronMatchesTextbookFormulas) {
  // Right tetrahedron with legs a, b, c on the axes: V = abc/6, centroid (a, b, c)/4,
  // integral x^2 dV = a^2 V / 10, integral x y dV = a b V / 20.
  const double a = 1.0, b = 2.0, c = 3.0;
  const Vec3 corner(0.4, -1.0, 2.5);
  const std::vector<Vec3> v = {corner + Vec3(0, 0, c), corner + Vec3(a, 0, 0), corner, corner + Vec3(0, b, 0)};
  const double rho = 7;
  const MassProperties p = mass_properties(body(convex(v), 0, rho));
  const double V = a * b * c / 6, m = rho * V;
  EXPECT_NEAR(p.volume, V, 1e-14);
  EXPECT_NEAR(p.mass, m, 1e-13);
  EXPECT_LE((p.com - (corner + Vec3(a, b, c) / 4)).norm(), 1e-14);
  // About the centroid: I_xx = 3 m (b^2 + c^2) / 80, I_xy = m a b / 80 (products of inertia enter
  // the tensor with a minus sign and the covariance x y is negative here).
  Mat3 expected;
  expected << 3 * m * (b * b + c * c) / 80, m * a * b / 80, m * a * c / 80,  //
      m * a * b / 80, 3 * m * (a * a + c * c) / 80, m * b * c / 80,          //
      m * a * c / 80, m * b * c / 80, 3 * m * (a * a + b * b) / 80;
  expect_matrix_near(p.inertia, expected, 1e-12);
}

std::vector<Vec3> rock(std::mt19937& rng, int n) {
  std::normal_distribution<double> g;
  std::vector<Vec3> v;
  for (int i = 0; i < n; ++i) v.push_back(Vec3(g(rng), g(rng), g(rng)).normalized().cwiseProduct(Vec3(0.3, 0.2, 0.12)));
  return v;
}

TEST(MassProperties, RigidMotionOfHullMovesComAndRotatesInertia) {
  std::mt19937 rng(3);
  const std::vector<Vec3> v = rock(rng, 40);
  const Mat3 R = Quat(Eigen::AngleAxisd(1.1, Vec3(1, -2, 0.5).normalized())).toRotationMatrix();
  const Vec3 t(10.0, -3.0, 0.25);
  std::vector<Vec3> w;
  for (const Vec3& x : v) w.push_back(R * x + t);
  const MassProperties p = unit_density_properties(convex(v));
  const MassProperties q = unit_density_properties(convex(w));
  EXPECT_GT(p.volume, 0.0);
  EXPECT_NEAR(q.volume, p.volume, 1e-14);
  EXPECT_LE((q.com - (R * p.com + t)).norm(), 1e-13);
  expect_matrix_near(q.inertia, R * p.inertia * R.transpose(), 1e-14);
  // A principal frame of a genuine rock has distinct moments, so the test sees the rotation.
  EXPECT_GT((p.inertia - q.inertia).cwiseAbs().maxCoeff(), 1e-5);
}

// Points spread evenly on the unit sphere (Fibonacci lattice).
std::vector<Vec3> sphere_cloud(int n) {
  std::vector<Vec3> v;
  const double golden = kPi * (3 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1 - (2 * i + 1.0) / n, s = std::sqrt(1 - z * z);
    v.emplace_back(s * std::cos(golden * i), s * std::sin(golden * i), z);
  }
  return v;
}

TEST(MassProperties, HullOfDenseSphereCloudApproachesTheSphere) {
  const MassProperties ball = unit_density_properties(sphere(1.0));
  double previous_error = INFINITY;
  for (int n : {200, 3000}) {
    const MassProperties p = unit_density_properties(convex(sphere_cloud(n)));
    const double error = std::abs(p.volume - ball.volume) / ball.volume;
    // An inscribed polyhedron with n vertices misses a volume fraction of about 2 pi / n.
    EXPECT_LT(p.volume, ball.volume);
    EXPECT_LT(error, 10.0 / n);
    EXPECT_LT(error, previous_error);
    previous_error = error;
    EXPECT_LT(p.com.norm(), 10.0 / n);
    expect_matrix_near(p.inertia, ball.inertia, 20.0 / n * ball.inertia(0, 0));
  }
}

TEST(MassProperties, MassOverridesDensityAndScalesInertia) {
  const Shape s = box(Vec3(0.1, 0.2, 0.3));
  const MassProperties unit = unit_density_properties(s);
  const MassProperties p = mass_properties(body(s, 4.0, 1000));
  EXPECT_DOUBLE_EQ(p.mass, 4.0);
  expect_matrix_near(p.inertia, unit.inertia * (4.0 / unit.volume), 1e-15);
}

TEST(MassProperties, StaticBodyNeedsOnlyASoundShape) {
  BodyDef b = body(box(Vec3(5, 5, 0.5)), 0, 0);
  b.is_static = true;
  EXPECT_EQ(mass_properties(b).mass, 0.0);
  b.shape.half_extents.z() = 0;
  EXPECT_THROW(mass_properties(b), InputError);
}

// Runs mass_properties and returns the InputError message ("" if it did not throw).
std::string error_of(const BodyDef& b) {
  try {
    mass_properties(b);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

void expect_error(const BodyDef& b, const std::string& fragment) {
  const std::string message = error_of(b);
  EXPECT_NE(message.find("probe"), std::string::npos) << message;
  EXPECT_NE(message.find(fragment), std::string::npos) << "message '" << message << "' lacks '" << fragment << "'";
}

TEST(MassProperties, DegenerateInputThrowsNamingTheProblem) {
  const double nan = std::nan(""), inf = INFINITY;
  for (double r : {0.0, -1.0, nan, inf}) expect_error(body(sphere(r), 1, 0), "sphere radius");
  expect_error(body(box(Vec3(1, 0, 1)), 1, 0), "box half_extents");
  expect_error(body(box(Vec3(1, nan, 1)), 1, 0), "box half_extents");
  expect_error(body(round_shape(ShapeType::Capsule, 0.1, -0.2), 1, 0), "capsule half_length");
  expect_error(body(round_shape(ShapeType::Capsule, inf, 0.2), 1, 0), "capsule radius");
  expect_error(body(round_shape(ShapeType::Cylinder, 0.1, 0), 1, 0), "cylinder half_length");
  expect_error(body(round_shape(ShapeType::Cylinder, -0.1, 1), 1, 0), "cylinder radius");

  expect_error(body(convex({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}), 1, 0), "at least 4 vertices");
  expect_error(body(convex({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, nan)}), 1, 0),
               "vertex 3 must be finite");
  // Coplanar (a tilted plane, so not aligned with Bullet's grid), collinear, coincident.
  std::vector<Vec3> plane;
  const Mat3 R = Quat(Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized())).toRotationMatrix();
  for (int i = 0; i < 12; ++i) plane.push_back(R * Vec3(std::cos(i), std::sin(2.0 * i), 0) + Vec3(1, 2, 3));
  expect_error(body(convex(plane), 1, 0), "coplanar");
  std::vector<Vec3> line;
  for (int i = 0; i < 6; ++i) line.push_back(Vec3(1, 2, 3) * (0.1 * i));
  expect_error(body(convex(line), 1, 0), "coplanar or collinear");
  expect_error(body(convex(std::vector<Vec3>(5, Vec3(1, 1, 1))), 1, 0), "at least 1e-06 m across");

  expect_error(body(sphere(1), 0, 0), "positive mass or a positive density");
  expect_error(body(sphere(1), -2, 0), "mass");
  expect_error(body(sphere(1), nan, 0), "mass");
  expect_error(body(sphere(1), 0, -5), "density");
  expect_error(body(sphere(1), 0, inf), "density");
}

// Finite but beyond what double-precision dynamics carries (issue #26: these ended in an internal
// error or a silently wrong run): sizes, masses, and masses that a density makes.
TEST(MassProperties, OutOfRangeSizesAndMassesThrowNamingThem) {
  expect_error(body(sphere(1e200), 1, 0), "sphere radius must lie in [1e-06, 10000] m (got 1e+200)");
  expect_error(body(sphere(1e-7), 1, 0), "sphere radius must lie in");
  expect_error(body(box(Vec3(1, 1e5, 1)), 1, 0), "box half_extents must lie in");
  expect_error(body(convex({Vec3(0, 0, 0), Vec3(1e5, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)}), 1, 0),
               "convex vertex 1 must be finite and within 10000 m");
  expect_error(body(sphere(1), 1e308, 0), "mass 1e+308 kg is outside [1e-09, 1e+12] kg");
  expect_error(body(sphere(1), 1e-308, 0), "mass 1e-308 kg is outside");
  expect_error(body(sphere(1), 0, 1e308), "(from its density) is outside");
  expect_error(body(sphere(1), 0, 1e-308), "(from its density) is outside");
  // A static body has no mass in the dynamics: only its shape is checked.
  BodyDef floor = body(box(Vec3(5e3, 5e3, 1)), 0, 1e-308);
  floor.is_static = true;
  EXPECT_EQ(error_of(floor), "");
}

}  // namespace
}  // namespace rbpart
