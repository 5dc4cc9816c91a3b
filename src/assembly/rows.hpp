#pragma once
// Constraint rows of one step (docs/design.md#dynamics), stored per field (structure of arrays). Each row
// acts on at most two dynamic bodies; a static body or the world is body index -1 and owns no unknowns. Row
// j's BLCP data: A = J M^-1 J^T + diag(sigma), q = J u* + b, lo <= lambda <= hi, where a friction row's
// bounds are +-mu * lambda[normal_of] of the same solve (the solver writes the final ones into lo, hi).
#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <vector>

namespace rbpart {

using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;

enum class RowKind : std::uint8_t { Normal, Friction, Joint };

// Index set of a row in the BLCP (docs/design.md#contact-problem): free, at its lower bound, at its upper
// bound.
enum class RowState : std::int8_t { Free = 0, Lower = 1, Upper = 2 };

struct Rows {
  std::vector<std::array<int, 2>> body;   // dynamic body (scene index) or -1
  std::vector<std::array<Vec6, 2>> jac;   // (linear, angular) Jacobian block per body slot
  std::vector<double> q;                  // J u* + b
  std::vector<double> lo, hi;             // bounds (friction rows: recomputed from their normal row)
  std::vector<double> sigma;              // regularisation (compliance/h^2 + floor), > 0
  std::vector<RowKind> kind;
  std::vector<int> normal_of;             // friction row -> its contact's normal row; else -1
  std::vector<double> mu;                 // friction coefficient (friction rows), else 0
  std::vector<std::uint64_t> key;         // persistent id for warm starts across steps
  // In: warm start; out: the solution.
  std::vector<double> lambda;
  std::vector<RowState> state;

  std::size_t size() const { return q.size(); }
  void clear();
  // n rows, each to be set before use (the rows in place keep their values).
  void resize(std::size_t n);
  // Sets row r anew: both Jacobian blocks zero, bounds, state and impulse those of a new row of its kind.
  void set(int r, RowKind kind, int body0, int body1, std::uint64_t key);
  // Appends a row set as by set(); returns its index.
  int add(RowKind kind, int body0, int body1, std::uint64_t key);
};

}  // namespace rbpart
