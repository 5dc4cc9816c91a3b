// Exact mass properties of the shapes (docs/design.md#dynamics: M = blockdiag(m I, I_body), about the centre
// of mass). Closed forms for the primitives; a convex hull by signed tetrahedra over its faces.
#include "scene/mass_properties.hpp"

#include <cmath>
#include <sstream>
#include <string>

#include "core/error.hpp"
#include "geometry/hull.hpp"
#include "scene/limits.hpp"

namespace rbpart {

namespace {

constexpr double kPi = 3.14159265358979323846;

[[noreturn]] void fail(const std::string& what) { throw InputError(what); }

std::string number(double x) {
  std::ostringstream s;
  s.precision(6);
  s << x;
  return s.str();
}

void require_size(double value, const char* what) {
  if (!std::isfinite(value) || value <= 0)
    fail(std::string(what) + " must be finite and positive (got " + number(value) + ")");
  if (value < limits::kMinLength || value > limits::kMaxLength)
    fail(std::string(what) + " must lie in [" + number(limits::kMinLength) + ", " + number(limits::kMaxLength) +
         "] m (got " + number(value) + ")");
}

// Inertia of a body with principal moments (ixx, iyy, izz) along the shape axes.
Mat3 diagonal(double ixx, double iyy, double izz) { return Vec3(ixx, iyy, izz).asDiagonal(); }

MassProperties sphere(double r) {
  require_size(r, "sphere radius");
  MassProperties p;
  p.volume = p.mass = 4.0 / 3.0 * kPi * r * r * r;
  const double i = 0.4 * p.volume * r * r;
  p.inertia = diagonal(i, i, i);
  return p;
}

MassProperties box(const Vec3& h) {
  for (int k = 0; k < 3; ++k) require_size(h[k], "box half_extents");
  MassProperties p;
  p.volume = p.mass = 8 * h.x() * h.y() * h.z();
  const Vec3 s = h.cwiseAbs2();
  p.inertia = diagonal(s.y() + s.z(), s.x() + s.z(), s.x() + s.y()) * (p.volume / 3);
  return p;
}

// Solid cylinder of radius r and length 2h along z: I_zz = m r^2/2, I_xx = m (r^2/4 + h^2/3).
MassProperties cylinder(double r, double h) {
  require_size(r, "cylinder radius");
  require_size(h, "cylinder half_length");
  MassProperties p;
  p.volume = p.mass = 2 * kPi * r * r * h;
  const double ixx = p.volume * (r * r / 4 + h * h / 3);
  p.inertia = diagonal(ixx, ixx, 0.5 * p.volume * r * r);
  return p;
}

// Cylinder of length 2h plus two hemispherical caps of radius r (together a sphere of volume Vs).
// A cap of mass M has I = 2/5 M r^2 about any diameter of its flat face and its centre of mass
// 3r/8 from that face, so about the capsule's centre (distance h + 3r/8 from the cap's centre of
// mass): I = 2/5 M r^2 - M (3r/8)^2 + M (h + 3r/8)^2 = M (2/5 r^2 + h^2 + 3/4 h r).
MassProperties capsule(double r, double h) {
  require_size(r, "capsule radius");
  require_size(h, "capsule half_length");
  const double vc = 2 * kPi * r * r * h, vs = 4.0 / 3.0 * kPi * r * r * r;
  MassProperties p;
  p.volume = p.mass = vc + vs;
  const double ixx = vc * (r * r / 4 + h * h / 3) + vs * (0.4 * r * r + h * h + 0.75 * h * r);
  const double izz = 0.5 * vc * r * r + 0.4 * vs * r * r;
  p.inertia = diagonal(ixx, ixx, izz);
  return p;
}

// The hull of the vertices, each face fanned into triangles and each triangle joined to an interior
// point o into a tetrahedron. With a, b, c relative to o and D = a.(b x c) (six times the signed
// volume), a tetrahedron contributes volume D/6, first moment D/24 (a+b+c) and second moment
// integral(x x^T) = D/120 (a a^T + b b^T + c c^T + s s^T), s = a+b+c; the sums are exact
// polyhedral integrals of the hull. Inertia about the centre of mass: I = tr(C) 1 - C with C the
// second moment about it.
MassProperties convex(const std::vector<Vec3>& vertices) {
  const int n = static_cast<int>(vertices.size());
  if (n < 4) fail("convex shape needs at least 4 vertices (got " + std::to_string(n) + ")");
  for (int i = 0; i < n; ++i)
    if (!vertices[i].allFinite() || vertices[i].cwiseAbs().maxCoeff() > limits::kMaxLength)
      fail("convex vertex " + std::to_string(i) + " must be finite and within " + number(limits::kMaxLength) +
           " m of the shape frame's origin");

  const HullFaces hull = convex_hull_faces(vertices);
  Vec3 lo = vertices[0], hi = vertices[0];
  for (const Vec3& v : vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  const double extent = (hi - lo).maxCoeff();
  if (extent < limits::kMinLength)
    fail("convex shape must be at least " + number(limits::kMinLength) + " m across (got " + number(extent) + ")");

  // Reference point inside the hull: a mean of its vertices (each counted once per face).
  Vec3 o = Vec3::Zero();
  for (int idx : hull.indices) o += vertices[idx];
  if (!hull.indices.empty()) o /= static_cast<double>(hull.indices.size());

  double d6 = 0;  // six times the volume
  Vec3 first = Vec3::Zero();
  Mat3 second = Mat3::Zero();
  for (int f = 0; f < hull.size(); ++f) {
    const int begin = hull.offsets[f], end = hull.offsets[f + 1];
    const Vec3 a = vertices[hull.indices[begin]] - o;
    for (int k = begin + 1; k + 1 < end; ++k) {
      const Vec3 b = vertices[hull.indices[k]] - o, c = vertices[hull.indices[k + 1]] - o;
      const double d = a.dot(b.cross(c));
      const Vec3 s = a + b + c;
      d6 += d;
      first += d * s;
      second += d * (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose());
    }
  }
  const double volume = d6 / 6;
  // A flat point set has a hull of zero volume (up to round-off relative to its size).
  if (hull.size() < 4 || !(volume > 1e-12 * extent * extent * extent))
    fail("convex vertices are coplanar or collinear (zero volume)");

  MassProperties p;
  p.volume = p.mass = volume;
  const Vec3 c = first / (24 * volume);  // centre of mass relative to o
  const Mat3 second_com = second / 120 - volume * c * c.transpose();
  p.com = o + c;
  p.inertia = second_com.trace() * Mat3::Identity() - second_com;
  p.inertia = 0.5 * (p.inertia + p.inertia.transpose());
  return p;
}

}  // namespace

MassProperties unit_density_properties(const Shape& shape) {
  switch (shape.type) {
    case ShapeType::Sphere: return sphere(shape.radius);
    case ShapeType::Box: return box(shape.half_extents);
    case ShapeType::Capsule: return capsule(shape.radius, shape.half_length);
    case ShapeType::Cylinder: return cylinder(shape.radius, shape.half_length);
    case ShapeType::Convex: return convex(shape.vertices);
  }
  fail("unknown shape type");
}

MassProperties mass_properties(const BodyDef& body) {
  const std::string who = "body '" + body.name + "': ";
  MassProperties p;
  try {
    p = unit_density_properties(body.shape);
  } catch (const InputError& e) {
    fail(who + e.what());
  }
  // 0 means "not given" for both.
  if (!std::isfinite(body.mass) || body.mass < 0)
    fail(who + "mass must be finite and positive (got " + number(body.mass) + ")");
  if (!std::isfinite(body.density) || body.density < 0)
    fail(who + "density must be finite and positive (got " + number(body.density) + ")");

  double mass = body.mass > 0 ? body.mass : body.density * p.volume;
  if (!(mass > 0)) {
    // A static body is only checked for a sound shape: it has no mass in the dynamics.
    if (!body.is_static) fail(who + "needs a positive mass or a positive density");
    mass = 0;
  }
  p.inertia *= mass / p.mass;
  p.mass = mass;
  if (!body.is_static) {
    if (!(mass >= limits::kMinMass && mass <= limits::kMaxMass))
      fail(who + "mass " + number(mass) + " kg" + (body.mass > 0 ? "" : " (from its density)") + " is outside [" +
           number(limits::kMinMass) + ", " + number(limits::kMaxMass) + "] kg");
    // The sizes and masses above keep the moments of inertia normal numbers; this is the backstop
    // for a hull whose points sit closer than its extent suggests.
    if (!(p.inertia.diagonal().minCoeff() > 0) || !p.inertia.inverse().allFinite())
      fail(who + "its inertia is not positive and finite (mass " + number(mass) + " kg)");
  }
  return p;
}

}  // namespace rbpart
