// The narrow phase's steps for one pair (narrow_phase.hpp): GJK/EPA's closest pair, moved onto the
// exact shapes' support planes, then the contact points, reduced to the pair's manifold.
#include "collision/narrow_phase.hpp"

#include <algorithm>
#include <cmath>

namespace rbpart::collision {

thread_local std::vector<Vec3> NarrowPhase::reference, NarrowPhase::incident, NarrowPhase::scratch, NarrowPhase::patch;
thread_local std::vector<PairPoint> NarrowPhase::candidates;

namespace {

double deepest_distance(const std::vector<PairPoint>& points) {
  double d = INFINITY;
  for (const PairPoint& p : points) d = std::min(d, p.distance);
  return d;
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

}  // namespace

// World velocity of the material point of `body` at p.
Vec3 NarrowPhase::point_velocity(int body, const Vec3& p) const {
  return velocity[body] + angular_velocity[body].cross(p - position[body] - rotation[body] * com_local[body]);
}

// Fills `candidates` with the pair's contact points up to the separation `margin` and returns the
// pair's distance (+inf beyond the margin). `axis` is the pair's normal of the previous call (zero
// at first), updated here.
double NarrowPhase::generate(int a, int b, double margin, Vec3& axis) {
  candidates.clear();
  // The broad phase pairs boxes grown by its own margin (Bullet's gDbvtMargin, 5 cm): pairs whose
  // boxes are further apart than the margin stop here, and so do pairs that the previous normal
  // still separates by more than the margin (any axis bounds the distance from below).
  if (((box_lo[a] - box_hi[b]).array() > margin).any() || ((box_lo[b] - box_hi[a]).array() > margin).any())
    return INFINITY;
  if (axis.squaredNorm() > 0 && axis.dot(support(a, -axis) - support(b, axis)) > margin) return INFINITY;
  const Geometry& ga = geometry[a];
  const Geometry& gb = geometry[b];
  const double scale = ga.size + gb.size;
  const double tolerance = 1e-9 * scale;

  // 1. Normal and closest pair by GJK on the cores (separated) or EPA on the shapes (cores overlap),
  //    each checked against the gap between the shapes' support planes along its normal (GjkEpa).
  //    When GJK does not converge and EPA gives up on a thin overlap, the best axis among the
  //    faces' normals stands in.
  const GjkEpaResult r = gjk_epa->closest_pair(a, b, axis);
  PairPoint closest = r.gjk;
  if (!r.converged) {
    // EPA's normal on a cylinder's round side is a polytope's approximation: a face's normal
    // that overlaps the pair less is the better axis. On polytopes EPA is exact.
    if (r.epa_valid && ga.type != ShapeType::Cylinder && gb.type != ShapeType::Cylinder) {
      closest = r.epa;
    } else {
      // GJK stopped short: its distance is an upper bound, its normal possibly far off. Axes are
      // compared by the gap between the exact shapes' support planes, a lower bound that is the
      // distance on the true axis (a box resting 4e-7 m from another's face, GJK stopped at
      // 1 cm along a wrong axis: its planes overlapped by 0.22 m, which became a contact's depth).
      const PairPoint face = best_face_axis(a, b, axis);
      const double gjk_gap =
          r.have_gjk ? closest.normal.dot(support(a, -closest.normal) - support(b, closest.normal)) : -INFINITY;
      if (r.epa_valid && r.epa.distance >= face.distance - tolerance)
        closest = r.epa;
      else if (face.distance > gjk_gap)
        closest = face;
    }
  }
  axis = closest.normal;
  // A rounded shape lies within a few rounding radii inside the exact one.
  if (r.converged && closest.distance > margin + 4 * (ga.rounding + gb.rounding)) return INFINITY;

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

int NarrowPhase::pair_contacts(int a, int b, Vec3& axis, PairPoint* out) {
  if (!(generate(a, b, pair_margin(a, b), axis) < INFINITY)) return 0;
  for (PairPoint& p : candidates)
    p.predicted = p.distance + h * p.normal.dot(point_velocity(a, p.on_a) - point_velocity(b, p.on_b));
  // A resting pair sinks by about the solver's slop per step, well within the rounding allowance.
  const int count = reduce(candidates, axis, std::min(geometry[a].size, geometry[b].size), 0.05 * contact_margin);
  std::copy(candidates.begin(), candidates.begin() + count, out);
  return count;
}

}  // namespace rbpart::collision
