#pragma once
// Collision stage: contact points between the bodies' shapes. This header hides Bullet; the only
// file that includes Bullet is bullet_adapter.cpp.
#include <rbpart/scene.hpp>

#include <cstdint>
#include <memory>
#include <vector>

namespace rbpart {

struct Contact {
  int body_a = -1;        // scene body indices; a is always dynamic, b may be static
  int body_b = -1;
  Vec3 point;             // world, midway between the two surfaces
  Vec3 normal;            // world, unit, from body b into body a
  double distance = 0;    // signed: negative = penetration depth (m)
  std::uint64_t id = 0;   // persistent: the same physical contact keeps its id across steps
};

// Convex hull of a point set by Bullet's btConvexHullComputer; mass properties and the collider
// both use it, so they see the same polyhedron. Faces are polygons over indices into `points`,
// counter-clockwise seen from outside, in CSR form: face f is indices[offsets[f] .. offsets[f+1]).
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

class Collider {
 public:
  // Builds collision shapes for every body; pairs of static bodies and pairs joined by a joint
  // (unless the joint has collide_connected) never produce contacts. Contacts are reported up to
  // `margin` separation.
  Collider(const SceneDef& scene, double margin);
  ~Collider();
  Collider(const Collider&) = delete;
  Collider& operator=(const Collider&) = delete;

  // Runs broad + narrow phase for the given shape-frame poses (scene body order) and fills
  // `contacts` (cleared first), sorted deterministically by (body_a, body_b, id).
  void collide(const std::vector<Vec3>& frame_position, const std::vector<Quat>& frame_orientation,
               std::vector<Contact>& contacts);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rbpart
