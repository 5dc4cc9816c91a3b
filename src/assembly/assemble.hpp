#pragma once
// Assembly stage: every contact and joint becomes constraint rows (docs/design.md#dynamics), warm started by
// persistent key from the previous step's solution.
#include <rbpart/params.hpp>
#include <rbpart/scene.hpp>

#include <cstdint>
#include <vector>

#include "assembly/rows.hpp"
#include "collision/collide.hpp"
#include "scene/bodies.hpp"

namespace rbpart {

// A joint's anchors and reference frames in each body's centre-of-mass frame, fixed at scene start.
struct JointFrame {
  JointType type = JointType::Ball;
  int body[2] = {-1, -1};      // dynamic body or -1 (static body or world)
  Vec3 anchor[2];              // body-local offset from the COM; world point when body is -1
  Vec3 axis[2];                // hinge axis, body-local (world when body is -1)
  Quat rest;                   // fixed joint: q_a^-1 q_b at scene start
  double compliance = 0;
};

std::vector<JointFrame> make_joint_frames(const SceneDef& scene, const Bodies& bodies);

// Previous step's solution, looked up by row key (sorted for binary search; reused buffers).
class WarmStart {
 public:
  struct Entry {
    std::uint64_t key;
    double lambda;
    RowState state;
    Vec3 direction;  // friction rows: the tangent the impulse was applied along
  };
  void store(const Rows& rows);
  // Returns false if the key was not solved last step.
  bool find(std::uint64_t key, double& lambda, RowState& state) const;
  // A contact's rows of the last step, normal and friction 1, 2 (null where absent): their keys are
  // adjacent, so one search finds the three.
  void find_contact(std::uint64_t contact_id, const Entry* (&rows)[3]) const;

 private:
  const Entry* lookup(std::uint64_t key) const;
  std::vector<Entry> entries_;
};

// Builds the step's rows. Velocities in `bodies` must already be the free velocities u*
// (q = J u* + b); `sliding_v`/`sliding_w` are the velocities before external forces, which define
// the sliding direction of friction.
void assemble_rows(const std::vector<Contact>& contacts, const std::vector<JointFrame>& joints,
                   const Bodies& bodies, const std::vector<Vec3>& sliding_v,
                   const std::vector<Vec3>& sliding_w, const StepParams& params, double h,
                   const WarmStart& warm, Rows& rows);

// Appends every joint's rows at the bodies' current poses with q = the row's position error phi
// (docs/design.md#dynamics) and sigma = the joint's compliance; assemble_rows scales both by the step.
void append_joint_rows(const std::vector<JointFrame>& joints, const Bodies& bodies, Rows& rows);

// Appends a contact's normal row (lambda >= 0 pushes body_a along the normal, body_b against it,
// a static body_b being -1) with q = 0; returns its index.
int add_contact_normal_row(const Contact& c, const Bodies& bodies, Rows& rows);

// (J M^-1 J^T)_jj of a row, the scale of its regularisation floor.
double row_diagonal(const Rows& rows, int r, const Bodies& bodies);

// Row keys: contact id c gives 4c + {0 normal, 1, 2 friction}; joint k's rows have the top bit set.
inline std::uint64_t contact_row_key(std::uint64_t contact_id, int k) { return contact_id * 4 + k; }
inline std::uint64_t joint_row_key(int joint, int k) {
  return (std::uint64_t{1} << 63) | (static_cast<std::uint64_t>(joint) << 3) | static_cast<std::uint64_t>(k);
}

}  // namespace rbpart
