#pragma once
// Convex hulls of point sets. The exact mass properties (scene/mass_properties.cpp), the collider's
// polyhedra (collision/shapes.cpp) and the recordings (io/recording.cpp) all take a convex shape's
// faces from here, so they see the same polyhedron; geometry needs neither scene nor collision.
#include <rbpart/scene.hpp>

#include <vector>

namespace rbpart {

// Convex hull of a point set by Bullet's btConvexHullComputer. Faces are polygons over indices into
// `points`, counter-clockwise seen from outside, in CSR form: face f is indices[offsets[f] .. offsets[f+1]).
// Bullet decides the hull on points rounded to 1/10216 of their bounding box; here its faces are
// re-formed from the given coordinates: triangles coplanar to round-off merge into one face (the
// 4-corner faces of a rotated box), the rest stay triangles. Fewer than 4 faces (or none) means
// the points are coplanar, collinear or coincident.
struct HullFaces {
  std::vector<int> offsets;  // faces + 1 entries (empty when there is no face)
  std::vector<int> indices;
  int size() const { return offsets.empty() ? 0 : static_cast<int>(offsets.size()) - 1; }
};
HullFaces convex_hull_faces(const std::vector<Vec3>& points);

}  // namespace rbpart
