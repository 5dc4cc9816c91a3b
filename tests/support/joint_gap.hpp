#pragma once
// Measures how far each joint's two anchors have drifted apart (m), against the scene's joints as
// defined at the start: the anchor is fixed in each body's centre-of-mass frame from the initial
// configuration. Used by the step and scene tests (joint gaps <= 1 mm).
#include <rbpart/world.hpp>

#include <algorithm>
#include <vector>

#include "scene/bodies.hpp"
#include "step/world_internals.hpp"

namespace rbpart::test {

class JointGapMeter {
 public:
  explicit JointGapMeter(const World& world) {
    const Bodies& B = world_bodies(world);
    for (const JointDef& j : world.scene().joints) {
      Anchor an{j.body_a, j.body_b, B.q[j.body_a].conjugate() * (j.anchor - B.x[j.body_a]), j.anchor};
      if (j.body_b >= 0) an.lb = B.q[j.body_b].conjugate() * (j.anchor - B.x[j.body_b]);
      anchors_.push_back(an);
    }
  }
  // Largest anchor distance over all joints in the world's current state.
  double max_gap(const World& world) const {
    const Bodies& B = world_bodies(world);
    double worst = 0;
    for (const Anchor& an : anchors_) {
      const Vec3 pa = B.x[an.a] + B.q[an.a] * an.la;
      const Vec3 pb = an.b >= 0 ? Vec3(B.x[an.b] + B.q[an.b] * an.lb) : an.lb;
      worst = std::max(worst, (pa - pb).norm());
    }
    return worst;
  }

 private:
  struct Anchor {
    int a, b;
    Vec3 la, lb;  // body-local anchors (lb: world point when b is the world)
  };
  std::vector<Anchor> anchors_;
};

}  // namespace rbpart::test
