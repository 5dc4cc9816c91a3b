#pragma once
// One island's BLCP in local numbering (DESIGN.md §2-3): rows 0..rows-1 in the island's row order,
// bodies 0..bodies-1 in its body order. Holds J and M^-1 J^T per row slot, so that A is never
// needed explicitly for products: A x = Sigma x + J (M^-1 J^T x). Shared by the Newton solver and
// its backends (which build the body-space systems from it), PGS and the residual.
#include "assembly/rows.hpp"
#include "graph/islands.hpp"
#include "scene/bodies.hpp"
#include "solve/bounds.hpp"
#include "solve/island_chunks.hpp"

#include <Eigen/Core>

#include <array>
#include <vector>

namespace rbpart {

struct IslandSystem {
  int rows = 0, bodies = 0;
  const int* global_rows = nullptr;          // local row -> Rows index (into Islands::rows)
  const int* global_bodies = nullptr;        // local body -> scene body (into Islands::bodies)
  std::vector<std::array<int, 2>> body;      // local body per slot, -1 = none (slot 0 first)
  std::vector<std::array<Vec6, 2>> jac;      // J block per slot
  std::vector<std::array<Vec6, 2>> mjac;     // M^-1 J^T block per slot
  std::vector<double> inv_mass;              // per local body
  std::vector<Mat3> inv_inertia;             // per local body (world)
  Eigen::VectorXd q, lo, hi, sigma;
  Eigen::VectorXd diag;                      // A_jj = (J M^-1 J^T)_jj + sigma_j
  std::vector<int> normal_of;                // local; -1 if none
  std::vector<double> mu;
  // Row slots per body (CSR): entries r * 2 + slot, rows increasing.
  std::vector<int> body_slot_offset, body_slots;
  std::vector<int> slot_fill;  // gather()'s scratch, kept so that gathering again allocates nothing

  // Gathers island `island`. `local_row` must map every Rows index of the island to its local
  // index (the caller fills it for all islands at once; islands own disjoint rows). A row whose two
  // slots name the same body is folded into slot 0. Bodies and rows are gathered in `chunks`.
  void gather(const Rows& rows, const Bodies& bodies, const Islands& islands, int island,
              const std::vector<int>& local_row, IslandChunks& chunks);
  void gather(const Rows& rows, const Bodies& bodies, const Islands& islands, int island,
              const std::vector<int>& local_row);

  FrictionCoupling coupling() const { return {&normal_of, &mu}; }
};

// A of an island, dense (both triangles): a reference for tests.
void build_dense(const IslandSystem& s, Eigen::MatrixXd& a);

// Island indices by decreasing row count (ties by index), so that one big island does not start
// last on a busy thread when islands are solved in parallel. Into `order`, whose capacity it reuses.
void largest_islands_first(const Islands& islands, std::vector<int>& order);
std::vector<int> largest_islands_first(const Islands& islands);

// Local index of every row within its island (-1 for rows in no island), for IslandSystem::gather.
void local_row_index(const Rows& rows, const Islands& islands, std::vector<int>& local);
std::vector<int> local_row_index(const Rows& rows, const Islands& islands);

// M of every body of the island: (m I3, I_world), the inverse of its M^-1 blocks.
void body_masses(const IslandSystem& s, std::vector<Mat6>& mass);

// du = M^-1 J^T x per body (6 * bodies entries: linear, angular); by bodies in `chunks`.
void apply_mjt(const IslandSystem& s, const Eigen::VectorXd& x, Eigen::VectorXd& du, IslandChunks& chunks);
void apply_mjt(const IslandSystem& s, const Eigen::VectorXd& x, Eigen::VectorXd& du);
// (J du)_j.
inline double row_velocity(const IslandSystem& s, int j, const Eigen::VectorXd& du) {
  double v = 0;
  for (int slot = 0; slot < 2; ++slot) {
    const int b = s.body[j][slot];
    if (b >= 0) v += s.jac[j][slot].dot(du.segment<6>(6 * b));
  }
  return v;
}
// y = A x = Sigma x + J M^-1 J^T x; du is scratch. Bodies, then rows, in `chunks`.
void apply_a(const IslandSystem& s, const Eigen::VectorXd& x, Eigen::VectorXd& du, Eigen::VectorXd& y,
             IslandChunks& chunks);
void apply_a(const IslandSystem& s, const Eigen::VectorXd& x, Eigen::VectorXd& du, Eigen::VectorXd& y);

}  // namespace rbpart
