#pragma once
// Interior-point phase of the Newton solver (newton.hpp): Mehrotra's predictor-corrector method on
// the island's complementarity problem, run when the warm start's Newton state is wrong (an
// impact, a new pile). It needs no Newton state, so it is not stalled by the kinks of the natural
// map, and it hands the Newton iteration a point whose state is (nearly) the answer's.
//
// Every bound of row j is a slack s >= 0 with a multiplier z >= 0, s z = tau -> 0:
//   lower: s = lambda_j - lo_j,  upper: s = hi_j - lambda_j  (friction: lo, hi = -+mu lambda_n),
//   A lambda + q - z_lo + z_hi = 0  (w pushes outward at an active bound).
// Eliminating the multipliers, a step solves
//   (A dlambda)_j + (z_lo/s_lo + z_hi/s_hi) dlambda_j + mu_j (z_lo/s_lo - z_hi/s_hi) dlambda_n(j) = r_j,
// every row Free with a shift, friction rows coupled to their normal (linear_system.hpp): one
// factorisation of the backend. Without the coupling (the friction box lagged a step) the method
// stalls on sliding contacts, whose z_hi / s_hi is large.
#include "solve/island_system.hpp"
#include "solve/linear_system.hpp"

#include <Eigen/Core>

#include <vector>

namespace rbpart {

// Mehrotra's method one factorisation at a time, so that the Newton solver can try its exact step
// between two interior-point steps.
class InteriorPoint {
 public:
  // A cold start: lambda = 0 moved into the interior (normals and bounded rows a tenth of the
  // island's free velocity scale away from their bounds, friction inside half its box), and the
  // multipliers. (Warm starts were measured and not kept: newton/experiments/.)
  void start(const IslandSystem& s);
  // One predictor-corrector step (one factorisation); returns its length in (0, 1], or 0 if the
  // system failed to factor, the step is not finite, or complementarity is met to round-off (no
  // step is then taken).
  // Its loops over rows and bodies run in `chunks`.
  double step(LinearSystem& system, IslandChunks& chunks);
  const Eigen::VectorXd& lambda() const { return lambda_; }
  // The state the last predictor indicates (Tapia's indicators: El-Bakry, Tapia & Zhang, SIAM
  // Review 36, 1994): a bound is active if the predictor would cut its slack by more than half,
  // that is when the slack falls faster than its multiplier (ds/s < dz/z, as z ds + s dz = -z s);
  // a friction row active at a bound is at -+mu lambda_n. Every row Free before the first step
  // (closed rows Lower). A better guess of the answer's state than the natural map at the iterate:
  // a row whose slack and multiplier are both still small looks free there, while the predictor,
  // which sees how the island's other rows respond, already takes it to its bound.
  const std::vector<RowState>& indicated() const { return indicated_; }

  // Per row: no interior (held at its bound), a lower bound, an upper bound (friction: both).
  struct Sides {
    std::vector<char> closed, lo, hi;
  };

 private:
  const IslandSystem* s_ = nullptr;
  double gap0_ = 0;
  Sides has_;
  int bounds_ = 0;  // the slacks: the rows' lower and upper bounds
  Piece piece_;
  std::vector<RowState> indicated_;
  Eigen::VectorXd lambda_, zlo_, zhi_, slo_, shi_, r_, d_, w_, du_, dzlo_, dzhi_, dslo_, dshi_, trial_;
};

}  // namespace rbpart
