#include "integrate/integrate.hpp"

#include <algorithm>
#include <cmath>

namespace rbpart {

void update_world_inertia(Bodies& bodies) {
  for (int i = 0; i < bodies.size(); ++i) {
    if (bodies.is_static[i]) {
      bodies.inv_inertia[i].setZero();
      continue;
    }
    const Mat3 R = bodies.q[i].toRotationMatrix();
    const double k = bodies.geometric_stiffness[i];
    bodies.inv_inertia[i] = k == 0 ? Mat3(R * bodies.inv_inertia_body[i] * R.transpose())
                                   : Mat3((R * bodies.inertia_body[i] * R.transpose() + k * Mat3::Identity()).inverse());
  }
}

void update_geometric_stiffness(const Rows& rows, Bodies& bodies, double h) {
  std::fill(bodies.geometric_stiffness.begin(), bodies.geometric_stiffness.end(), 0.0);
  for (std::size_t r = 0; r < rows.size(); ++r) {
    if (rows.kind[r] != RowKind::Joint) continue;
    for (int s = 0; s < 2; ++s) {
      const int k = rows.body[r][s];
      if (k >= 0) bodies.geometric_stiffness[k] += h * std::abs(rows.lambda[r]) * rows.jac[r][s].tail<3>().norm();
    }
  }
}

void apply_external_forces(Bodies& bodies, const Vec3& gravity, double h) {
  for (int i = 0; i < bodies.size(); ++i) {
    if (bodies.is_static[i]) continue;
    bodies.v[i] += h * gravity;
    // Implicit gyroscopic step (Catto, "Numerical methods", GDC 2015): solve
    // I (w - w0) + h w x (I w) = 0 by one Newton step from w0, in the body frame.
    const Mat3 R = bodies.q[i].toRotationMatrix();
    const Vec3 w0 = R.transpose() * bodies.w[i];
    const Mat3& I = bodies.inertia_body[i];
    const Vec3 Iw = I * w0;
    const Vec3 f = h * w0.cross(Iw);
    auto skew = [](const Vec3& a) {
      Mat3 m;
      m << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
      return m;
    };
    const Mat3 jac = I + h * (skew(w0) * I - skew(Iw));
    bodies.w[i] = R * (w0 - jac.lu().solve(f));
  }
}

void apply_body_forces(Bodies& bodies, const std::vector<Vec3>& force, const std::vector<Vec3>& torque, double h) {
  for (int i = 0; i < bodies.size(); ++i) {
    bodies.v[i] += h * bodies.inv_mass[i] * force[i];
    bodies.w[i] += h * (bodies.inv_inertia[i] * torque[i]);
  }
}

void apply_impulses(const Rows& rows, Bodies& bodies) {
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const double l = rows.lambda[r];
    if (l == 0) continue;
    for (int s = 0; s < 2; ++s) {
      const int k = rows.body[r][s];
      if (k < 0) continue;
      bodies.v[k] += bodies.inv_mass[k] * l * rows.jac[r][s].head<3>();
      bodies.w[k] += bodies.inv_inertia[k] * (l * rows.jac[r][s].tail<3>());
    }
  }
}

void integrate_positions(Bodies& bodies, double h) {
  for (int i = 0; i < bodies.size(); ++i) {
    if (bodies.is_static[i]) continue;
    bodies.x[i] += h * bodies.v[i];
    const Vec3& w = bodies.w[i];
    Quat& q = bodies.q[i];
    const Quat dq(0, w.x(), w.y(), w.z());
    q.coeffs() += 0.5 * h * (dq * q).coeffs();
    q.normalize();
  }
}

}  // namespace rbpart
