#pragma once
// Random contact problems for the solve tests and bench/newton_island_bench.cpp (fixed seeds), as
// graph/generate.hpp gives graphs to the partition tests and benchmarks: an island built like the
// assembly stage builds one (DESIGN.md §2), bodies with random masses and inertias, contacts (a
// normal row [0, inf) and two friction rows, coupled to it) between two bodies or against a static
// body, bilateral joint rows, and a few general box rows, with A = J M^-1 J^T + Sigma, sigma a 1e-6
// floor of the diagonal (rigid) or compliant. With more rows than 6 * bodies it is redundant, as
// contact piles are; with many contacts on one or two bodies (random normals, mu up to 0.8) it is
// harder than a pile's islands.
#include "solve/island_system.hpp"

#include "assembly/rows.hpp"
#include "graph/islands.hpp"
#include "scene/bodies.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <random>

namespace rbpart::testing {

struct RandomIsland {
  Rows rows;
  Bodies bodies;
  Islands islands;
  std::vector<int> local_row;
  IslandSystem system;  // island 0 in local numbering (the whole problem)
};

struct IslandOptions {
  int rows = 30;
  int bodies = 0;                  // 0: max(1, rows / 10)
  double static_fraction = 0.3;    // contacts against a static body
  double joint_fraction = 0.15;    // bilateral rows
  double box_fraction = 0.1;       // general box rows [lo, hi] (may exclude 0)
  double compliant_fraction = 0.1; // rows with sigma = 1e-2 of the diagonal instead of the 1e-6 floor
  double q_consistent = 0.7;       // fraction of q = J v + noise (a feasible target) vs pure noise
  double neighbour_radius = 1.5;   // bodies sit on a unit lattice; 1.5 joins diagonal neighbours too
  // Friction rows bounded by +-mu lambda_n of their normal; false: by fixed boxes +-U(0, 1), which
  // makes the problem a strictly convex box QP (DESIGN.md §3, fixed bounds).
  bool coupled_friction = true;
};

// Entries uniform in [-1, 1] from `rng` (Eigen's Random() draws from std::rand, not from the seed).
inline Eigen::MatrixXd uniform_matrix(std::mt19937& rng, int rows, int cols) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  return Eigen::MatrixXd::NullaryExpr(rows, cols, [&]() { return u(rng); });
}

inline Vec3 random_unit(std::mt19937& rng) {
  std::normal_distribution<double> g;
  Vec3 v(g(rng), g(rng), g(rng));
  return v.normalized();
}

inline Mat3 random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> g;
  return Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized().toRotationMatrix();
}

// An island of `opt.rows` rows (rounded to whole contacts) on connected bodies.
inline void random_contact_island(std::mt19937& rng, const IslandOptions& opt, RandomIsland& out) {
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  const int nb = opt.bodies > 0 ? opt.bodies : std::max(1, opt.rows / 10);
  Bodies& b = out.bodies;
  b = Bodies{};
  b.inv_mass.resize(nb);
  b.inv_inertia.resize(nb);
  for (int k = 0; k < nb; ++k) {
    const double m = std::exp(std::log(0.2) + u01(rng) * std::log(50.0));  // 0.2 .. 10 kg
    const Vec3 half(0.1 + 0.3 * u01(rng), 0.1 + 0.3 * u01(rng), 0.1 + 0.3 * u01(rng));
    const Vec3 inertia(m / 3 * (half.y() * half.y() + half.z() * half.z()),
                       m / 3 * (half.x() * half.x() + half.z() * half.z()),
                       m / 3 * (half.x() * half.x() + half.y() * half.y()));
    const Mat3 r = random_rotation(rng);
    b.inv_mass[k] = 1 / m;
    b.inv_inertia[k] = r * inertia.cwiseInverse().asDiagonal() * r.transpose();
  }
  // Bodies on a jittered cubic lattice (spacing 1); constraints join lattice neighbours, so the body
  // graph is three-dimensional and local like a pile's, not an expander.
  const int side = std::max(1, static_cast<int>(std::ceil(std::cbrt(static_cast<double>(nb)))));
  std::vector<Vec3> centre(nb);
  for (int k = 0; k < nb; ++k)
    centre[k] = Vec3(k % side, (k / side) % side, k / (side * side)) + 0.1 * uniform_matrix(rng, 3, 1);
  std::vector<std::vector<int>> neighbours(nb);
  for (int k = 0; k < nb; ++k)
    for (int l = 0; l < nb; ++l)
      if (l != k && (centre[l] - centre[k]).norm() < opt.neighbour_radius) neighbours[k].push_back(l);
  // A random world velocity per body makes q = J v consistent (the system can satisfy w = 0).
  std::vector<Vec6> velocity(nb);
  for (auto& v : velocity) v = uniform_matrix(rng, 6, 1);

  Rows& rows = out.rows;
  rows.clear();
  int tree = 1;  // bodies 0 .. tree-1 are connected so far
  auto pick_pair = [&](int& a, int& c) {
    // Until every body is attached, join the next body to a connected lattice neighbour (bodies are
    // numbered along the lattice, so one exists), keeping the island connected.
    if (tree < nb) {
      c = tree++;
      std::vector<int> earlier;
      for (int l : neighbours[c])
        if (l < c) earlier.push_back(l);
      a = earlier.empty() ? c - 1 : earlier[std::uniform_int_distribution<int>(0, static_cast<int>(earlier.size()) - 1)(rng)];
      return;
    }
    a = std::uniform_int_distribution<int>(0, nb - 1)(rng);
    c = -1;
    if (u01(rng) >= opt.static_fraction && !neighbours[a].empty())
      c = neighbours[a][std::uniform_int_distribution<int>(0, static_cast<int>(neighbours[a].size()) - 1)(rng)];
  };
  auto finish_row = [&](int r, double sigma_scale) {
    double jmj = 0, jv = 0;
    for (int slot = 0; slot < 2; ++slot) {
      const int k = rows.body[r][slot];
      if (k < 0) continue;
      const Vec6& j = rows.jac[r][slot];
      jmj += b.inv_mass[k] * j.head<3>().squaredNorm() + j.tail<3>().dot(b.inv_inertia[k] * j.tail<3>());
      jv += j.dot(velocity[k]);
    }
    rows.sigma[r] = sigma_scale * jmj;
    const double noise = 2 * u01(rng) - 1;
    rows.q[r] = u01(rng) < opt.q_consistent ? jv + 1e-3 * noise : noise;
  };
  auto jacobian = [&](int r, int c, const Vec3& dir, const Vec3& ra, const Vec3& rc) {
    rows.jac[r][0] << dir, ra.cross(dir);
    if (c >= 0) rows.jac[r][1] << -dir, -rc.cross(dir);
  };
  std::uint64_t key = 0;
  while (static_cast<int>(rows.size()) < opt.rows || tree < nb) {
    int a, c;
    pick_pair(a, c);
    const double sigma_scale = u01(rng) < opt.compliant_fraction ? 1e-2 : 1e-6;
    // Contact point between the two centres (below a static contact's body), lever arms from it.
    const Vec3 p = c >= 0 ? Vec3(0.5 * (centre[a] + centre[c]) + 0.2 * uniform_matrix(rng, 3, 1))
                          : Vec3(centre[a] + Vec3(0, 0, -0.5) + 0.2 * uniform_matrix(rng, 3, 1));
    const Vec3 ra = p - centre[a], rc = c >= 0 ? Vec3(p - centre[c]) : Vec3::Zero();
    const Vec3 between = c >= 0 ? Vec3(centre[a] - centre[c]) : Vec3::UnitZ();
    const double kind = u01(rng);
    if (kind < opt.joint_fraction) {
      const int r = rows.add(RowKind::Joint, a, c, key++);
      jacobian(r, c, random_unit(rng), ra, rc);
      finish_row(r, sigma_scale);
    } else if (kind < opt.joint_fraction + opt.box_fraction) {
      const int r = rows.add(RowKind::Joint, a, c, key++);
      jacobian(r, c, random_unit(rng), ra, rc);
      const double x = 2 * u01(rng) - 1, y = 2 * u01(rng) - 1;
      rows.lo[r] = std::min(x, y);
      rows.hi[r] = std::max(x, y);
      finish_row(r, sigma_scale);
    } else {
      // A contact: normal row and two friction rows along tangents.
      const Vec3 n = (between.normalized() + 0.3 * random_unit(rng)).normalized();
      const Vec3 t1 = n.unitOrthogonal(), t2 = n.cross(t1);
      const int rn = rows.add(RowKind::Normal, a, c, key++);
      jacobian(rn, c, n, ra, rc);
      finish_row(rn, sigma_scale);
      const double mu = 0.1 + 0.7 * u01(rng);
      for (const Vec3& t : {t1, t2}) {
        const int rt = rows.add(RowKind::Friction, a, c, key++);
        jacobian(rt, c, t, ra, rc);
        finish_row(rt, sigma_scale);
        if (opt.coupled_friction) {
          rows.normal_of[rt] = rn;
          rows.mu[rt] = mu;
        } else {
          const double bound = u01(rng);
          rows.lo[rt] = -bound;
          rows.hi[rt] = bound;
        }
      }
    }
  }
  build_islands(rows, nb, out.islands);
  out.local_row = local_row_index(rows, out.islands);
  out.system.gather(rows, b, out.islands, 0, out.local_row);
}

}  // namespace rbpart::testing
