#include "integrate/joint_projection.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

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

double JointProjection::project(const std::vector<JointFrame>& joints, const std::vector<Contact>& contacts,
                                const Rows& step_rows, Bodies& bodies, double h, double sigma_floor,
                                double tolerance, int max_iterations, const SolverParams& solver) {
  jointed_.assign(bodies.size(), 0);
  for (const JointFrame& f : joints)
    for (int k : f.body)
      if (k >= 0) jointed_[k] = 1;
  // Contacts of jointed bodies, with their gaps after the step: d + h J v (to first order).
  contact_row_.clear();
  gap_.clear();
  std::vector<Vec6> velocity(bodies.size());
  for (int b = 0; b < bodies.size(); ++b) velocity[b] << bodies.v[b], bodies.w[b];
  for (std::size_t c = 0; c < contacts.size(); ++c) {
    const int r = static_cast<int>(3 * c);
    const Contact& k = contacts[c];
    if (step_rows.key[r] != contact_row_key(k.id, 0)) throw std::logic_error("joint projection: rows out of contact order");
    if (!jointed_[k.body_a] && !(k.body_b >= 0 && jointed_[k.body_b])) continue;
    contact_row_.push_back(r);
    gap_.push_back(k.distance + h * row_dot(step_rows, r, velocity));
  }

  std::vector<Vec6> move(bodies.size(), Vec6::Zero());  // this step's projection so far
  double worst = 0;
  for (int iteration = 0; iteration <= max_iterations; ++iteration) {
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
    if (worst <= tolerance || iteration == max_iterations) break;
    for (std::size_t c = 0; c < contact_row_.size(); ++c) {
      const int from = contact_row_[c];
      const int r = rows_.add(RowKind::Normal, step_rows.body[from][0], step_rows.body[from][1], step_rows.key[from]);
      rows_.jac[r] = step_rows.jac[from];
      rows_.q[r] = std::max(0.0, gap_[c] + row_dot(step_rows, from, move));
    }
    for (std::size_t r = 0; r < rows_.size(); ++r)
      rows_.sigma[r] = sigma_floor * row_diagonal(rows_, static_cast<int>(r), bodies);

    build_islands(rows_, bodies.size(), islands_);
    solve_direct(rows_, bodies, islands_, solver);

    // Move every body by M^-1 J^T delta: translation, and rotation by the small angle it gives.
    std::vector<Vec6> du(bodies.size(), Vec6::Zero());
    for (std::size_t r = 0; r < rows_.size(); ++r)
      for (int s = 0; s < 2; ++s) {
        const int k = rows_.body[r][s];
        if (k < 0) continue;
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
