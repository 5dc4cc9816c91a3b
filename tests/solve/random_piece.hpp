#pragma once
// Newton pieces (solve/linear_system.hpp) for the backends' tests: random ones, and a piece's
// system E as a dense matrix, row by row from linear_system.hpp's definition.
#include "solve/island_system.hpp"
#include "solve/linear_system.hpp"

#include <Eigen/Core>

#include <random>

namespace rbpart::testing {

inline Eigen::MatrixXd piece_matrix(const IslandSystem& s, const Piece& piece) {
  Eigen::MatrixXd a;
  build_dense(s, a);
  Eigen::MatrixXd e = Eigen::MatrixXd::Zero(s.rows, s.rows);
  for (int j = 0; j < s.rows; ++j) {
    switch (piece.equation[j]) {
      case RowEquation::Free: e.row(j) = a.row(j); e(j, j) += piece.shift[j]; break;
      case RowEquation::Fixed: e(j, j) = 1; break;
      case RowEquation::Tied: e(j, j) = 1; e(j, s.normal_of[j]) = -piece.tie[j]; break;
    }
  }
  return e;
}

// A random piece: normals free or fixed, friction free, tied (to a free normal) or fixed.
inline Piece random_piece(const IslandSystem& s, std::mt19937& rng, bool ties) {
  Piece p;
  p.equation.resize(s.rows);
  p.tie.setZero(s.rows);
  p.shift.setZero(s.rows);
  std::uniform_int_distribution<int> pick(0, 2);
  for (int j = 0; j < s.rows; ++j)
    if (s.normal_of[j] < 0) p.equation[j] = pick(rng) == 0 ? RowEquation::Fixed : RowEquation::Free;
  for (int j = 0; j < s.rows; ++j) {
    if (s.normal_of[j] < 0) continue;
    const int k = pick(rng);
    const bool normal_free = p.equation[s.normal_of[j]] == RowEquation::Free;
    p.equation[j] = k == 0 || !normal_free ? RowEquation::Fixed : k == 1 || !ties ? RowEquation::Free : RowEquation::Tied;
    if (p.equation[j] == RowEquation::Tied) p.tie[j] = (pick(rng) == 0 ? -1 : 1) * s.mu[j];
    if (p.equation[j] == RowEquation::Free && pick(rng) == 0) p.shift[j] = 1e-2 * s.diag[j];
  }
  return p;
}

}  // namespace rbpart::testing
