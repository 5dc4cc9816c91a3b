#include "integrate/joint_projection.hpp"

#include <algorithm>
#include <cmath>

namespace rbpart {

double JointProjection::project(const std::vector<JointFrame>& joints, Bodies& bodies, double sigma_floor,
                                double tolerance, int max_iterations) {
  double worst = 0;
  for (int iteration = 0; iteration <= max_iterations; ++iteration) {
    rows_.clear();
    append_joint_rows(joints, bodies, rows_);
    // Compliant joints are meant to stretch: only rigid rows are projected.
    rigid_.clear();
    worst = 0;
    for (std::size_t r = 0; r < rows_.size(); ++r)
      if (rows_.sigma[r] == 0) {
        rigid_.push_back(static_cast<int>(r));
        worst = std::max(worst, std::abs(rows_.q[r]));
      }
    if (worst <= tolerance || iteration == max_iterations) break;

    // CSR of the rigid rows on each body, then A = J M^-1 J^T (+ floor) by pairs of rows per body.
    const int n = static_cast<int>(rigid_.size());
    body_row_offset_.assign(bodies.size() + 1, 0);
    for (int i = 0; i < n; ++i)
      for (int s = 0; s < 2; ++s)
        if (rows_.body[rigid_[i]][s] >= 0) ++body_row_offset_[rows_.body[rigid_[i]][s] + 1];
    for (int b = 0; b < bodies.size(); ++b) body_row_offset_[b + 1] += body_row_offset_[b];
    body_rows_.resize(body_row_offset_.back());
    std::vector<int> fill(body_row_offset_.begin(), body_row_offset_.end() - 1);
    for (int i = 0; i < n; ++i)
      for (int s = 0; s < 2; ++s)
        if (rows_.body[rigid_[i]][s] >= 0) body_rows_[fill[rows_.body[rigid_[i]][s]]++] = 2 * i + s;

    auto m_inv_j = [&](int i, int s) {
      const int k = rows_.body[rigid_[i]][s];
      const Vec6& j = rows_.jac[rigid_[i]][s];
      Vec6 m;
      m << bodies.inv_mass[k] * j.head<3>(), bodies.inv_inertia[k] * j.tail<3>();
      return m;
    };
    triplets_.clear();
    for (int b = 0; b < bodies.size(); ++b)
      for (int e = body_row_offset_[b]; e < body_row_offset_[b + 1]; ++e) {
        const int i = body_rows_[e] >> 1, si = body_rows_[e] & 1;
        const Vec6 mi = m_inv_j(i, si);
        for (int f = body_row_offset_[b]; f < body_row_offset_[b + 1]; ++f) {
          const int j = body_rows_[f] >> 1, sj = body_rows_[f] & 1;
          if (j >= i) triplets_.emplace_back(j, i, rows_.jac[rigid_[j]][sj].dot(mi));
        }
      }
    a_.resize(n, n);
    a_.setFromTriplets(triplets_.begin(), triplets_.end());
    for (int i = 0; i < n; ++i) a_.coeffRef(i, i) *= 1 + sigma_floor;
    ldlt_.compute(a_);  // lower triangle is read (SimplicialLDLT's default)
    if (ldlt_.info() != Eigen::Success) break;
    phi_.resize(n);
    for (int i = 0; i < n; ++i) phi_[i] = -rows_.q[rigid_[i]];
    delta_ = ldlt_.solve(phi_);

    // Move every body by M^-1 J^T delta: translation, and rotation by the small angle it gives.
    for (int b = 0; b < bodies.size(); ++b) {
      Vec6 du = Vec6::Zero();
      for (int e = body_row_offset_[b]; e < body_row_offset_[b + 1]; ++e) {
        const int i = body_rows_[e] >> 1, si = body_rows_[e] & 1;
        du += delta_[i] * m_inv_j(i, si);
      }
      if (du.isZero()) continue;
      bodies.x[b] += du.head<3>();
      const Vec3 dtheta = du.tail<3>();
      bodies.q[b].coeffs() += 0.5 * (Quat(0, dtheta.x(), dtheta.y(), dtheta.z()) * bodies.q[b]).coeffs();
      bodies.q[b].normalize();
    }
  }
  return worst;
}

}  // namespace rbpart
