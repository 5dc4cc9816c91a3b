#pragma once
// The bodies' shapes as the narrow phase sees them (narrow_phase.hpp): their sizes, the rounding
// radius that keeps GJK's cores apart, and boxes and hulls as polyhedra with face planes.
#include <rbpart/scene.hpp>

#include <vector>

namespace rbpart::collision {

// A convex polyhedron in its shape frame: faces in CSR form, counter-clockwise seen from outside,
// with planes normal . x = offset. Bullet builds the hull on rounded points (see convex_hull_faces);
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

// The polyhedron of the convex hull of `points` (geometry/hull.hpp). Throws InputError when they
// span no volume.
Polyhedron make_polyhedron(const std::vector<Vec3>& points);

// A body's shape as the narrow phase sees it.
struct Geometry {
  ShapeType type = ShapeType::Sphere;
  double radius = 0, half_length = 0;  // sphere, capsule, cylinder
  double core_radius = 0;              // sphere, capsule: Bullet core (point, segment) to surface
  double rounding = 0;                 // box, cylinder, convex: radius of the rounded Bullet shape
  double size = 0;                     // characteristic length (m)
  int polyhedron = -1;                 // box, convex
};

// The geometry of `shape` for the contact margin `margin`; a box's or hull's polyhedron is appended
// to `polyhedra`. For a hull, `core` receives the vertices of its rounded core, on which GJK runs
// (bullet_adapter.cpp): the hull scaled about the mean of its vertices so that every face moves in
// by at least the rounding radius. Throws InputError as make_polyhedron.
Geometry make_geometry(const Shape& shape, double margin, std::vector<Polyhedron>& polyhedra,
                       std::vector<Vec3>& core);

}  // namespace rbpart::collision
