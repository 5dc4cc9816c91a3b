// Contact points of a pair (narrow_phase.hpp, steps 3 and 5): the incident feature clipped against a
// reference face (Sutherland-Hodgman), and the vertices of one polytope over the faces of the other.
#include "collision/narrow_phase.hpp"

#include <algorithm>
#include <cmath>

namespace rbpart::collision {

namespace {

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

}  // namespace

void NarrowPhase::add_candidate(const PairPoint& p, double tolerance) {
  for (const PairPoint& c : candidates)
    if ((c.on_a - p.on_a).squaredNorm() <= tolerance * tolerance) return;
  candidates.push_back(p);
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

}  // namespace rbpart::collision
