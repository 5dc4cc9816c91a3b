#include "project/position_projection.hpp"

#include <algorithm>
#include <cmath>

#include "solve/solve.hpp"

namespace rbpart {

namespace {

// J_r . (dx, dtheta) over the row's bodies, for per-body moves `move`.
double row_dot(const Rows& rows, int r, const std::vector<Vec6>& move) {
  double d = 0;
  for (int s = 0; s < 2; ++s)
    if (rows.body[r][s] >= 0) d += rows.jac[r][s].dot(move[rows.body[r][s]]);
  return d;
}

}  // namespace

double PositionProjection::project(const std::vector<JointFrame>& joints, const std::vector<Contact>& contacts,
                                   Bodies& bodies, const StepParams& params, const SolverParams& solver) {
  // Contact rows at the poses on entry; their Jacobians are kept through the Gauss-Newton steps.
  contact_rows_.clear();
  for (const Contact& c : contacts) add_contact_normal_row(c, bodies, contact_rows_);

  std::vector<Vec6>& move = move_;  // the projection so far
  move.assign(bodies.size(), Vec6::Zero());
  double worst = 0;
  for (int iteration = 0; iteration <= params.joint_projection_iterations; ++iteration) {
    joint_rows_.clear();
    append_joint_rows(joints, bodies, joint_rows_);
    // Compliant joints are meant to stretch: only rigid rows are projected.
    rows_.clear();
    worst = 0;
    for (std::size_t j = 0; j < joint_rows_.size(); ++j) {
      if (joint_rows_.sigma[j] != 0) continue;
      worst = std::max(worst, std::abs(joint_rows_.q[j]));
      const int r = rows_.add(RowKind::Joint, joint_rows_.body[j][0], joint_rows_.body[j][1], joint_rows_.key[j]);
      rows_.jac[r] = joint_rows_.jac[j];
      rows_.q[r] = joint_rows_.q[j];
    }
    bool too_deep = false;
    for (std::size_t c = 0; c < contacts.size(); ++c) {
      const int from = static_cast<int>(c);
      const double d = contacts[c].distance + row_dot(contact_rows_, from, move);
      // A contact found deeper than depth is pushed back to half of it, so that the linearisation's
      // error at the next collision (a turning body's corner) stays within depth.
      const double depth = params.projection_depth * (contacts[c].distance < -params.projection_depth ? 0.5 : 1.0);
      const double slack = std::max(d, 0.0) + std::min(0.0, d + depth);
      too_deep = too_deep || slack < -params.joint_tolerance;
      const int r = rows_.add(RowKind::Normal, contact_rows_.body[from][0], contact_rows_.body[from][1],
                              contact_rows_.key[from]);
      rows_.jac[r] = contact_rows_.jac[from];
      rows_.q[r] = slack;
    }
    if ((worst <= params.joint_tolerance && !too_deep) || iteration == params.joint_projection_iterations) break;
    for (std::size_t r = 0; r < rows_.size(); ++r)
      rows_.sigma[r] = params.sigma_floor * row_diagonal(rows_, static_cast<int>(r), bodies);

    build_islands(rows_, bodies.size(), islands_);
    solve_newton_direct(rows_, bodies, islands_, solver, &island_cache_);

    // Move every body by M^-1 J^T delta: translation, and rotation by the small angle it gives.
    std::vector<Vec6>& du = du_;
    du.assign(bodies.size(), Vec6::Zero());
    for (std::size_t r = 0; r < rows_.size(); ++r)
      for (int s = 0; s < 2; ++s) {
        const int k = rows_.body[r][s];
        if (k < 0 || rows_.lambda[r] == 0) continue;
        const Vec6& j = rows_.jac[r][s];
        du[k].head<3>() += rows_.lambda[r] * bodies.inv_mass[k] * j.head<3>();
        du[k].tail<3>() += rows_.lambda[r] * (bodies.inv_inertia[k] * j.tail<3>());
      }
    for (int b = 0; b < bodies.size(); ++b) {
      if (du[b].isZero()) continue;
      move[b] += du[b];
      bodies.x[b] += du[b].head<3>();
      const Vec3 dtheta = du[b].tail<3>();
      bodies.q[b].coeffs() += 0.5 * (Quat(0, dtheta.x(), dtheta.y(), dtheta.z()) * bodies.q[b]).coeffs();
      bodies.q[b].normalize();
    }
  }
  return worst;
}

}  // namespace rbpart
