#pragma once
// The narrow phase: a pair's contact points, rbpart's own on top of GJK/EPA (docs/pipeline.md#collide).
//
// - Speculative margin (collide.hpp): a pair (a, b) reports contacts up to the separation
//   margin_ab = margin + sweep_a + sweep_b, where a body's sweep bounds how far its points move in
//   the step. Every test below that says "the margin" uses the pair's margin_ab.
// - Why our own: Bullet's convex algorithms report a separated pair with one point per call at most
//   (box-box none at all), and its collision margins and contact perturbation move the points (a
//   hull grows by 0.04 m by default), so they cannot give multi-point manifolds with true distances
//   up to the margin. Ours, per pair (generate, narrow_phase.cpp):
//   1. GJK/EPA gives a normal and a closest pair: GJK on the shapes' cores, EPA on the shapes when
//      the cores overlap (Bullet's btGjkEpaSolver2, the one part that Bullet does: GjkEpa below,
//      bullet_adapter.cpp). Spheres and capsules are a point or segment core plus their radius,
//      which is exact. Margin-free polytopes in contact give GJK a zero vector to normalise, so one
//      shape of every other pair is rounded: a core shrunk by a rounding radius (a twentieth of the
//      contact margin), plus that radius. Touching shapes then have cores apart, and resting
//      contacts, which sink by about the solver's slop, never need EPA.
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
//   6. At most 8 points are kept (reduce, manifold.hpp): a footprint of four (when it includes
//      higher points, also the points in contact beside it), then the points that the bodies'
//      motion drives in within the step.
// Steps 2-3 ask the shapes for support points and features (features.cpp); steps 3 and 5 make the
// points (clip.cpp).
#include "collision/manifold.hpp"
#include "collision/shapes.hpp"

#include <vector>

namespace rbpart::collision {

// Support points this close (relative to the size) along a normal tie.
constexpr double kFlat = 1e-6;
// A flat face is the reference of a manifold when its normal is within ~0.8 degrees of the contact
// normal; GJK/EPA return a face normal to round-off for face contacts, an edge cross product or
// a direction between round parts otherwise.
constexpr double kFaceAlignment = 0.9999;
// Corners of the polygon that stands for a cylinder cap.
constexpr int kCapCorners = 8;

// One shape's feature facing the other body: a polygon (counter-clockwise seen from outside, with
// outward normal), a segment, or a point; `radius` is the distance from it to the surface.
enum class FeatureKind { Point, Segment, Polygon };

// The points of an exact shape farthest along a direction: one point (a vertex, a cap or a rim
// point, a sphere), a segment (an edge, a side line) or a flat patch (a face, a cylinder cap).
struct SupportSet {
  enum Kind { Point, Segment, Flat } kind;
  Vec3 p0, p1;  // the point; the segment's ends; on a flat patch, a GJK/EPA witness moved onto it
};

// What GJK and EPA give for a pair (step 1), on the exact surfaces: GJK's closest pair, repeated
// until its distance is the gap between the shapes' support planes along its normal (converged);
// if it does not converge, EPA's pair and depth, valid when they match that gap too.
struct GjkEpaResult {
  PairPoint gjk;
  bool have_gjk = false, converged = false;
  PairPoint epa;
  bool epa_valid = false;
};

// GJK/EPA as the narrow phase asks for it: bodies a and b, `axis` the pair's previous normal (zero at
// first). The Collider answers it with Bullet (bullet_adapter.cpp).
class GjkEpa {
 public:
  virtual GjkEpaResult closest_pair(int a, int b, const Vec3& axis) const = 0;

 protected:
  ~GjkEpa() = default;
};

// The point of convex polygon `poly` (counter-clockwise about its normal m) nearest to p, a point
// in its plane.
Vec3 into_polygon(const std::vector<Vec3>& poly, const Vec3& m, const Vec3& p);

// State shared by the pair algorithms of one Collider (read-only during the pairs' runs), and the
// per-call scratch they reuse.
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

  const GjkEpa* gjk_epa = nullptr;  // step 1

  // Per-call scratch, one set per thread: pairs run in parallel on one NarrowPhase, and each call
  // writes a buffer before it reads it.
  static thread_local std::vector<Vec3> reference, incident, scratch, patch;
  static thread_local std::vector<PairPoint> candidates;

  double pair_margin(int a, int b) const { return contact_margin + sweep[a] + sweep[b]; }
  // The pair's contacts (at most kMaxPoints) up to its margin into `out`, and their number. `axis` is
  // the pair's normal of the previous call (zero at first), updated here.
  int pair_contacts(int a, int b, Vec3& axis, PairPoint* out);

 private:
  struct Face {
    bool cap = false;
    Vec3 normal = Vec3::Zero();  // world, outward
    double alignment = -2;       // normal . direction (-2: the shape has no flat face)
    int index = -1;              // polyhedron face, or the cap's side (+1 / -1 along the axis)
  };
  // features.cpp: the posed shapes' support points, support sets and features.
  Vec3 support(int body, const Vec3& dir) const;
  PairPoint best_face_axis(int a, int b, const Vec3& previous) const;
  SupportSet support_set(int body, const Vec3& dir, const Vec3& near);
  bool feature(int body, const SupportSet& set, Vec3& f0, Vec3& f1) const;
  Face flat_face(int body, const Vec3& dir) const;
  void face_polygon(int body, const Face& face, std::vector<Vec3>& poly) const;
  FeatureKind incident_feature(int body, const Vec3& m, const Vec3& facing, double& radius);
  // clip.cpp: contact points from a reference face and from the vertices over faces.
  void add_candidate(const PairPoint& p, double tolerance);
  void clip_face(int a, int b, const Vec3& dir, bool contact_normal, bool speculative, double margin, double tolerance);
  void vertex_faces(int a, int b, const Vec3& n, double plane_a, double plane_b, double margin, double tolerance);
  // narrow_phase.cpp: the pair's steps 1-5.
  double generate(int a, int b, double margin, Vec3& axis);
  Vec3 point_velocity(int body, const Vec3& p) const;
};

}  // namespace rbpart::collision
