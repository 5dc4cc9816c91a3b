// The narrow phase's shapes (shapes.hpp): rounding radii, polyhedra from hulls, per-body geometry.
#include "collision/shapes.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "geometry/hull.hpp"

namespace rbpart::collision {

namespace {

// Rounding radius of polytopes and cylinders (narrow_phase.hpp, step 1): a twentieth of the contact
// margin, so that resting contacts (which sink by about the solver's slop, well under a tenth of
// the margin) keep the cores apart and never need EPA; at most a twentieth of the shape's
// thickness; at least 1e-6 of its size, so that touching cores stay apart with no margin at all.
// It does not enter distances (support planes) or face contacts (clipping); a contact where a
// vertex or a cylinder rim meets an edge can sit up to about the radius off along the surface.
double rounding_radius(double margin, double thickness, double size) {
  return std::max(1e-6 * size, std::min(0.05 * margin, 0.05 * thickness));
}

}  // namespace

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

Geometry make_geometry(const Shape& shape, double margin, std::vector<Polyhedron>& polyhedra,
                       std::vector<Vec3>& core) {
  Geometry g;
  g.type = shape.type;
  core.clear();
  switch (shape.type) {
    case ShapeType::Sphere:
      g.radius = g.core_radius = g.size = shape.radius;
      break;
    case ShapeType::Capsule:
      g.radius = g.core_radius = shape.radius;
      g.half_length = shape.half_length;
      g.size = shape.radius + shape.half_length;
      break;
    case ShapeType::Cylinder:
      g.radius = shape.radius;
      g.half_length = shape.half_length;
      g.size = std::hypot(shape.radius, shape.half_length);
      g.rounding = rounding_radius(margin, std::min(shape.radius, shape.half_length), g.size);
      break;
    case ShapeType::Box: {
      const Vec3& h = shape.half_extents;
      std::vector<Vec3> corners;
      for (int i = 0; i < 8; ++i) corners.emplace_back(i & 1 ? h.x() : -h.x(), i & 2 ? h.y() : -h.y(), i & 4 ? h.z() : -h.z());
      g.polyhedron = static_cast<int>(polyhedra.size());
      polyhedra.push_back(make_polyhedron(corners));
      g.size = h.norm();
      g.rounding = rounding_radius(margin, h.minCoeff(), g.size);
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
      const double shrink = 1 - g.rounding / inner;
      for (const Vec3& v : p.vertices) core.push_back(c + shrink * (v - c));
      break;
    }
  }
  return g;
}

}  // namespace rbpart::collision
