#pragma once
// Bodies built by hand for the stage tests that take a `Bodies` directly (assembly, integrate):
// static bodies and boxes of given mass, half extents and pose, with the world inverse inertia of
// their pose, and the dense mass matrix the tests compare the stages' sparse products against.
#include <Eigen/Dense>

#include "scene/bodies.hpp"

namespace rbpart::test {

// Appends a body with body-frame inertia `inertia` (ignored when static); returns its index.
inline int add_body(Bodies& b, bool is_static, double mass, const Mat3& inertia, const Vec3& x,
                    const Quat& q = Quat::Identity(), double friction = 0.5) {
  const Mat3 R = q.toRotationMatrix();
  b.is_static.push_back(is_static);
  b.mass.push_back(is_static ? 0 : mass);
  b.inv_mass.push_back(is_static ? 0 : 1 / mass);
  b.inertia_body.push_back(is_static ? Mat3::Zero() : inertia);
  b.inv_inertia_body.push_back(is_static ? Mat3::Zero() : Mat3(inertia.inverse()));
  b.inv_inertia.push_back(R * b.inv_inertia_body.back() * R.transpose());
  b.com_local.push_back(Vec3::Zero());
  b.friction.push_back(friction);
  b.x.push_back(x);
  b.q.push_back(q);
  b.v.push_back(Vec3::Zero());
  b.w.push_back(Vec3::Zero());
  b.geometric_stiffness.push_back(0);
  return b.size() - 1;
}

// Inertia of a solid box of mass m and half extents h about its centre: m/3 (h_y^2 + h_z^2), ...
inline Mat3 box_inertia(double m, const Vec3& h) {
  return Vec3(m / 3 * (h.y() * h.y() + h.z() * h.z()), m / 3 * (h.x() * h.x() + h.z() * h.z()),
              m / 3 * (h.x() * h.x() + h.y() * h.y()))
      .asDiagonal();
}

inline int add_box(Bodies& b, double mass, const Vec3& half, const Vec3& x, const Quat& q = Quat::Identity(),
                   double friction = 0.5) {
  return add_body(b, false, mass, box_inertia(mass, half), x, q, friction);
}

inline int add_static(Bodies& b, const Vec3& x, double friction = 0.5) {
  return add_body(b, true, 0, Mat3::Zero(), x, Quat::Identity(), friction);
}

// Dense inverse mass matrix over the velocities (v_0, w_0, v_1, w_1, ...) of every body, from the
// masses and the body-frame inertias rotated to the bodies' poses (static bodies: zero blocks).
inline Eigen::MatrixXd inverse_mass_matrix(const Bodies& b) {
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(6 * b.size(), 6 * b.size());
  for (int k = 0; k < b.size(); ++k) {
    if (b.is_static[k]) continue;
    const Mat3 R = b.q[k].toRotationMatrix();
    m.block<3, 3>(6 * k, 6 * k) = Mat3::Identity() / b.mass[k];
    m.block<3, 3>(6 * k + 3, 6 * k + 3) = (R * b.inertia_body[k] * R.transpose()).inverse();
  }
  return m;
}

// The velocity of the point at world position p of body k.
inline Vec3 point_velocity(const Bodies& b, int k, const Vec3& p) { return b.v[k] + b.w[k].cross(p - b.x[k]); }

}  // namespace rbpart::test
