#pragma once
// Collision stage: contact points between the bodies' shapes. This header hides Bullet and the
// narrow phase: bullet_adapter.cpp implements the Collider on narrow_phase.hpp and manifold.hpp.
#include <rbpart/scene.hpp>

#include <algorithm>
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

// The largest penetration depth among `contacts` (m; 0 when none penetrates).
inline double deepest_penetration(const std::vector<Contact>& contacts) {
  double deepest = 0;
  for (const Contact& c : contacts) deepest = std::max(deepest, -c.distance);
  return deepest;
}

class Collider {
 public:
  // Builds collision shapes for every body; pairs of static bodies and pairs joined by a joint
  // (unless the joint has collide_connected) never produce contacts. `margin` is the contact
  // margin: the separation up to which resting pairs report contacts.
  Collider(const SceneDef& scene, double margin);
  ~Collider();
  Collider(const Collider&) = delete;
  Collider& operator=(const Collider&) = delete;

  // Runs broad + narrow phase for the given shape-frame poses (scene body order) and fills
  // `contacts` (cleared first), sorted deterministically by (body_a, body_b, id).
  //
  // Speculative margin: a pair reports contacts up to the separation
  //   margin_ab = margin + sweep_a + sweep_b,  sweep_k = min(h (|v_k| + |w_k| reach_k), kMaxSweep),
  // with v_k, w_k the velocity of body k's centre of mass and its angular velocity (static bodies:
  // 0), and reach_k the largest distance from its centre of mass to its surface; sweep_k bounds how
  // far any point of body k moves in a step of length h. So every pair that can touch within the
  // step has its contacts at their exact (positive) distances, and the solver's speculative rows
  // (b = d/h) stop the approach before it closes past zero: no tunnelling, however thin the shapes.
  // The contact margin absorbs the velocity the step itself adds (gravity: h^2 g = 2.7 mm at
  // h = 1/60 s). At rest the sweeps vanish and margin_ab = margin.
  void collide(const std::vector<Vec3>& frame_position, const std::vector<Quat>& frame_orientation,
               const std::vector<Vec3>& velocity, const std::vector<Vec3>& angular_velocity, double h,
               std::vector<Contact>& contacts);

  // reach_k above: how far a point of body k can be from its centre of mass (0 for static bodies).
  double reach(int body) const;

  // A body's sweep is capped at this (m): 60 m/s at h = 1/60 s, beyond any impact the scenes hold
  // (free fall from 180 m); it bounds the broad phase's pairs if a body's velocity blows up.
  static constexpr double kMaxSweep = 1.0;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rbpart
