#pragma once
// A pair's manifold: the at most kMaxPoints contact points kept of the narrow phase's candidates
// (reduce), and the persistent ids they carry from call to call (collide.hpp: Contact::id). The pair
// algorithm keeps its manifold itself (bullet_adapter.cpp); Bullet's btPersistentManifold, which
// holds four points at most, is not used.
//
// Persistence: a new point within the pair's margin of one of its previous points (in either body's
// frame; the sweeps bound how far a point moves on the other body, rolling moves it on both) takes
// over that point's id; other points get fresh ids from the Collider's counter, assigned in
// (body_a, body_b) order after sorting, so runs are deterministic.
#include "collision/collide.hpp"

#include <cstdint>
#include <vector>

namespace rbpart::collision {

constexpr int kFootprint = 4;
constexpr int kMaxPoints = 8;

// A contact point of a pair (A, B) = (manifold body 0, body 1), all in world coordinates.
struct PairPoint {
  Vec3 on_a, on_b;
  Vec3 normal;  // from B into A
  double distance;
  double predicted = 0;  // distance after the step at the bodies' current velocities (reduce)
};

// Keeps at most kMaxPoints of `pts` in place, and returns their number: a footprint of four, then the
// points that the bodies' motion drives in within the step (the rules and why: manifold.cpp).
int reduce(std::vector<PairPoint>& pts, const Vec3& n, double size, double allowance);

// A pair's contact point as the pair keeps it between calls: the point, where it lies on each body
// (shape frame), and its persistent id (0: none yet).
struct PairContact {
  PairPoint point;
  Vec3 local_a, local_b;
  std::uint64_t id = 0;
};

// A pair's points between calls.
class Manifold {
 public:
  // Replaces the points by `pts`; a new point takes the id of the closest previous point within the
  // pair's margin (distance of the anchors in A's frame or in B's, whichever is smaller), each
  // previous point going to one new point at most, closest pairs first. Ra, xa and Rb, xb are the
  // bodies' shape-frame poses.
  void update(const Mat3& Ra, const Vec3& xa, const Mat3& Rb, const Vec3& xb, double margin, const PairPoint* pts,
              int count);
  int count() const { return count_; }
  PairContact& contact(int i) { return contacts_[i]; }

 private:
  PairContact contacts_[kMaxPoints];
  int count_ = 0;
};

// The Collider's id counter: points without an id get theirs after the call's contacts are sorted.
class ContactIds {
 public:
  // The point's id, or a placeholder above every id (and in order of the calls) while it has none.
  std::uint64_t id(PairContact& point);
  // Sorts `contacts` by (body_a, body_b, id), then gives the placeholders fresh ids, in that order.
  void sort_and_number(std::vector<Contact>& contacts);

 private:
  std::vector<PairContact*> fresh_;  // points awaiting an id in the current call
  std::uint64_t last_id_ = 0;
};

}  // namespace rbpart::collision
