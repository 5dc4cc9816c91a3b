#include "solve/island_system.hpp"

#include <algorithm>
#include <numeric>

namespace rbpart {

void IslandSystem::gather(const Rows& all, const Bodies& bodies_in, const Islands& islands, int island,
                          const std::vector<int>& local_row) {
  IslandChunks serial;
  gather(all, bodies_in, islands, island, local_row, serial);
}

void IslandSystem::gather(const Rows& all, const Bodies& bodies_in, const Islands& islands, int island,
                          const std::vector<int>& local_row, IslandChunks& chunks) {
  const int row_begin = islands.row_offset[island], body_begin = islands.body_offset[island];
  rows = islands.row_offset[island + 1] - row_begin;
  bodies = islands.body_offset[island + 1] - body_begin;
  global_rows = islands.rows.data() + row_begin;
  global_bodies = islands.bodies.data() + body_begin;

  inv_mass.resize(bodies);
  inv_inertia.resize(bodies);
  chunks.each(bodies, [&](int b) {
    inv_mass[b] = bodies_in.inv_mass[global_bodies[b]];
    inv_inertia[b] = bodies_in.inv_inertia[global_bodies[b]];
  });

  body.resize(rows);
  jac.resize(rows);
  mjac.resize(rows);
  q.resize(rows);
  lo.resize(rows);
  hi.resize(rows);
  sigma.resize(rows);
  diag.resize(rows);
  normal_of.resize(rows);
  mu.resize(rows);
  chunks.each(rows, [&](int r) {
    const int g = global_rows[r];
    for (int slot = 0; slot < 2; ++slot) {
      const int b = all.body[g][slot];
      // Island bodies are sorted, so the local index is a binary search away.
      body[r][slot] = b < 0 ? -1 : static_cast<int>(std::lower_bound(global_bodies, global_bodies + bodies, b) - global_bodies);
      jac[r][slot] = all.jac[g][slot];
    }
    if (body[r][0] < 0 || body[r][0] == body[r][1]) {
      // Keep slot 0 filled; a row naming one body twice acts on it with the summed blocks.
      if (body[r][0] == body[r][1]) jac[r][0] += jac[r][1];
      else jac[r][0] = jac[r][1];
      body[r][0] = body[r][1] >= 0 ? body[r][1] : body[r][0];
      body[r][1] = -1;
      jac[r][1].setZero();
    }
    double jmj = 0;
    for (int slot = 0; slot < 2; ++slot) {
      const int b = body[r][slot];
      if (b < 0) {
        mjac[r][slot].setZero();
        continue;
      }
      mjac[r][slot] << inv_mass[b] * jac[r][slot].head<3>(), inv_inertia[b] * jac[r][slot].tail<3>();
      jmj += jac[r][slot].dot(mjac[r][slot]);
    }
    q[r] = all.q[g];
    lo[r] = all.lo[g];
    hi[r] = all.hi[g];
    sigma[r] = all.sigma[g];
    diag[r] = jmj + sigma[r];
    normal_of[r] = all.normal_of[g] >= 0 ? local_row[all.normal_of[g]] : -1;
    mu[r] = all.mu[g];
  });
  // Each body's row slots, in row order.
  body_slot_offset.assign(bodies + 1, 0);
  for (int r = 0; r < rows; ++r)
    for (int slot = 0; slot < 2; ++slot)
      if (body[r][slot] >= 0) ++body_slot_offset[body[r][slot] + 1];
  for (int b = 0; b < bodies; ++b) body_slot_offset[b + 1] += body_slot_offset[b];
  body_slots.resize(body_slot_offset[bodies]);
  slot_fill.assign(body_slot_offset.begin(), body_slot_offset.end() - 1);
  for (int r = 0; r < rows; ++r)
    for (int slot = 0; slot < 2; ++slot)
      if (body[r][slot] >= 0) body_slots[slot_fill[body[r][slot]]++] = 2 * r + slot;
}

void largest_islands_first(const Islands& islands, std::vector<int>& order) {
  order.resize(islands.count());
  std::iota(order.begin(), order.end(), 0);
  // Ties by index, as a stable sort would leave them (std::stable_sort allocates its buffer).
  const auto rows = [&](int i) { return islands.row_offset[i + 1] - islands.row_offset[i]; };
  std::sort(order.begin(), order.end(), [&](int x, int y) { return rows(x) > rows(y) || (rows(x) == rows(y) && x < y); });
}

std::vector<int> largest_islands_first(const Islands& islands) {
  std::vector<int> order;
  largest_islands_first(islands, order);
  return order;
}

void local_row_index(const Rows& rows, const Islands& islands, std::vector<int>& local) {
  local.assign(rows.size(), -1);
  for (std::size_t i = 0; i < islands.count(); ++i)
    for (int k = islands.row_offset[i]; k < islands.row_offset[i + 1]; ++k)
      local[islands.rows[k]] = k - islands.row_offset[i];
}

std::vector<int> local_row_index(const Rows& rows, const Islands& islands) {
  std::vector<int> local;
  local_row_index(rows, islands, local);
  return local;
}

void build_dense(const IslandSystem& s, Eigen::MatrixXd& a) {
  a.setZero(s.rows, s.rows);
  // A = J M^-1 J^T body by body: every pair of row slots on the same body, lower triangle.
  for (int b = 0; b < s.bodies; ++b)
    for (int e = s.body_slot_offset[b]; e < s.body_slot_offset[b + 1]; ++e) {
      const int k = s.body_slots[e] >> 1, sk = s.body_slots[e] & 1;
      for (int f = e; f < s.body_slot_offset[b + 1]; ++f) {
        const int j = s.body_slots[f] >> 1, sj = s.body_slots[f] & 1;
        a(j, k) += s.jac[j][sj].dot(s.mjac[k][sk]);
      }
    }
  a.diagonal() += s.sigma;
  a.triangularView<Eigen::StrictlyUpper>() = a.transpose();
}

void body_masses(const IslandSystem& s, std::vector<Mat6>& mass) {
  mass.resize(s.bodies);
  for (int b = 0; b < s.bodies; ++b) {
    mass[b].setZero();
    mass[b].topLeftCorner<3, 3>().diagonal().setConstant(1.0 / s.inv_mass[b]);
    mass[b].bottomRightCorner<3, 3>() = s.inv_inertia[b].inverse();
  }
}

void apply_mjt(const IslandSystem& s, const Eigen::VectorXd& x, Eigen::VectorXd& du, IslandChunks& chunks) {
  du.resize(6 * s.bodies);
  // Each body gathers its rows' terms in row order: the sums of a scatter over the rows.
  chunks.each(s.bodies, [&](int b) {
    Vec6 sum = Vec6::Zero();
    for (int e = s.body_slot_offset[b]; e < s.body_slot_offset[b + 1]; ++e) {
      const int r = s.body_slots[e] / 2;
      sum += s.mjac[r][s.body_slots[e] % 2] * x[r];
    }
    du.segment<6>(6 * b) = sum;
  });
}

void apply_mjt(const IslandSystem& s, const Eigen::VectorXd& x, Eigen::VectorXd& du) {
  IslandChunks serial;
  apply_mjt(s, x, du, serial);
}

void apply_a(const IslandSystem& s, const Eigen::VectorXd& x, Eigen::VectorXd& du, Eigen::VectorXd& y,
             IslandChunks& chunks) {
  apply_mjt(s, x, du, chunks);
  y.resize(s.rows);
  chunks.each(s.rows, [&](int r) { y[r] = s.sigma[r] * x[r] + row_velocity(s, r, du); });
}

void apply_a(const IslandSystem& s, const Eigen::VectorXd& x, Eigen::VectorXd& du, Eigen::VectorXd& y) {
  IslandChunks serial;
  apply_a(s, x, du, y, serial);
}

}  // namespace rbpart
