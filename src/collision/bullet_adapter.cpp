// Collision stage (docs/design.md#step "collide") on Bullet's collision module in double precision.
// Besides geometry/hull.cpp (btConvexHullComputer), the only file that includes Bullet.
//
// The setup, and why:
// - Speculative margin (collide.hpp): a pair (a, b) reports contacts up to the separation
//   margin_ab = margin + sweep_a + sweep_b, where a body's sweep bounds how far its points move in
//   the step. Every test below that says "the margin" uses the pair's margin_ab.
// - Broad phase: btDbvtBroadphase inside a btCollisionWorld. AABBs are set here, each grown by half
//   the contact margin plus the body's own sweep, so the boxes of every pair closer than margin_ab
//   overlap. Static-static pairs are excluded by the filter masks and joined pairs by an overlap
//   filter: filtered pairs never become pairs.
// - Narrow phase: one collision algorithm of ours, registered with the dispatcher for every pair
//   of shape types. Bullet's convex algorithms report a separated pair with one point per call at
//   most (box-box none at all), and its collision margins and contact perturbation move the points
//   (a hull grows by 0.04 m by default), so they cannot give multi-point manifolds with true
//   distances up to the margin. Ours, per pair:
//   1. btGjkEpaSolver2 gives a normal and a closest pair: GJK on the shapes' cores, EPA on the
//      shapes when the cores overlap. Spheres and capsules are a point or segment core plus their
//      radius, which is exact. Margin-free polytopes in contact give GJK a zero vector to
//      normalise, so one shape of every other pair is rounded: a core shrunk by a rounding radius
//      (a twentieth of the contact margin), plus that radius. Touching shapes then have cores
//      apart, and resting contacts, which sink by about the solver's slop, never need EPA.
//   2. The closest pair is moved onto the exact shapes' support sets along the normal, so its
//      distance is the gap between their support planes, free of the rounding. Where both support
//      sets are vertices, edges or cores, the normal becomes the line between their closest points.
//   3. If a flat face (box or hull face, cylinder cap) is aligned with the normal, it is the
//      reference face, and the other shape's supporting feature (face, cap polygon, side line,
//      capsule segment) is clipped against the face's side planes (Sutherland-Hodgman). Every
//      clipped point within the margin is a contact at its exact distance from the face's plane.
//      When the pair moves further in the step than the contact margin, a face that is not
//      aligned gives its clipped points on or above its plane (a box landing on a corner: the
//      rest of the box), and so do the faces facing the relative motion. Otherwise (edge on
//      edge, round on round), or when it is deeper than all of those, the closest pair is a
//      contact.
//   4. Without a face, parallel support segments (capsules side by side, an edge along an edge)
//      give the two ends of their overlap instead.
//   5. Between two polytopes, every vertex of one within the margin of a face of the other (its
//      foot inside the face) is a contact too, in both directions (vertex_faces): a rock's faces
//      are small triangles, so steps 3-4 cover a few centimetres of it, and the vertices beside
//      them, which a tilting or turning rock brings down within the step, would go unguarded.
//   6. At most 8 points are kept (reduce): a footprint of four (when it includes higher points, also
//      the points in contact beside it), then the points that the bodies' motion drives in within
//      the step.
// - Persistence: each pair algorithm keeps its points (a btPersistentManifold holds four at most).
//   A new point within the pair's margin of one of its previous points (in either body's frame;
//   the sweeps bound how far a point moves on the other body, rolling moves it on both) takes over
//   that point's id; other points get fresh ids from the Collider's counter, assigned in
//   (body_a, body_b) order after sorting, so runs are deterministic.
#include "collision/collide.hpp"

#include <btBulletCollisionCommon.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkEpa2.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "core/error.hpp"
#include "geometry/hull.hpp"
#include "scene/mass_properties.hpp"

namespace rbpart {

namespace {

btVector3 to_bt(const Vec3& v) { return btVector3(v.x(), v.y(), v.z()); }
Vec3 to_eigen(const btVector3& v) { return Vec3(v.x(), v.y(), v.z()); }

// Rounding radius of polytopes and cylinders (see the file comment): a twentieth of the contact
// margin, so that resting contacts (which sink by about the solver's slop, well under a tenth of
// the margin) keep the cores apart and never need EPA; at most a twentieth of the shape's
// thickness; at least 1e-6 of its size, so that touching cores stay apart with no margin at all.
// It does not enter distances (support planes) or face contacts (clipping); a contact where a
// vertex or a cylinder rim meets an edge can sit up to about the radius off along the surface.
double rounding_radius(double margin, double thickness, double size) {
  return std::max(1e-6 * size, std::min(0.05 * margin, 0.05 * thickness));
}

// Support points this close (relative to the size) along a normal tie.
constexpr double kFlat = 1e-6;
// A flat face is the reference of a manifold when its normal is within ~0.8 degrees of the contact
// normal; GJK/EPA return a face normal to round-off for face contacts, an edge cross product or
// a direction between round parts otherwise.
constexpr double kFaceAlignment = 0.9999;
// Corners of the polygon that stands for a cylinder cap.
constexpr int kCapCorners = 8;
constexpr int kFootprint = 4;
constexpr int kMaxPoints = 8;

// A convex polyhedron in its shape frame: faces in CSR form, counter-clockwise seen from outside,
// with planes normal . x = offset. Bullet builds the hull on rounded points (geometry/hull.hpp);
// in about 2% of random rocks a face, often a sliver, then has a given point up to 1e-4 of the size
// above its plane, and a sliver's normal can be anything. Such faces still bound the volume but
// are never a contact's reference or incident face.
struct Polyhedron {
  std::vector<Vec3> vertices;
  std::vector<int> face_offsets, face_vertices;
  std::vector<Vec3> normals;
  std::vector<double> offsets;
  std::vector<int> supporting;  // faces with every point on or below their plane

  // The supporting face whose outward normal is most aligned with `dir` (shape frame).
  int support_face(const Vec3& dir) const {
    int best = supporting[0];
    double best_dot = -INFINITY;
    for (int f : supporting) {
      const double d = normals[f].dot(dir);
      if (d > best_dot) best_dot = d, best = f;
    }
    return best;
  }
};

Polyhedron make_polyhedron(const std::vector<Vec3>& points) {
  const HullFaces hull = convex_hull_faces(points);
  if (hull.size() < 4) throw InputError("convex vertices are coplanar or collinear (zero volume)");
  Vec3 lo = points[0], hi = points[0];
  for (const Vec3& x : points) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  const double tolerance = 1e-9 * (hi - lo).maxCoeff();
  Polyhedron p;
  std::vector<int> remap(points.size(), -1);
  p.face_offsets = hull.offsets;
  for (int idx : hull.indices) {
    if (remap[idx] < 0) {
      remap[idx] = static_cast<int>(p.vertices.size());
      p.vertices.push_back(points[idx]);
    }
    p.face_vertices.push_back(remap[idx]);
  }
  for (int f = 0; f < hull.size(); ++f) {
    const int begin = p.face_offsets[f], end = p.face_offsets[f + 1];
    const Vec3& v0 = p.vertices[p.face_vertices[begin]];
    Vec3 n = Vec3::Zero();
    for (int k = begin + 1; k + 1 < end; ++k)
      n += (p.vertices[p.face_vertices[k]] - v0).cross(p.vertices[p.face_vertices[k + 1]] - v0);
    n.normalize();
    double offset = -INFINITY;
    for (int k = begin; k < end; ++k) offset = std::max(offset, n.dot(p.vertices[p.face_vertices[k]]));
    p.normals.push_back(n);
    p.offsets.push_back(offset);
    double above = 0;
    for (const Vec3& x : points) above = std::max(above, n.dot(x) - offset);
    if (above <= tolerance) p.supporting.push_back(f);
  }
  if (p.supporting.empty()) throw InputError("convex vertices are coplanar or collinear (zero volume)");
  return p;
}

// A body's shape as the narrow phase sees it.
struct Geometry {
  ShapeType type = ShapeType::Sphere;
  double radius = 0, half_length = 0;  // sphere, capsule, cylinder
  double core_radius = 0;              // sphere, capsule: Bullet core (point, segment) to surface
  double rounding = 0;                 // box, cylinder, convex: radius of the rounded Bullet shape
  const btConvexShape* exact = nullptr;    // the shape itself (margin 0, or a core plus radius)
  const btConvexShape* rounded = nullptr;  // box, cylinder, convex: shrunk core plus `rounding`
  double size = 0;                     // characteristic length (m)
  int polyhedron = -1;                 // box, convex
};

// A contact point of a pair (A, B) = (manifold body 0, body 1), all in world coordinates.
struct PairPoint {
  Vec3 on_a, on_b;
  Vec3 normal;  // from B into A
  double distance;
  double predicted = 0;  // distance after the step at the bodies' current velocities (reduce)
};

// One shape's feature facing the other body: a polygon (counter-clockwise seen from outside, with
// outward normal), a segment, or a point; `radius` is the distance from it to the surface.
enum class FeatureKind { Point, Segment, Polygon };

// The points of an exact shape farthest along a direction: one point (a vertex, a cap or a rim
// point, a sphere), a segment (an edge, a side line) or a flat patch (a face, a cylinder cap).
struct SupportSet {
  enum Kind { Point, Segment, Flat } kind;
  Vec3 p0, p1;  // the point; the segment's ends; on a flat patch, a GJK/EPA witness moved onto it
};

// State shared by the pair algorithms of one Collider, and the per-call scratch they reuse.
struct NarrowPhase {
  double contact_margin = 0;  // a pair's own margin adds the two bodies' sweeps to it
  std::vector<Geometry> geometry;
  std::vector<Polyhedron> polyhedra;
  std::vector<Mat3> rotation;  // shape frame -> world, per body
  std::vector<Vec3> position;
  std::vector<Vec3> box_lo, box_hi;  // world AABB per body
  std::vector<double> sweep;         // per body: how far its points move in this step at most (m)
  // The step's motion: length, velocity of the centre of mass, angular velocity, centre of mass in
  // the shape frame.
  double h = 0;
  std::vector<Vec3> velocity, angular_velocity, com_local;

  std::vector<Vec3> reference, incident, scratch, patch;
  std::vector<PairPoint> candidates;

  double pair_margin(int a, int b) const { return contact_margin + sweep[a] + sweep[b]; }
  int pair_contacts(int a, int b, const btTransform& ta, const btTransform& tb, Vec3& axis, PairPoint* out);

 private:
  struct Face {
    bool cap = false;
    Vec3 normal = Vec3::Zero();  // world, outward
    double alignment = -2;       // normal . direction (-2: the shape has no flat face)
    int index = -1;              // polyhedron face, or the cap's side (+1 / -1 along the axis)
  };
  Vec3 support(int body, const Vec3& dir) const;
  PairPoint best_face_axis(int a, int b, const Vec3& previous) const;
  SupportSet support_set(int body, const Vec3& dir, const Vec3& near);
  bool feature(int body, const SupportSet& set, Vec3& f0, Vec3& f1) const;
  Face flat_face(int body, const Vec3& dir) const;
  void face_polygon(int body, const Face& face, std::vector<Vec3>& poly) const;
  FeatureKind incident_feature(int body, const Vec3& m, const Vec3& facing, double& radius);
  double generate(int a, int b, const btTransform& ta, const btTransform& tb, double margin, Vec3& axis);
  void add_candidate(const PairPoint& p, double tolerance);
  void clip_face(int a, int b, const Vec3& dir, bool contact_normal, bool speculative, double margin, double tolerance);
  void vertex_faces(int a, int b, const Vec3& n, double plane_a, double plane_b, double margin, double tolerance);
  Vec3 point_velocity(int body, const Vec3& p) const;
};

// The point of the exact shape (not the rounded core) farthest along the world direction `dir`.
Vec3 NarrowPhase::support(int body, const Vec3& dir) const {
  const Geometry& g = geometry[body];
  const Mat3& R = rotation[body];
  const Vec3 d = R.transpose() * dir;
  Vec3 local = Vec3::Zero();
  switch (g.type) {
    case ShapeType::Sphere:
      local = g.radius * d;
      break;
    case ShapeType::Capsule:
      local = Vec3(0, 0, d.z() >= 0 ? g.half_length : -g.half_length) + g.radius * d;
      break;
    case ShapeType::Cylinder: {
      local = Vec3(0, 0, d.z() >= 0 ? g.half_length : -g.half_length);
      const double across = std::hypot(d.x(), d.y());
      if (across > 0) local += Vec3(d.x(), d.y(), 0) * (g.radius / across);
      break;
    }
    case ShapeType::Box:
    case ShapeType::Convex: {
      const Polyhedron& p = polyhedra[g.polyhedron];
      double best = -INFINITY;
      for (const Vec3& v : p.vertices)
        if (v.dot(d) > best) best = v.dot(d), local = v;
      break;
    }
  }
  return position[body] + R * local;
}

// The point of convex polygon `poly` (counter-clockwise about its normal m) nearest to p, a point
// in its plane.
Vec3 into_polygon(const std::vector<Vec3>& poly, const Vec3& m, const Vec3& p) {
  const int k = static_cast<int>(poly.size());
  bool inside = true;
  for (int e = 0; e < k && inside; ++e) inside = m.cross(poly[(e + 1) % k] - poly[e]).dot(p - poly[e]) >= 0;
  if (inside) return p;
  Vec3 best = poly[0];
  for (int e = 0; e < k; ++e) {
    const Vec3 edge = poly[(e + 1) % k] - poly[e];
    const double t = std::clamp(edge.dot(p - poly[e]) / edge.squaredNorm(), 0.0, 1.0);
    const Vec3 q = poly[e] + t * edge;
    if ((q - p).squaredNorm() < (best - p).squaredNorm()) best = q;
  }
  return best;
}

// A support set as a segment f0-f1 (a point when f0 = f1) that stays put as the normal turns: a
// sphere's or capsule's core, a polytope's vertex or edge; false otherwise (a face, or any part of a
// cylinder, whose rim point and side line turn with the normal).
bool NarrowPhase::feature(int body, const SupportSet& set, Vec3& f0, Vec3& f1) const {
  const Geometry& g = geometry[body];
  if (g.type == ShapeType::Cylinder) return false;
  if (g.type == ShapeType::Sphere || g.type == ShapeType::Capsule) {
    const Vec3 half = g.half_length * rotation[body].col(2);
    f0 = position[body] - half;
    f1 = position[body] + half;
    return true;
  }
  if (set.kind == SupportSet::Flat) return false;
  f0 = set.p0;
  f1 = set.kind == SupportSet::Point ? set.p0 : set.p1;
  return true;
}

// Of the flat faces' normals, the previous normal and the centre line, the axis that separates the
// pair most (overlaps it least), with the support points along it: stands in when GJK and EPA
// fail, and checks EPA next to a cylinder.
PairPoint NarrowPhase::best_face_axis(int a, int b, const Vec3& previous) const {
  PairPoint best;
  best.distance = -INFINITY;
  auto consider = [&](const Vec3& n) {  // n from B towards A
    const Vec3 pa = support(a, -n), pb = support(b, n);
    const double gap = n.dot(pa - pb);
    if (gap > best.distance) best = {pa, pb, n, gap};
  };
  auto faces_of = [&](int body, double sign) {
    const Geometry& g = geometry[body];
    if (g.polyhedron >= 0)
      for (int f : polyhedra[g.polyhedron].supporting) consider(sign * (rotation[body] * polyhedra[g.polyhedron].normals[f]));
    if (g.type == ShapeType::Cylinder)
      for (double side : {-1.0, 1.0}) consider(side * rotation[body].col(2));
  };
  faces_of(a, -1);
  faces_of(b, 1);
  if (previous.squaredNorm() > 0) consider(previous);
  consider(position[a] != position[b] ? Vec3((position[a] - position[b]).normalized()) : Vec3::UnitZ());
  return best;
}

// The support set of `body` along the world direction `dir`. Points within kFlat of the size of
// the farthest count as farthest: the normal is not known better, and a lone support point would
// jump between the ends of an edge or a side line as the normal turns. `near` is a GJK/EPA
// witness, used on a flat patch (EPA's witnesses on round parts lie on chords inside the surface).
SupportSet NarrowPhase::support_set(int body, const Vec3& dir, const Vec3& near) {
  const Geometry& g = geometry[body];
  const Vec3& x = position[body];
  const Mat3& R = rotation[body];
  const Vec3 axis = R.col(2);
  const double along = axis.dot(dir), flat = kFlat * g.size;
  auto on_plane = [&](const Vec3& p) { return SupportSet{SupportSet::Flat, near + dir.dot(p - near) * dir, {}}; };
  switch (g.type) {
    case ShapeType::Sphere:
      return {SupportSet::Point, support(body, dir), {}};
    case ShapeType::Capsule:
    case ShapeType::Cylinder: {
      if (2 * g.half_length * std::abs(along) <= flat) {  // a side line
        const Vec3 side = x + g.radius * (dir - along * axis).normalized();
        return {SupportSet::Segment, side + g.half_length * axis, side - g.half_length * axis};
      }
      if (g.type == ShapeType::Cylinder && 2 * g.radius * std::sqrt(std::max(0.0, 1 - along * along)) <= flat) {
        // The cap: the witness moved onto it, within the rim.
        const Vec3 centre = x + (along > 0 ? g.half_length : -g.half_length) * axis;
        Vec3 across = near - centre - axis.dot(near - centre) * axis;
        if (across.norm() > g.radius) across *= g.radius / across.norm();
        return {SupportSet::Flat, centre + across, {}};
      }
      return {SupportSet::Point, support(body, dir), {}};
    }
    case ShapeType::Box:
    case ShapeType::Convex: {
      const Polyhedron& p = polyhedra[g.polyhedron];
      const Vec3 d = R.transpose() * dir;
      double top = -INFINITY;
      for (const Vec3& v : p.vertices) top = std::max(top, v.dot(d));
      int count = 0;
      Vec3 ends[2];
      for (const Vec3& v : p.vertices)
        if (v.dot(d) >= top - flat && count++ < 2) ends[count - 1] = x + R * v;
      if (count == 1) return {SupportSet::Point, ends[0], {}};
      if (count == 2) return {SupportSet::Segment, ends[0], ends[1]};
      // A face: the witness moved onto it, and into its polygon (a rounded core's witness can lie
      // up to the rounding radius beyond the sharp face's edge).
      Face face;
      face.index = p.support_face(d);
      face_polygon(body, face, patch);
      SupportSet set = on_plane(ends[0]);
      for (const Vec3& v : patch)
        if (dir.dot(v - ends[0]) < -flat) return set;  // not that face: leave the witness
      set.p0 = into_polygon(patch, R * p.normals[face.index], set.p0);
      return set;
    }
  }
  return on_plane(near);
}

// The flat face of `body` whose outward normal is most aligned with the world direction `dir`.
NarrowPhase::Face NarrowPhase::flat_face(int body, const Vec3& dir) const {
  const Geometry& g = geometry[body];
  const Mat3& R = rotation[body];
  Face face;
  if (g.polyhedron >= 0) {
    const Polyhedron& p = polyhedra[g.polyhedron];
    face.index = p.support_face(R.transpose() * dir);
    face.normal = R * p.normals[face.index];
  } else if (g.type == ShapeType::Cylinder) {
    const Vec3 axis = R.col(2);
    face.index = axis.dot(dir) >= 0 ? 1 : -1;
    face.normal = face.index * axis;
    face.cap = true;
  } else {
    return face;
  }
  face.alignment = face.normal.dot(dir);
  return face;
}

// The polygon of a flat face, world coordinates, counter-clockwise seen from outside.
void NarrowPhase::face_polygon(int body, const Face& face, std::vector<Vec3>& poly) const {
  const Geometry& g = geometry[body];
  const Mat3& R = rotation[body];
  const Vec3& x = position[body];
  poly.clear();
  if (!face.cap) {
    const Polyhedron& p = polyhedra[g.polyhedron];
    for (int k = p.face_offsets[face.index]; k < p.face_offsets[face.index + 1]; ++k)
      poly.push_back(x + R * p.vertices[p.face_vertices[k]]);
    return;
  }
  // A cap's corners run counter-clockwise about its outward normal (+z: increasing angle).
  constexpr double kStep = 2 * 3.14159265358979323846 / kCapCorners;
  for (int k = 0; k < kCapCorners; ++k) {
    const double angle = face.index * k * kStep;
    poly.push_back(x + R * Vec3(g.radius * std::cos(angle), g.radius * std::sin(angle), face.index * g.half_length));
  }
}

// The feature of `body` that faces a reference face with outward normal m (world), in `incident`:
// the face, or the cylinder's cap or side, turned against `facing` (m, or for a face not aligned
// with the contact the direction from the reference body towards `body`); a cylinder's side line
// and a capsule's core lie lowest towards m.
FeatureKind NarrowPhase::incident_feature(int body, const Vec3& m, const Vec3& facing, double& radius) {
  const Geometry& g = geometry[body];
  const Mat3& R = rotation[body];
  const Vec3& x = position[body];
  const Vec3 axis = R.col(2);
  incident.clear();
  radius = 0;
  switch (g.type) {
    case ShapeType::Sphere:
      return FeatureKind::Point;
    case ShapeType::Capsule:
      radius = g.radius;
      incident.push_back(x + g.half_length * axis);
      incident.push_back(x - g.half_length * axis);
      return FeatureKind::Segment;
    case ShapeType::Cylinder: {
      const double turned = axis.dot(facing), along = axis.dot(m);
      const Vec3 across = along * axis - m;
      // Jolt's rule: the cap when the axis is within 45 degrees of the normal, else the side line
      // (unless the face lies square to the axis, with no lowest line on the side).
      const bool cap_turned = std::abs(turned) >= std::sqrt(0.5);
      if (cap_turned || across.norm() < 1e-9) {
        Face cap;
        cap.cap = true;
        cap.index = (cap_turned ? turned : along) > 0 ? -1 : 1;
        face_polygon(body, cap, incident);
        return FeatureKind::Polygon;
      }
      const Vec3 side = across.normalized();
      incident.push_back(x + g.radius * side + g.half_length * axis);
      incident.push_back(x + g.radius * side - g.half_length * axis);
      return FeatureKind::Segment;
    }
    case ShapeType::Box:
    case ShapeType::Convex: {
      Face face;
      face.index = polyhedra[g.polyhedron].support_face(-(R.transpose() * facing));
      face_polygon(body, face, incident);
      return FeatureKind::Polygon;
    }
  }
  return FeatureKind::Point;
}

void NarrowPhase::add_candidate(const PairPoint& p, double tolerance) {
  for (const PairPoint& c : candidates)
    if ((c.on_a - p.on_a).squaredNorm() <= tolerance * tolerance) return;
  candidates.push_back(p);
}

double deepest_distance(const std::vector<PairPoint>& points) {
  double d = INFINITY;
  for (const PairPoint& p : points) d = std::min(d, p.distance);
  return d;
}

// Keeps the part of `poly` inside the side planes of the reference polygon `ref` (outward normal m).
void clip_polygon(const std::vector<Vec3>& ref, const Vec3& m, std::vector<Vec3>& poly, std::vector<Vec3>& tmp) {
  const int k = static_cast<int>(ref.size());
  for (int e = 0; e < k && !poly.empty(); ++e) {
    const Vec3& r0 = ref[e];
    const Vec3 inward = m.cross(ref[(e + 1) % k] - r0);
    tmp.clear();
    const int n = static_cast<int>(poly.size());
    for (int i = 0; i < n; ++i) {
      const Vec3& p = poly[i];
      const Vec3& q = poly[(i + 1) % n];
      const double dp = inward.dot(p - r0), dq = inward.dot(q - r0);
      if (dp >= 0) tmp.push_back(p);
      if ((dp >= 0) != (dq >= 0)) tmp.push_back(p + (dp / (dp - dq)) * (q - p));
    }
    poly.swap(tmp);
  }
}

// Clips the segment seg[0]-seg[1] to the side planes of `ref`; false if nothing is left.
bool clip_segment(const std::vector<Vec3>& ref, const Vec3& m, std::vector<Vec3>& seg) {
  const int k = static_cast<int>(ref.size());
  const Vec3 p0 = seg[0], d = seg[1] - seg[0];
  double t0 = 0, t1 = 1;
  for (int e = 0; e < k; ++e) {
    const Vec3 inward = m.cross(ref[(e + 1) % k] - ref[e]);
    const double f0 = inward.dot(p0 - ref[e]), fd = inward.dot(d);
    if (fd == 0) {
      if (f0 < 0) return false;
    } else if (fd > 0) {
      t0 = std::max(t0, -f0 / fd);
    } else {
      t1 = std::min(t1, -f0 / fd);
    }
    if (t0 > t1) return false;
  }
  seg[0] = p0 + t0 * d;
  seg[1] = p0 + t1 * d;
  if (t0 == t1) seg.pop_back();
  return true;
}

// Keeps at most kMaxPoints of `pts` (normal n, `size` the smaller body's, `allowance` the depth
// below which differences do not count):
// - A point with one deeper by more than the allowance near it across n (similar normal) is
//   dropped: within a tenth of `size`, or so far below it that only a turn by more than about 30
//   degrees could bring it down as deep. A rock's vertices lie at different heights.
// - A footprint of at most four: the deepest point, the farthest from it, the one spanning the
//   largest triangle with those two, and the one adding the most area to that triangle (lengths
//   across n, each less twice the point's height above the deepest). Drawn from the points as deep
//   as the deepest if they span a triangle (a rock resting on the three vertices of a small face
//   needs all three), else from all. A footprint bounds a flat patch; a pair at rest needs no more.
// - When the footprint was drawn from all points, the points in contact (distance <= 0) beside it
//   (over none of its triangles): a turn about its edge drives them further in at once, and its
//   higher points do not hold them. A rock rocking on the floor between two corners (two points as
//   deep as the deepest) kept a footprint point 8 mm up; the other corner, 0.6 mm in, was dropped
//   for a step, sank 2 mm, and the stabilisation's push out kept the rock rocking for good.
// - The points that the step's motion would drive in by more than the allowance (predicted
//   distance), most threatened first: a turning or tumbling rock brings down vertices that no
//   footprint bounds.
// - A point over a triangle of kept points but below their plane by more than the allowance: to
//   first order a rigid motion takes the points over a triangle no further in than its corners
//   only if they lie on or above the corners' plane.
int reduce(std::vector<PairPoint>& pts, const Vec3& n, double size, double allowance) {
  const int count = static_cast<int>(pts.size());
  if (count <= kFootprint) return count;
  auto across = [&](int i) {
    const Vec3 m = 0.5 * (pts[i].on_a + pts[i].on_b);
    return Vec3(m - n.dot(m) * n);
  };
  auto near = [&](int i, int k) {  // k holds i's spot
    const double apart = (across(i) - across(k)).norm();
    return apart < std::max(0.1 * size, 2 * (pts[i].distance - pts[k].distance)) &&
           pts[i].normal.dot(pts[k].normal) > 0.9;
  };
  std::vector<int> low;  // the points with no deeper neighbour
  for (int i = 0; i < count; ++i) {
    bool covered = false;
    for (int k = 0; k < count && !covered; ++k)
      covered = pts[k].distance < pts[i].distance - allowance && near(i, k);
    if (!covered) low.push_back(i);
  }
  std::vector<int> pick = {low[0]};
  for (int i : low)
    if (pts[i].distance < pts[pick[0]].distance) pick[0] = i;
  // The footprint's points: those as deep as the deepest (up to the allowance) if they span a
  // plane, else all. A rock resting on the three vertices of a small face needs all three, which
  // a footprint spread over higher points could miss.
  std::vector<int> level;
  for (int i : low)
    if (pts[i].distance <= pts[pick[0]].distance + allowance) level.push_back(i);
  const bool spread = level.size() < 3;  // the footprint is drawn from all points
  if (spread) level = low;
  const Vec3 p0 = across(pick[0]);
  auto height = [&](int i) { return 2 * (pts[i].distance - pts[pick[0]].distance); };
  int far = pick[0];
  double best = -INFINITY;
  for (int i : level) {
    const double d = (across(i) - p0).norm() - height(i);
    if (d > best) best = d, far = i;
  }
  const Vec3 p1 = across(far);
  const double span = std::max((p1 - p0).norm(), 1e-12 * size);
  int wide = pick[0];
  best = -INFINITY;
  for (int i : level) {
    const double a = std::abs((p1 - p0).cross(across(i) - p0).dot(n)) / span - height(i);
    if (a > best) best = a, wide = i;
  }
  const Vec3 p2 = across(wide);
  const double orientation = (p1 - p0).cross(p2 - p0).dot(n) >= 0 ? 1 : -1;
  const Vec3 tri[3] = {p0, p1, p2};
  int fourth = -1;
  best = 0;
  for (int i : level) {
    const Vec3 p = across(i);
    for (int e = 0; e < 3; ++e) {
      const Vec3 edge = tri[(e + 1) % 3] - tri[e];
      const double length = edge.norm();
      if (length == 0) continue;
      const double outside = -orientation * edge.cross(p - tri[e]).dot(n) / length - height(i);
      if (outside > best) best = outside, fourth = i;
    }
  }
  for (int i : {far, wide, fourth})
    if (i >= 0 && std::find(pick.begin(), pick.end(), i) == pick.end()) pick.push_back(i);
  // How far point i lies below the plane of a kept triangle over it, the least over such
  // triangles (-inf over none): a rigid motion takes the points over a triangle no further in than
  // its corners (to first order) if they lie on or above the corners' plane.
  auto below = [&](int i) {
    const Vec3 p = across(i);
    double least = -INFINITY;
    for (std::size_t x = 0; x < pick.size(); ++x)
      for (std::size_t y = x + 1; y < pick.size(); ++y)
        for (std::size_t z = y + 1; z < pick.size(); ++z) {
          const Vec3 c0 = across(pick[x]), c1 = across(pick[y]), c2 = across(pick[z]);
          const double area = (c1 - c0).cross(c2 - c0).dot(n);
          if (std::abs(area) <= 1e-12 * size * size) continue;
          const double u = (c1 - p).cross(c2 - p).dot(n) / area, v = (c2 - p).cross(c0 - p).dot(n) / area;
          if (u < -1e-9 || v < -1e-9 || u + v > 1 + 1e-9) continue;
          const double plane =
              u * pts[pick[x]].distance + v * pts[pick[y]].distance + (1 - u - v) * pts[pick[z]].distance;
          least = least == -INFINITY ? plane - pts[i].distance : std::min(least, plane - pts[i].distance);
        }
    return least;
  };
  auto add_unless_held = [&](int i) {
    bool held = below(i) > -INFINITY && below(i) <= allowance;
    for (int k : pick) held = held || k == i || near(i, k);
    if (!held) pick.push_back(i);
  };
  for (int i : low)
    if (spread && static_cast<int>(pick.size()) < kMaxPoints && pts[i].distance <= 0 && below(i) == -INFINITY &&
        std::find(pick.begin(), pick.end(), i) == pick.end())
      pick.push_back(i);
  std::vector<int> order(count);
  for (int i = 0; i < count; ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](int x, int y) { return pts[x].predicted < pts[y].predicted; });
  for (int i : order) {
    if (static_cast<int>(pick.size()) == kMaxPoints || !(pts[i].predicted < -allowance)) break;
    add_unless_held(i);
  }
  while (static_cast<int>(pick.size()) < kMaxPoints) {
    int worst = -1;
    double deepest = allowance;
    for (int i : low) {
      if (std::find(pick.begin(), pick.end(), i) != pick.end()) continue;
      const double b = below(i);
      if (b > deepest) deepest = b, worst = i;
    }
    if (worst < 0) break;
    pick.push_back(worst);
  }
  std::vector<PairPoint> chosen;
  for (int k : pick) chosen.push_back(pts[k]);
  pts.assign(chosen.begin(), chosen.end());
  return static_cast<int>(pts.size());
}

// Parameters (s, t) in [0, 1] of the closest points of segments p0-p1 and q0-q1 (Ericson,
// Real-Time Collision Detection, 5.1.9).
void closest_on_segments(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1, double& s, double& t) {
  const Vec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  if (a <= 0 && e <= 0) {
    s = t = 0;
    return;
  }
  if (a <= 0) {
    s = 0;
    t = std::clamp(f / e, 0.0, 1.0);
    return;
  }
  const double c = d1.dot(r);
  if (e <= 0) {
    t = 0;
    s = std::clamp(-c / a, 0.0, 1.0);
    return;
  }
  const double b = d1.dot(d2), denom = a * e - b * b;
  s = denom > 0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
  t = (b * s + f) / e;
  if (t < 0) {
    t = 0;
    s = std::clamp(-c / a, 0.0, 1.0);
  } else if (t > 1) {
    t = 1;
    s = std::clamp((b - c) / a, 0.0, 1.0);
  }
}

// Where across the normal n two support sets meet: at a lone point, where two segments pass
// closest (seen along n), at the segment's point nearest a flat patch's witness, else midway.
Vec3 meeting_point(const SupportSet& a, const SupportSet& b, const Vec3& n) {
  if (a.kind == SupportSet::Point) return a.p0;
  if (b.kind == SupportSet::Point) return b.p0;
  auto flatten = [&](const Vec3& p) { return Vec3(p - n.dot(p) * n); };
  double s = 0, t = 0;
  if (a.kind == SupportSet::Segment && b.kind == SupportSet::Segment) {
    closest_on_segments(flatten(a.p0), flatten(a.p1), flatten(b.p0), flatten(b.p1), s, t);
    return 0.5 * (a.p0 + s * (a.p1 - a.p0) + b.p0 + t * (b.p1 - b.p0));
  }
  if (a.kind == SupportSet::Segment) {
    closest_on_segments(flatten(a.p0), flatten(a.p1), flatten(b.p0), flatten(b.p0), s, t);
    return a.p0 + s * (a.p1 - a.p0);
  }
  if (b.kind == SupportSet::Segment) {
    closest_on_segments(flatten(b.p0), flatten(b.p1), flatten(a.p0), flatten(a.p0), s, t);
    return b.p0 + s * (b.p1 - b.p0);
  }
  return 0.5 * (a.p0 + b.p0);
}

// Reference face for the direction `dir` (from B into A): the flat face of A facing against it or
// of B facing along it, whichever is better aligned (cylinder caps are polygons inscribed in the
// disc, so a polyhedron face wins a tie). The incident feature of the other body is clipped against
// the face's side planes and every clipped point within `margin` of the face plane is a candidate,
// at its distance s from the plane. A point on or above the plane is exact: its foot on the face is
// its closest point on the convex reference body. Below the plane, s is the point's depth only if
// the face is aligned with the contact normal `dir`, so such points are kept only then. A face
// that is not aligned with `dir` serves only if `speculative`.
void NarrowPhase::clip_face(int a, int b, const Vec3& dir, bool contact_normal, bool speculative, double margin,
                            double tolerance) {
  const Face fa = flat_face(a, -dir), fb = flat_face(b, dir);
  const double ca = fa.alignment - (fa.cap ? 1e-9 : 0), cb = fb.alignment - (fb.cap ? 1e-9 : 0);
  const bool aligned = std::max(ca, cb) >= kFaceAlignment;
  if (!(aligned || (speculative && std::max(ca, cb) > 0))) return;
  const bool below = contact_normal && aligned;
  const bool ref_is_a = ca >= cb;
  const int ref = ref_is_a ? a : b, inc = ref_is_a ? b : a;
  const Face& face = ref_is_a ? fa : fb;
  const Vec3& m = face.normal;  // outward from the reference body, towards the incident one
  face_polygon(ref, face, reference);
  const double plane = m.dot(reference[0]);
  auto add = [&](const Vec3& q) {  // q on the incident surface
    const double s = m.dot(q) - plane;
    if (!(s <= margin) || (s < 0 && !below)) return;
    const Vec3 foot = q - s * m;
    add_candidate(ref_is_a ? PairPoint{foot, q, -m, s} : PairPoint{q, foot, m, s}, tolerance);
  };
  double radius = 0;
  const FeatureKind kind = incident_feature(inc, m, aligned ? m : Vec3(ref_is_a ? -dir : dir), radius);
  if (kind == FeatureKind::Polygon) {
    clip_polygon(reference, m, incident, scratch);
    for (const Vec3& q : incident) add(q);
  } else if (kind == FeatureKind::Segment && clip_segment(reference, m, incident)) {
    if (radius == 0) {  // a cylinder's side line, on its surface
      for (const Vec3& q : incident) add(q);
      return;
    }
    // A capsule's core, clipped. Below a core point c, along -m (so over the same spot of the
    // face), its surface is r / cos(tilt) away on its side where the core goes on towards the face
    // for r tan(tilt) beyond c, else on the sphere about the core's end nearest the face.
    const Geometry& g = geometry[inc];
    const Vec3 axis = rotation[inc].col(2);
    const double along = m.dot(axis), cos_tilt = std::sqrt(std::max(0.0, 1 - along * along));
    const Vec3 low_end = position[inc] - (along >= 0 ? g.half_length : -g.half_length) * axis;
    for (const Vec3& c : incident) {
      const Vec3 w = c - low_end;
      const double mw = m.dot(w);
      const double t = w.norm() * cos_tilt >= radius * std::abs(along)
                           ? radius / cos_tilt
                           : mw + std::sqrt(std::max(0.0, mw * mw - w.squaredNorm() + radius * radius));
      add(c - t * m);
    }
  }
}

// Every vertex of one polytope within `margin` of the other, in both directions, at its exact
// distance: over a face, the foot on the face's plane is the vertex's closest point on the other
// body, which lies wholly behind that plane; beside an edge or a corner, the closest point of the
// face polygon, certified so; inside the other body, the nearest face plane gives its depth. n is the pair's normal
// (from B into A) and plane_a, plane_b its support planes along it: a vertex further than `margin`
// beyond the other body's support plane is out of reach.
void NarrowPhase::vertex_faces(int a, int b, const Vec3& n, double plane_a, double plane_b, double margin,
                               double tolerance) {
  for (int side = 0; side < 2; ++side) {
    const int from = side == 0 ? a : b, to = side == 0 ? b : a;
    const Polyhedron& pv = polyhedra[geometry[from].polyhedron];
    const Polyhedron& pf = polyhedra[geometry[to].polyhedron];
    const Mat3& Rf = rotation[from];
    const Mat3& Rt = rotation[to];
    const Vec3 towards = side == 0 ? n : Vec3(-n);  // out of `to`, towards `from`
    const double reach = side == 0 ? plane_b + margin : -plane_a + margin;
    const Vec3 facing = Rt.transpose() * towards;
    for (const Vec3& v : pv.vertices) {
      const Vec3 p = position[from] + Rf * v;
      if (towards.dot(p) > reach) continue;
      // The face whose plane the vertex lies furthest beyond; of faces within a twentieth of the
      // contact margin of that (a vertex on an edge: cubes stacked corner on corner, sagging by the
      // slop) the one facing the other body most, if the vertex lies over it. Its distance then
      // errs by that much at most, on the side of caution.
      const Vec3 local = Rt.transpose() * (p - position[to]);
      int deepest_face = -1;
      double top = -INFINITY;
      for (int f : pf.supporting) {
        const double d = pf.normals[f].dot(local) - pf.offsets[f];
        if (d > top) top = d, deepest_face = f;
      }
      if (!(top <= margin)) continue;
      int face = -1;
      double s = top, alignment = -INFINITY;
      for (int f : pf.supporting) {
        const double d = pf.normals[f].dot(local) - pf.offsets[f], al = pf.normals[f].dot(facing);
        if (d >= top - 0.05 * contact_margin && al > alignment) s = d, face = f, alignment = al;
      }
      auto inside = [&](int f, const Vec3& foot) {
        for (int k = pf.face_offsets[f], end = pf.face_offsets[f + 1]; k < end; ++k) {
          const Vec3& e0 = pf.vertices[pf.face_vertices[k]];
          const Vec3& e1 = pf.vertices[pf.face_vertices[k + 1 < end ? k + 1 : pf.face_offsets[f]]];
          if (pf.normals[f].cross(e1 - e0).dot(foot - e0) < -tolerance) return false;
        }
        return true;
      };
      Vec3 m, on_face;
      if (inside(face, local - s * pf.normals[face])) {
        m = Rt * pf.normals[face];
        on_face = p - s * m;
      } else if (top < 0) {
        // Inside the other body: the nearest face plane gives the depth, and the foot on it lies
        // on that face.
        s = top;
        m = Rt * pf.normals[deepest_face];
        on_face = p - s * m;
      } else {
        // Beside an edge or a corner (the foot falls outside the face): the closest point of the
        // face's polygon, provided the other body lies wholly behind the plane through it normal
        // to the line from it to the vertex (then it is the body's closest point).
        Face nearest;
        nearest.index = deepest_face;
        face_polygon(to, nearest, patch);
        const Vec3 world_normal = Rt * pf.normals[deepest_face];
        on_face = into_polygon(patch, world_normal, p - top * world_normal);
        s = (p - on_face).norm();
        if (!(s <= margin) || s == 0) continue;
        m = (p - on_face) / s;
        bool behind = true;
        for (const Vec3& w : pf.vertices) behind = behind && m.dot(position[to] + Rt * w - on_face) <= tolerance;
        if (!behind) continue;
      }
      if (!(m.dot(towards) > 0)) continue;
      add_candidate(side == 0 ? PairPoint{p, on_face, m, s} : PairPoint{on_face, p, Vec3(-m), s}, tolerance);
    }
  }
}

// World velocity of the material point of `body` at p.
Vec3 NarrowPhase::point_velocity(int body, const Vec3& p) const {
  return velocity[body] + angular_velocity[body].cross(p - position[body] - rotation[body] * com_local[body]);
}

// Fills `candidates` with the pair's contact points up to the separation `margin` and returns the
// pair's distance (+inf beyond the margin). `axis` is the pair's normal of the previous call (zero
// at first), updated here.
double NarrowPhase::generate(int a, int b, const btTransform& ta, const btTransform& tb, double margin, Vec3& axis) {
  candidates.clear();
  // The broad phase pairs boxes grown by its own margin (Bullet's gDbvtMargin, 5 cm): pairs whose
  // boxes are further apart than the margin stop here, and so do pairs that the previous normal
  // still separates by more than the margin (any axis bounds the distance from below).
  if (((box_lo[a] - box_hi[b]).array() > margin).any() || ((box_lo[b] - box_hi[a]).array() > margin).any())
    return INFINITY;
  if (axis.squaredNorm() > 0 && axis.dot(support(a, -axis) - support(b, axis)) > margin) return INFINITY;
  const Geometry& ga = geometry[a];
  const Geometry& gb = geometry[b];
  // One rounded shape per pair keeps touching cores apart: none next to a sphere or capsule (their
  // cores are a point or a segment), else B's, or A's when only A is a polytope (a cylinder's rim
  // stays exact).
  const bool round_pair = !ga.rounded || !gb.rounded;
  const bool round_a = !round_pair && ga.polyhedron >= 0 && gb.polyhedron < 0;
  const bool round_b = !round_pair && !round_a;
  const btConvexShape* sa = round_a ? ga.rounded : ga.exact;
  const btConvexShape* sb = round_b ? gb.rounded : gb.exact;
  const double ra = round_a ? ga.rounding : ga.core_radius, rb = round_b ? gb.rounding : gb.core_radius;
  const double scale = ga.size + gb.size;

  // 1. Normal and closest pair by GJK on the cores (separated) or EPA on the shapes (cores overlap).
  //    Each result is checked against the gap between the Bullet shapes' support planes along its
  //    normal, a lower bound that equals the distance (or minus the depth) at the solution:
  //    btGjkEpaSolver2's GJK can stop short of the minimum (it ends when a support point repeats
  //    one of its last four) and then restarts from its normal; EPA can give up on a thin overlap
  //    (it then returns its guess as the normal, at depth 0) and then the best axis among the
  //    faces' normals stands in. btGjkEpaSolver2 works in A's frame: the guess is A - B there,
  //    the normal comes back in it.
  btVector3 guess = (axis.squaredNorm() > 0 ? to_bt(axis) : ta.getOrigin() - tb.getOrigin()) * ta.getBasis();
  if (guess.length2() == 0) guess.setValue(0, 0, 1);
  auto rounded_support = [](const btConvexShape* shape, const btTransform& t, const btVector3& world_dir) {
    const btVector3 d = world_dir * t.getBasis();
    return t * (shape->localGetSupportingVertexWithoutMargin(d) + d * shape->getMargin());
  };
  auto plane_gap = [&](const btVector3& local_n) {  // separation of the Bullet shapes along n
    const btVector3 nw = ta.getBasis() * local_n;
    return nw.dot(rounded_support(sa, ta, -nw) - rounded_support(sb, tb, nw));
  };
  const double tolerance = 1e-9 * scale;
  btGjkEpaSolver2::sResults r;
  PairPoint closest;
  bool have_pair = false, converged = false;
  for (int attempt = 0; attempt < 4 && !converged; ++attempt) {
    if (!btGjkEpaSolver2::Distance(sa, ta, sb, tb, guess, r) || !(r.distance > tolerance)) break;
    const double d = r.distance - ra - rb;
    converged = d - plane_gap(r.normal) <= tolerance;
    guess = r.normal * r.distance;
    const Vec3 n = to_eigen(ta.getBasis() * r.normal);
    closest = {to_eigen(r.witnesses[0]) - ra * n, to_eigen(r.witnesses[1]) + rb * n, n, d};
    have_pair = true;
  }
  if (!converged) {
    // EPA's normal on a cylinder's round side is a polytope's approximation: a face's normal
    // that overlaps the pair less is the better axis. On polytopes EPA is exact.
    const bool epa = btGjkEpaSolver2::Penetration(sa, ta, sb, tb, guess, r, true) &&
                     std::abs(r.distance - plane_gap(r.normal)) <= 1e-6 * scale;
    const PairPoint from_epa = {to_eigen(r.witnesses[0]), to_eigen(r.witnesses[1]),
                                to_eigen(ta.getBasis() * r.normal), r.distance};
    if (epa && ga.type != ShapeType::Cylinder && gb.type != ShapeType::Cylinder) {
      closest = from_epa;
    } else {
      // GJK stopped short: its distance is an upper bound, its normal possibly far off. Axes are
      // compared by the gap between the exact shapes' support planes, a lower bound that is the
      // distance on the true axis (a box resting 4e-7 m from another's face, GJK stopped at
      // 1 cm along a wrong axis: its planes overlapped by 0.22 m, which became a contact's depth).
      const PairPoint face = best_face_axis(a, b, axis);
      const double gjk_gap =
          have_pair ? closest.normal.dot(support(a, -closest.normal) - support(b, closest.normal)) : -INFINITY;
      if (epa && r.distance >= face.distance - tolerance)
        closest = from_epa;
      else if (face.distance > gjk_gap)
        closest = face;
    }
  }
  axis = closest.normal;
  // A rounded shape lies within a few rounding radii inside the exact one.
  if (converged && closest.distance > margin + 4 * (ga.rounding + gb.rounding)) return INFINITY;

  // 2. The closest pair moves onto the exact shapes' support sets along the normal, so its distance
  //    is the gap between their support planes: exact for the true normal, which the cores share
  //    with the shapes (an edge cross product, a direction between round parts), and free of the
  //    rounding. Across the normal it lies at a lone support point, else where two support
  //    segments pass closest, else at the witnesses.
  Vec3 n = closest.normal;
  SupportSet sa_set = support_set(a, -n, closest.on_a), sb_set = support_set(b, n, closest.on_b);
  // The normal of separated shapes is the line between their closest points. GJK measured one
  // shape rounded: where both support sets are fixed points or segments (vertices, edges, the core
  // of a sphere or capsule), the line between their closest points is the sharp shapes' normal,
  // provided the same features support along it.
  Vec3 fa0, fa1, fb0, fb1;
  if (feature(a, sa_set, fa0, fa1) && feature(b, sb_set, fb0, fb1)) {
    double s = 0, t = 0;
    closest_on_segments(fa0, fa1, fb0, fb1, s, t);
    const Vec3 u = fa0 + s * (fa1 - fa0) - (fb0 + t * (fb1 - fb0));
    if (u.dot(n) > 0) {
      const Vec3 refined = u.normalized();
      const SupportSet along_a = support_set(a, -refined, closest.on_a);
      const SupportSet along_b = support_set(b, refined, closest.on_b);
      Vec3 ga0, ga1, gb0, gb1;
      if (feature(a, along_a, ga0, ga1) && feature(b, along_b, gb0, gb1) && ga0 == fa0 && ga1 == fa1 &&
          gb0 == fb0 && gb1 == fb1) {
        n = refined;
        sa_set = along_a;
        sb_set = along_b;
      }
    }
  }
  closest.normal = axis = n;
  const double plane_a = n.dot(sa_set.p0), plane_b = n.dot(sb_set.p0);
  closest.distance = plane_a - plane_b;
  if (!(closest.distance <= margin)) return INFINITY;
  const Vec3 across = meeting_point(sa_set, sb_set, n);
  closest.on_a = across + (plane_a - n.dot(across)) * n;
  closest.on_b = across + (plane_b - n.dot(across)) * n;

  // 3. Reference face along the normal (clip_face): a face aligned with it gives the face-on-face
  //    and edge-on-face points. When the pair's bodies move further within the step than the
  //    contact margin (their sweeps exceed it), its margin reaches parts that the motion brings
  //    together, and more faces serve: a face along the normal that is not aligned with it (a box
  //    landing on a corner: the rest of the box, which a tilted or tumbling body brings down
  //    within the step; held by its corner only, it would swing through), and the faces facing
  //    the relative motion (a box falling past the edge of a tilted box lands with its bottom
  //    face, which is not the face along the closest pair's normal). Pairs at rest keep the
  //    aligned faces only, so piles get no extra rows.
  const bool fast = margin - contact_margin > contact_margin;
  clip_face(a, b, n, true, fast, margin, tolerance);
  if (fast) {
    const Vec3 meet = 0.5 * (closest.on_a + closest.on_b);
    const Vec3 approach = point_velocity(b, meet) - point_velocity(a, meet);  // B towards A
    if (approach.squaredNorm() > 0) clip_face(a, b, approach.normalized(), false, true, margin, tolerance);
  }
  // 4. Without a reference face, parallel support segments (capsules side by side, an edge along
  //    an edge, a cylinder's side line on either) touch along their overlap: its two ends are the
  //    contacts, so the pair is held, or speculatively stopped, along the line and not at one end
  //    only (which would turn it about that end and let it slide past). The segments lie opposite
  //    each other along the normal (step 2 made it the line between them), each on its support
  //    plane, so both points are at the closest pair's distance.
  if (candidates.empty() && sa_set.kind == SupportSet::Segment && sb_set.kind == SupportSet::Segment) {
    const Vec3 da = sa_set.p1 - sa_set.p0, db = sb_set.p1 - sb_set.p0;
    const double la = da.norm(), lb = db.norm();
    if (la > 0 && lb > 0 && da.cross(db).norm() <= kFlat * la * lb) {
      const Vec3 u = da / la;
      const double b0 = u.dot(sb_set.p0 - sa_set.p0), b1 = u.dot(sb_set.p1 - sa_set.p0);
      const double lo = std::max(0.0, std::min(b0, b1)), hi = std::min(la, std::max(b0, b1));
      if (hi - lo > kFlat * scale)
        for (double t : {lo, hi}) {
          const Vec3 on_a = sa_set.p0 + t * u;
          const Vec3 on_b = sb_set.p0 + u.dot(on_a - sb_set.p0) * u;
          candidates.push_back({on_a, on_b, n, n.dot(on_a - on_b)});
        }
    }
  }
  if (ga.polyhedron >= 0 && gb.polyhedron >= 0) vertex_faces(a, b, n, plane_a, plane_b, margin, tolerance);
  // 5. The closest pair alone (edge on edge, round on round, nothing over the face), or with the
  //    other points when it is deeper than all of them (a tilted rim between the corners of its cap
  //    polygon, a part beside the face). The allowance is the normal's error times the extent of
  //    the support sets.
  if (closest.distance < deepest_distance(candidates) - 1e-7 * scale) candidates.push_back(closest);
  return closest.distance;
}

// The pair's contacts (at most kMaxPoints) up to its margin into `out`; `axis` as in generate().
int NarrowPhase::pair_contacts(int a, int b, const btTransform& ta, const btTransform& tb, Vec3& axis,
                               PairPoint* out) {
  if (!(generate(a, b, ta, tb, pair_margin(a, b), axis) < INFINITY)) return 0;
  for (PairPoint& p : candidates)
    p.predicted = p.distance + h * p.normal.dot(point_velocity(a, p.on_a) - point_velocity(b, p.on_b));
  // A resting pair sinks by about the solver's slop per step, well within the rounding allowance.
  const int count = reduce(candidates, axis, std::min(geometry[a].size, geometry[b].size), 0.05 * contact_margin);
  std::copy(candidates.begin(), candidates.begin() + count, out);
  return count;
}

// The dispatcher keeps the narrow phase for its algorithms.
class Dispatcher : public btCollisionDispatcher {
 public:
  Dispatcher(btCollisionConfiguration* config, NarrowPhase* narrow)
      : btCollisionDispatcher(config), narrow_(narrow) {}
  NarrowPhase& narrow() { return *narrow_; }

 private:
  NarrowPhase* narrow_;
};

// A pair's contact point as the pair keeps it between calls: the point, where it lies on each body
// (shape frame), and its persistent id (0: none yet).
struct PairContact {
  PairPoint point;
  Vec3 local_a, local_b;
  std::uint64_t id = 0;
};

// The pair algorithm: generates the pair's points and carries ids over from its previous points.
class PairAlgorithm : public btCollisionAlgorithm {
 public:
  PairAlgorithm(const btCollisionAlgorithmConstructionInfo& ci, const btCollisionObjectWrapper* w0,
                const btCollisionObjectWrapper* w1)
      : btCollisionAlgorithm(ci), a_(w0->getCollisionObject()), b_(w1->getCollisionObject()) {}

  void processCollision(const btCollisionObjectWrapper*, const btCollisionObjectWrapper*, const btDispatcherInfo&,
                        btManifoldResult*) override {
    NarrowPhase& narrow = static_cast<Dispatcher*>(m_dispatcher)->narrow();
    const int a = body_a(), b = body_b();
    PairPoint pts[kMaxPoints];
    const int count = narrow.pair_contacts(a, b, a_->getWorldTransform(), b_->getWorldTransform(), axis_, pts);
    update(narrow, a, b, narrow.pair_margin(a, b), pts, count);
  }

  btScalar calculateTimeOfImpact(btCollisionObject*, btCollisionObject*, const btDispatcherInfo&,
                                 btManifoldResult*) override {
    return 1;
  }
  void getAllContactManifolds(btManifoldArray&) override {}

  int body_a() const { return a_->getUserIndex(); }
  int body_b() const { return b_->getUserIndex(); }
  int count() const { return count_; }
  PairContact& contact(int i) { return contacts_[i]; }

  struct CreateFunc : btCollisionAlgorithmCreateFunc {
    btCollisionAlgorithm* CreateCollisionAlgorithm(btCollisionAlgorithmConstructionInfo& ci,
                                                   const btCollisionObjectWrapper* w0,
                                                   const btCollisionObjectWrapper* w1) override {
      void* memory = ci.m_dispatcher1->allocateCollisionAlgorithm(sizeof(PairAlgorithm));
      return new (memory) PairAlgorithm(ci, w0, w1);
    }
  };

 private:
  // Replaces the pair's points by the new ones; a new point takes the id of the closest previous
  // point within the pair's margin (distance of the anchors in A's frame or in B's, whichever is
  // smaller), each previous point going to one new point at most, closest pairs first.
  void update(const NarrowPhase& narrow, int a, int b, double margin, const PairPoint* pts, int count) {
    const Mat3& Ra = narrow.rotation[a];
    const Mat3& Rb = narrow.rotation[b];
    PairContact next[kMaxPoints];
    for (int i = 0; i < count; ++i) {
      next[i].point = pts[i];
      next[i].local_a = Ra.transpose() * (pts[i].on_a - narrow.position[a]);
      next[i].local_b = Rb.transpose() * (pts[i].on_b - narrow.position[b]);
    }
    bool taken_new[kMaxPoints] = {}, taken_old[kMaxPoints] = {};
    const double radius2 = margin * margin;
    for (int round = 0; round < std::min(count, count_); ++round) {
      int bi = -1, bj = -1;
      double best = radius2;
      for (int i = 0; i < count; ++i) {
        if (taken_new[i]) continue;
        for (int j = 0; j < count_; ++j) {
          if (taken_old[j]) continue;
          const double d = std::min((contacts_[j].local_a - next[i].local_a).squaredNorm(),
                                    (contacts_[j].local_b - next[i].local_b).squaredNorm());
          if (d <= best) best = d, bi = i, bj = j;
        }
      }
      if (bi < 0) break;
      taken_new[bi] = taken_old[bj] = true;
      next[bi].id = contacts_[bj].id;
    }
    std::copy(next, next + count, contacts_);
    count_ = count;
  }

  const btCollisionObject* a_;
  const btCollisionObject* b_;
  PairContact contacts_[kMaxPoints];
  int count_ = 0;
  Vec3 axis_ = Vec3::Zero();  // the pair's last normal: warm start and separation test
};

// Broad-phase filter: Bullet's group/mask test (static-static pairs) and the joined pairs.
struct PairFilter : btOverlapFilterCallback {
  std::vector<std::uint64_t> excluded;  // sorted keys of joined pairs without collide_connected

  static std::uint64_t key(int i, int j) {
    return (static_cast<std::uint64_t>(std::min(i, j)) << 32) | static_cast<std::uint32_t>(std::max(i, j));
  }
  bool needBroadphaseCollision(btBroadphaseProxy* p0, btBroadphaseProxy* p1) const override {
    if (!(p0->m_collisionFilterGroup & p1->m_collisionFilterMask) ||
        !(p1->m_collisionFilterGroup & p0->m_collisionFilterMask))
      return false;
    const int i = static_cast<const btCollisionObject*>(p0->m_clientObject)->getUserIndex();
    const int j = static_cast<const btCollisionObject*>(p1->m_clientObject)->getUserIndex();
    return !std::binary_search(excluded.begin(), excluded.end(), key(i, j));
  }
};

// The exact Bullet shape of `shape` into shapes[0], and for boxes, cylinders and hulls a rounded
// one into shapes[1]; `g` is filled in (its pointers too).
void make_bullet_shapes(const Shape& shape, double margin, Geometry& g, std::vector<Polyhedron>& polyhedra,
                        std::unique_ptr<btConvexShape> (&shapes)[2]) {
  g.type = shape.type;
  switch (shape.type) {
    case ShapeType::Sphere:
      g.radius = g.core_radius = g.size = shape.radius;
      shapes[0] = std::make_unique<btSphereShape>(shape.radius);
      break;
    case ShapeType::Capsule:
      g.radius = g.core_radius = shape.radius;
      g.half_length = shape.half_length;
      g.size = shape.radius + shape.half_length;
      shapes[0] = std::make_unique<btCapsuleShapeZ>(shape.radius, 2 * shape.half_length);
      break;
    case ShapeType::Cylinder: {
      g.radius = shape.radius;
      g.half_length = shape.half_length;
      g.size = std::hypot(shape.radius, shape.half_length);
      g.rounding = rounding_radius(margin, std::min(shape.radius, shape.half_length), g.size);
      const btVector3 half(shape.radius, shape.radius, shape.half_length);
      shapes[0] = std::make_unique<btCylinderShapeZ>(half);
      shapes[1] = std::make_unique<btCylinderShapeZ>(half);
      break;
    }
    case ShapeType::Box: {
      const Vec3& h = shape.half_extents;
      std::vector<Vec3> corners;
      for (int i = 0; i < 8; ++i) corners.emplace_back(i & 1 ? h.x() : -h.x(), i & 2 ? h.y() : -h.y(), i & 4 ? h.z() : -h.z());
      g.polyhedron = static_cast<int>(polyhedra.size());
      polyhedra.push_back(make_polyhedron(corners));
      g.size = h.norm();
      g.rounding = rounding_radius(margin, h.minCoeff(), g.size);
      shapes[0] = std::make_unique<btBoxShape>(to_bt(h));
      shapes[1] = std::make_unique<btBoxShape>(to_bt(h));
      break;
    }
    case ShapeType::Convex: {
      g.polyhedron = static_cast<int>(polyhedra.size());
      polyhedra.push_back(make_polyhedron(shape.vertices));
      const Polyhedron& p = polyhedra.back();
      Vec3 c = Vec3::Zero();
      for (const Vec3& v : p.vertices) c += v;
      c /= static_cast<double>(p.vertices.size());
      double inner = INFINITY, outer = 0;
      for (int f : p.supporting) inner = std::min(inner, p.offsets[f] - p.normals[f].dot(c));
      for (const Vec3& v : p.vertices) outer = std::max(outer, (v - c).norm());
      g.size = outer;
      g.rounding = rounding_radius(margin, inner, outer);
      // The rounded core: the hull scaled about c so that every face moves in by at least the
      // rounding radius.
      const double shrink = 1 - g.rounding / inner;
      auto exact = std::make_unique<btConvexHullShape>();
      auto core = std::make_unique<btConvexHullShape>();
      for (const Vec3& v : p.vertices) {
        exact->addPoint(to_bt(v), false);
        core->addPoint(to_bt(c + shrink * (v - c)), false);
      }
      exact->recalcLocalAabb();
      core->recalcLocalAabb();
      shapes[0] = std::move(exact);
      shapes[1] = std::move(core);
      break;
    }
  }
  // Boxes and cylinders keep their outer size when the margin changes: their core shrinks.
  if (shapes[1]) {
    shapes[0]->setMargin(0);
    shapes[1]->setMargin(g.rounding);
  }
  g.exact = shapes[0].get();
  g.rounded = shapes[1].get();
}

constexpr std::uint64_t kFresh = std::uint64_t{1} << 63;  // marks a point that has no id yet

}  // namespace

struct Collider::Impl {
  NarrowPhase narrow;
  std::vector<char> is_static;
  std::vector<std::unique_ptr<btConvexShape>> shapes;  // per body: exact, rounded (or none)
  std::vector<std::unique_ptr<btCollisionObject>> objects;
  std::vector<double> reach;  // per dynamic body: farthest point of the shape from the centre of mass
  std::vector<Vec3> last_position;
  std::vector<Quat> last_orientation;
  std::vector<double> last_sweep;
  bool posed = false;
  PairFilter filter;
  PairAlgorithm::CreateFunc create_pair;
  std::unique_ptr<btDefaultCollisionConfiguration> config;
  std::unique_ptr<Dispatcher> dispatcher;
  std::unique_ptr<btDbvtBroadphase> broadphase;
  std::unique_ptr<btCollisionWorld> world;  // destroyed first: it releases pairs and manifolds
  std::vector<PairContact*> fresh;           // points awaiting an id in the current call
  std::uint64_t last_id = 0;
};

Collider::Collider(const SceneDef& scene, double margin) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  if (!std::isfinite(margin) || margin < 0)
    throw InputError("contact margin must be finite and non-negative (got " + std::to_string(margin) + ")");
  const int n = static_cast<int>(scene.bodies.size());
  NarrowPhase& narrow = m.narrow;
  narrow.contact_margin = margin;
  narrow.geometry.resize(n);
  narrow.rotation.assign(n, Mat3::Identity());
  narrow.position.assign(n, Vec3::Zero());
  narrow.box_lo.assign(n, Vec3::Zero());
  narrow.box_hi.assign(n, Vec3::Zero());
  narrow.sweep.assign(n, 0.0);
  narrow.velocity.assign(n, Vec3::Zero());
  narrow.angular_velocity.assign(n, Vec3::Zero());
  narrow.com_local.assign(n, Vec3::Zero());

  btDefaultCollisionConstructionInfo info;
  info.m_customCollisionAlgorithmMaxElementSize = static_cast<int>(sizeof(PairAlgorithm));
  // A pool for the pairs of a dense pile (about 20 broad-phase pairs per body); beyond, Bullet
  // allocates. The pair algorithms keep their points themselves: no manifolds.
  info.m_defaultMaxCollisionAlgorithmPoolSize = std::max(4096, 16 * n);
  info.m_defaultMaxPersistentManifoldPoolSize = 1;
  m.config = std::make_unique<btDefaultCollisionConfiguration>(info);
  m.dispatcher = std::make_unique<Dispatcher>(m.config.get(), &narrow);
  for (int t0 : {SPHERE_SHAPE_PROXYTYPE, BOX_SHAPE_PROXYTYPE, CAPSULE_SHAPE_PROXYTYPE, CYLINDER_SHAPE_PROXYTYPE,
                 CONVEX_HULL_SHAPE_PROXYTYPE})
    for (int t1 : {SPHERE_SHAPE_PROXYTYPE, BOX_SHAPE_PROXYTYPE, CAPSULE_SHAPE_PROXYTYPE, CYLINDER_SHAPE_PROXYTYPE,
                   CONVEX_HULL_SHAPE_PROXYTYPE})
      m.dispatcher->registerCollisionCreateFunc(t0, t1, &m.create_pair);
  m.broadphase = std::make_unique<btDbvtBroadphase>();
  m.world = std::make_unique<btCollisionWorld>(m.dispatcher.get(), m.broadphase.get(), m.config.get());

  for (const JointDef& j : scene.joints) {
    if (j.body_a < 0 || j.body_a >= n || j.body_b < -1 || j.body_b >= n)
      throw InputError("joint between bodies " + std::to_string(j.body_a) + " and " + std::to_string(j.body_b) +
                       ": no such body");
    if (!j.collide_connected && j.body_b >= 0) m.filter.excluded.push_back(PairFilter::key(j.body_a, j.body_b));
  }
  std::sort(m.filter.excluded.begin(), m.filter.excluded.end());
  m.world->getPairCache()->setOverlapFilterCallback(&m.filter);

  m.is_static.resize(n);
  m.reach.assign(n, 0.0);
  for (int i = 0; i < n; ++i) {
    const BodyDef& body = scene.bodies[i];
    m.is_static[i] = body.is_static;
    std::unique_ptr<btConvexShape> pair[2];
    const Geometry& g = narrow.geometry[i];
    try {
      make_bullet_shapes(body.shape, margin, narrow.geometry[i], narrow.polyhedra, pair);
      if (!body.is_static) {
        // The centre of mass that World's velocities refer to (the same function fixes it there).
        const Vec3 com = narrow.com_local[i] = unit_density_properties(body.shape).com;
        if (g.polyhedron >= 0) {
          for (const Vec3& v : narrow.polyhedra[g.polyhedron].vertices) m.reach[i] = std::max(m.reach[i], (v - com).norm());
        } else {  // sphere, capsule, cylinder: g.size is the farthest point from the frame origin
          m.reach[i] = com.norm() + g.size;
        }
      }
    } catch (const InputError& e) {
      throw InputError("body '" + body.name + "': " + e.what());
    }
    auto object = std::make_unique<btCollisionObject>();
    object->setCollisionShape(pair[0].get());
    for (auto& shape : pair)
      if (shape) m.shapes.push_back(std::move(shape));
    object->setUserIndex(i);
    if (body.is_static) object->setCollisionFlags(object->getCollisionFlags() | btCollisionObject::CF_STATIC_OBJECT);
    const int group = body.is_static ? btBroadphaseProxy::StaticFilter : btBroadphaseProxy::DefaultFilter;
    const int mask = body.is_static ? btBroadphaseProxy::AllFilter ^ btBroadphaseProxy::StaticFilter
                                    : btBroadphaseProxy::AllFilter;
    m.world->addCollisionObject(object.get(), group, mask);
    m.objects.push_back(std::move(object));
  }
  m.last_position.assign(n, Vec3::Zero());
  m.last_orientation.assign(n, Quat::Identity());
  m.last_sweep.assign(n, 0.0);
}

Collider::~Collider() = default;

double Collider::reach(int body) const { return impl_->reach[body]; }

void Collider::collide(const std::vector<Vec3>& frame_position, const std::vector<Quat>& frame_orientation,
                       const std::vector<Vec3>& velocity, const std::vector<Vec3>& angular_velocity, double h,
                       std::vector<Contact>& contacts) {
  Impl& m = *impl_;
  NarrowPhase& narrow = m.narrow;
  const int n = static_cast<int>(m.objects.size());
  if (static_cast<int>(frame_position.size()) != n || static_cast<int>(frame_orientation.size()) != n ||
      static_cast<int>(velocity.size()) != n || static_cast<int>(angular_velocity.size()) != n)
    throw std::invalid_argument("collide: expected " + std::to_string(n) + " poses and velocities");
  if (!std::isfinite(h) || h < 0) throw std::invalid_argument("collide: the step must be finite and non-negative");
  narrow.h = h;

  // Sweeps, poses and broad-phase boxes of the bodies that moved or changed speed. Each box grows
  // by half the contact margin and by its body's sweep, so two boxes overlap when their gap is
  // within the pair's margin.
  for (int i = 0; i < n; ++i) {
    const Vec3& x = frame_position[i];
    const Quat& q = frame_orientation[i];
    if (!x.allFinite() || !q.coeffs().allFinite() || q.squaredNorm() == 0)
      throw std::invalid_argument("collide: body " + std::to_string(i) + " has a non-finite pose");
    if (!velocity[i].allFinite() || !angular_velocity[i].allFinite())
      throw std::invalid_argument("collide: body " + std::to_string(i) + " has a non-finite velocity");
    const double sweep =
        m.is_static[i] ? 0.0
                       : std::min(h * (velocity[i].norm() + angular_velocity[i].norm() * m.reach[i]), kMaxSweep);
    narrow.sweep[i] = sweep;
    if (!m.is_static[i]) {
      narrow.velocity[i] = velocity[i];
      narrow.angular_velocity[i] = angular_velocity[i];
    }
    const bool moved = !m.posed || x != m.last_position[i] || q.coeffs() != m.last_orientation[i].coeffs();
    if (!moved && sweep == m.last_sweep[i]) continue;
    m.last_sweep[i] = sweep;
    btCollisionObject& object = *m.objects[i];
    if (moved) {
      m.last_position[i] = x;
      m.last_orientation[i] = q;
      const Mat3 R = q.normalized().toRotationMatrix();
      narrow.rotation[i] = R;
      narrow.position[i] = x;
      const btTransform t(btMatrix3x3(R(0, 0), R(0, 1), R(0, 2), R(1, 0), R(1, 1), R(1, 2), R(2, 0), R(2, 1), R(2, 2)),
                          to_bt(x));
      object.setWorldTransform(t);
      btVector3 lo, hi;
      object.getCollisionShape()->getAabb(t, lo, hi);
      narrow.box_lo[i] = to_eigen(lo);
      narrow.box_hi[i] = to_eigen(hi);
    }
    const double grow = 0.5 * narrow.contact_margin + sweep;
    const btVector3 g(grow, grow, grow);
    m.broadphase->setAabb(object.getBroadphaseHandle(), to_bt(narrow.box_lo[i]) - g, to_bt(narrow.box_hi[i]) + g,
                          m.dispatcher.get());
  }
  m.posed = true;

  m.world->computeOverlappingPairs();
  m.dispatcher->dispatchAllCollisionPairs(m.world->getPairCache(), m.world->getDispatchInfo(), m.dispatcher.get());

  // Contacts with body_a dynamic (the lower index when both are), normal from b into a.
  contacts.clear();
  m.fresh.clear();
  btBroadphasePairArray& pairs = m.world->getPairCache()->getOverlappingPairArray();
  for (int k = 0; k < pairs.size(); ++k) {
    if (!pairs[k].m_algorithm) continue;
    PairAlgorithm& pair = *static_cast<PairAlgorithm*>(pairs[k].m_algorithm);
    const int i0 = pair.body_a(), i1 = pair.body_b();
    const bool swap = m.is_static[i0] || (!m.is_static[i1] && i1 < i0);
    for (int p = 0; p < pair.count(); ++p) {
      PairContact& pc = pair.contact(p);
      Contact c;
      c.body_a = swap ? i1 : i0;
      c.body_b = swap ? i0 : i1;
      c.normal = swap ? Vec3(-pc.point.normal) : pc.point.normal;
      c.point = 0.5 * (pc.point.on_a + pc.point.on_b);
      c.distance = pc.point.distance;
      c.id = pc.id;
      if (c.id == 0) {
        c.id = kFresh | m.fresh.size();
        m.fresh.push_back(&pc);
      }
      contacts.push_back(c);
    }
  }
  std::sort(contacts.begin(), contacts.end(), [](const Contact& x, const Contact& y) {
    if (x.body_a != y.body_a) return x.body_a < y.body_a;
    if (x.body_b != y.body_b) return x.body_b < y.body_b;
    return x.id < y.id;
  });
  // Fresh ids in sorted order: they exceed every earlier id, so the order stays sorted.
  for (Contact& c : contacts) {
    if (!(c.id & kFresh)) continue;
    c.id = m.fresh[c.id & ~kFresh]->id = ++m.last_id;
  }
}

}  // namespace rbpart
