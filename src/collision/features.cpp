// The posed shapes as the narrow phase asks about them (narrow_phase.hpp, steps 1-3): support points
// and support sets along a direction, flat faces and their polygons, the feature facing a face.
#include "collision/narrow_phase.hpp"

#include <algorithm>
#include <cmath>

namespace rbpart::collision {

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

}  // namespace rbpart::collision
