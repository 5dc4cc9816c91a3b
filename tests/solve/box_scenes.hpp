#pragma once
// Small contact problems built by hand for the solver tests: cubes resting or sliding on static
// ground or on each other (DESIGN.md §2 rows), with analytic answers where symmetry gives them.
#include "assembly/rows.hpp"
#include "graph/islands.hpp"
#include "scene/bodies.hpp"

#include <vector>

namespace rbpart::testing {

constexpr double kGravity = 9.81, kStep = 1.0 / 60.0;

struct Scene {
  Rows rows;
  Bodies bodies;
  Islands islands;
  std::vector<Vec6> free_velocity;  // u* per body
};

// A cube of half extent a and mass m resting face-down on static ground (z = 0, below = -1) or on
// the cube `below` (same half extent), the four corners of the contact face as contacts (normal +
// two friction rows each; relative velocity top minus below), moving with velocity
// (vx, vy, -g h) and spin wz about z before contact (gravity applied: u* = u + h g).
inline void add_box_on(Scene& s, int below, double m, double a, double vx, double mu, double vy = 0, double wz = 0) {
  const int body = static_cast<int>(s.bodies.inv_mass.size());
  const double inertia = m / 3 * (2 * a * a);
  s.bodies.inv_mass.push_back(1 / m);
  s.bodies.inv_inertia.push_back(Mat3::Identity() / inertia);
  s.bodies.x.push_back(below < 0 ? Vec3(3.0 * body, 0, a) : Vec3(s.bodies.x[below] + Vec3(0, 0, 2 * a)));
  Vec6 u;
  u << vx, vy, -kGravity * kStep, 0, 0, wz;
  s.free_velocity.push_back(u);
  for (double cx : {-a, a})
    for (double cy : {-a, a}) {
      const Vec3 r(cx, cy, -a), r_below(cx, cy, a);
      const auto row = [&](RowKind kind, const Vec3& dir) {
        const int j = s.rows.add(kind, body, below, s.rows.size());
        s.rows.jac[j][0] << dir, r.cross(dir);
        double jmj = dir.squaredNorm() / m + r.cross(dir).squaredNorm() / inertia;
        s.rows.q[j] = s.rows.jac[j][0].dot(u);
        if (below >= 0) {
          s.rows.jac[j][1] << -dir, -r_below.cross(dir);
          jmj += dir.squaredNorm() * s.bodies.inv_mass[below] +
                 r_below.cross(dir).squaredNorm() * s.bodies.inv_inertia[below](0, 0);
          s.rows.q[j] += s.rows.jac[j][1].dot(s.free_velocity[below]);
        }
        s.rows.sigma[j] = 1e-6 * jmj;
        return j;
      };
      const int n = row(RowKind::Normal, Vec3::UnitZ());
      for (const Vec3& t : {Vec3(Vec3::UnitX()), Vec3(Vec3::UnitY())}) {
        const int f = row(RowKind::Friction, t);
        s.rows.normal_of[f] = n;
        s.rows.mu[f] = mu;
      }
    }
}

inline void add_box(Scene& s, double m, double a, double vx, double mu) { add_box_on(s, -1, m, a, vx, mu); }

inline void finish(Scene& s) { build_islands(s.rows, static_cast<int>(s.bodies.inv_mass.size()), s.islands); }

// Body velocity after the impulses, u* + M^-1 J^T lambda.
inline Vec6 velocity_after(const Scene& s, int body) {
  Vec6 u = s.free_velocity[body];
  for (std::size_t j = 0; j < s.rows.size(); ++j)
    if (s.rows.body[j][0] == body) {
      const Vec6& jac = s.rows.jac[j][0];
      u.head<3>() += s.bodies.inv_mass[body] * jac.head<3>() * s.rows.lambda[j];
      u.tail<3>() += s.bodies.inv_inertia[body] * jac.tail<3>() * s.rows.lambda[j];
    }
  return u;
}

}  // namespace rbpart::testing
