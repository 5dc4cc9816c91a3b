#pragma once
// The one interface through which the Newton solver (newton.hpp) reaches the matrix (DESIGN.md §3).
// A Newton state fixes, for every row of the island, which linear equation it obeys (a piece of
// the natural map):
//   Free    (A x)_j + shift_j x_j - tie_j x_n(j) = g_j
//                                            (w_j = 0 for tie = shift = 0; the interior-point phase
//                                             shifts every row and couples friction to its normal)
//   Fixed   x_j = g_j                        (at a bound given as a number)
//   Tied    x_j - tie_j x_n(j) = g_j         (friction at the edge of its box: lambda_t = +-mu lambda_n;
//                                             its normal row n(j) is Free)
// A backend factors the system of a piece and solves it for any right-hand side g. The monolithic
// backend (monolithic.hpp) factors the island in body space; the substructured one (DESIGN.md §7)
// will factor it by parts. Products with A are the problem's own (island_system.hpp, apply_a).
#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace rbpart {

enum class RowEquation : std::uint8_t { Free, Fixed, Tied };

struct Piece {
  std::vector<RowEquation> equation;
  Eigen::VectorXd tie;    // Tied rows: +-mu_j; Free rows: a coupling to the normal (usually 0)
  Eigen::VectorXd shift;  // Free rows: proximal shift (>= 0)
};

class LinearSystem {
 public:
  virtual ~LinearSystem() = default;
  // Factors the system of `piece`; false if it is numerically singular.
  virtual bool factor(const Piece& piece) = 0;
  // x = E^-1 g for the system E of the last successful factor(). The body-space form loses digits
  // to the small regularisation, so the caller refines against the exact equations.
  virtual void solve(const Eigen::VectorXd& g, Eigen::VectorXd& x) = 0;
};

}  // namespace rbpart
