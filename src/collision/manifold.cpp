// Manifolds (manifold.hpp): the reduction to at most kMaxPoints points, and persistent contact ids.
#include "collision/manifold.hpp"

#include <algorithm>
#include <cmath>

namespace rbpart::collision {

namespace {

constexpr std::uint64_t kFresh = std::uint64_t{1} << 63;  // marks a point that has no id yet

}  // namespace

// Keeps at most kMaxPoints of `pts` (normal n, `size` the smaller body's, `allowance` the depth
// below which differences do not count):
// - A point with one deeper by more than the allowance near it across n (similar normal) is
//   dropped: within a tenth of `size`, or so far below it that only a turn by more than about 30
//   degrees could bring it down as deep. A rock's vertices lie at different heights.
// - A footprint of at most four: a first point, the farthest from it, the one spanning the
//   largest triangle with those two, and the one adding the most area to that triangle (lengths
//   across n, each less twice the point's height above the first). Drawn from the points as deep
//   as the deepest if they span a triangle (a rock resting on the three vertices of a small face
//   needs all three), the first being the one farthest from their centre; else from all, the first
//   being the deepest. A footprint bounds a flat patch; a pair at rest needs no more.
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
  // Index lists kept per thread (pairs run in parallel), so that a warm step allocates nothing.
  thread_local std::vector<int> low, pick, level, order;
  thread_local std::vector<PairPoint> chosen;
  low.clear();  // the points with no deeper neighbour
  for (int i = 0; i < count; ++i) {
    bool covered = false;
    for (int k = 0; k < count && !covered; ++k)
      covered = pts[k].distance < pts[i].distance - allowance && near(i, k);
    if (!covered) low.push_back(i);
  }
  pick.assign(1, low[0]);
  for (int i : low)
    if (pts[i].distance < pts[pick[0]].distance) pick[0] = i;
  // The footprint's points: those as deep as the deepest (up to the allowance) if they span a
  // plane, else all. A rock resting on the three vertices of a small face needs all three, which
  // a footprint spread over higher points could miss.
  level.clear();
  for (int i : low)
    if (pts[i].distance <= pts[pick[0]].distance + allowance) level.push_back(i);
  const bool spread = level.size() < 3;  // the footprint is drawn from all points
  if (spread) level = low;
  if (!spread) {
    // Points as deep as the deepest (a face on a face: all of them, to round-off) start the
    // footprint from the one farthest from their centre, not from the deepest: which is deepest
    // turns on round-off there, and a resting pair's points would alternate between two sets.
    Vec3 centre = Vec3::Zero();
    for (int i : level) centre += across(i);
    centre /= static_cast<double>(level.size());
    double farthest = -1;
    for (int i : level) {
      const double d = (across(i) - centre).squaredNorm();
      if (d > farthest) {
        farthest = d;
        pick[0] = i;
      }
    }
  }
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
  order.resize(count);
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
  chosen.clear();
  for (int k : pick) chosen.push_back(pts[k]);
  pts.assign(chosen.begin(), chosen.end());
  return static_cast<int>(pts.size());
}

void Manifold::update(const Mat3& Ra, const Vec3& xa, const Mat3& Rb, const Vec3& xb, double margin,
                      const PairPoint* pts, int count) {
  PairContact next[kMaxPoints];
  for (int i = 0; i < count; ++i) {
    next[i].point = pts[i];
    next[i].local_a = Ra.transpose() * (pts[i].on_a - xa);
    next[i].local_b = Rb.transpose() * (pts[i].on_b - xb);
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

std::uint64_t ContactIds::id(PairContact& point) {
  if (point.id != 0) return point.id;
  fresh_.push_back(&point);
  return kFresh | (fresh_.size() - 1);
}

void ContactIds::sort_and_number(std::vector<Contact>& contacts) {
  std::sort(contacts.begin(), contacts.end(), [](const Contact& x, const Contact& y) {
    if (x.body_a != y.body_a) return x.body_a < y.body_a;
    if (x.body_b != y.body_b) return x.body_b < y.body_b;
    return x.id < y.id;
  });
  // Fresh ids in sorted order: they exceed every earlier id, so the order stays sorted.
  for (Contact& c : contacts) {
    if (!(c.id & kFresh)) continue;
    c.id = fresh_[c.id & ~kFresh]->id = ++last_id_;
  }
  fresh_.clear();
}

}  // namespace rbpart::collision
