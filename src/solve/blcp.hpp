#pragma once
// The fixed-bounds BLCP core (DESIGN.md §3): w = A lambda + q, lo <= lambda <= hi, A symmetric
// positive definite, solved exactly. The BLCP is the optimality condition of the strictly convex
// box QP  min f(l) = 1/2 l^T A l + q^T l,  lo <= l <= hi,  whose minimiser is unique. Block principal
// pivoting (Judice & Pires 1994) runs first: from warm-start sets it usually finishes in one or two
// iterations. It is not monotone, and on piles with box friction and redundant contacts (A's
// eigenvalue ratio ~1e-8) it cycles; when it stops reaching new lows of infeasible rows, a
// projected Newton method on the QP (Bertsekas 1982) takes over from the best feasible point seen:
// every iteration solves with A_FF on the current face and takes a projected step that decreases
// f, so it cannot cycle, and its last step is the same exact face solve as pivoting's. On large
// BLCPs an interior-point method on the QP runs first and gives projected Newton its start. The
// matrix is reached only through BlcpMatrix (products with A, factor and solve with the free block
// A_FF, or with A_FF plus a diagonal shift for the interior-point phase), so the monolithic
// solver, its sparse backends and the interface problem of the substructured solver (DESIGN.md §7)
// share this one implementation. The friction outer loop (friction_passes) is written once on top
// of any fixed-bounds solve.
#include "assembly/rows.hpp"

#include <Eigen/Core>
#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <unordered_set>
#include <vector>

namespace rbpart {

// max_j |v_j| by a plain loop (Eigen's vectorised reduction trips GCC 12's -Wmaybe-uninitialized
// under -march=native with AVX-512).
inline double max_abs(const Eigen::VectorXd& v) {
  double m = 0;
  for (Eigen::Index j = 0; j < v.size(); ++j) m = std::max(m, std::abs(v[j]));
  return m;
}

// A as the pivoting uses it. factor() is called only when the free set changed (see prepare()).
class BlcpMatrix {
 public:
  virtual ~BlcpMatrix() = default;
  virtual int size() const = 0;
  // A_jj (> 0): scales the impulse tolerances of row j.
  virtual const Eigen::VectorXd& diagonal() const = 0;
  // y = A x.
  virtual void multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) = 0;
  // x_F <- A_FF^-1 x_F for the free set of the last successful factorisation; entries of x outside
  // F are left as they are.
  virtual void solve(Eigen::VectorXd& x) = 0;

  // Makes A_FF factored for F = {j : free[j] != 0}, refactoring only if F changed since the last
  // call (the friction passes and the substructured iteration often repeat a set). Returns 1 if it
  // factored, 0 if it reused the factor, -1 if A_FF is not numerically positive definite.
  int prepare(const std::vector<char>& free) {
    if (valid_ && free == factored_) return 0;
    factored_ = free;
    valid_ = factor(free);
    return valid_ ? 1 : -1;
  }
  // Factors A_FF + diag(shift)_FF for the interior-point phase of solve_blcp; solve() then solves
  // with it. False if the backend has no such factorisation (the phase is then skipped) or it is
  // not numerically positive definite. The next prepare() refactors.
  bool prepare_shifted(const std::vector<char>& free, const Eigen::VectorXd& shift) {
    valid_ = false;
    return factor_shifted(free, shift);
  }
  // The coupled friction step's tied system (tied_factor.hpp): rows with free[j] as in A_FF, row
  // sliding[i] tied to its (free) normal, x_t - coef[i] x_n = r_t, other rows x_j = r_j. False if
  // the backend has no such factorisation (the step then solves it iteratively around A_FF) or it
  // failed. It does not change the factor of A_FF.
  virtual bool factor_tied(const std::vector<char>& /*free*/, const std::vector<int>& /*sliding*/,
                           const std::vector<double>& /*coef*/) {
    return false;
  }
  // x <- E^-1 x for the tied system of the last successful factor_tied().
  virtual void solve_tied(Eigen::VectorXd& /*x*/) { throw std::logic_error("solve_tied: no tied factorisation"); }
 protected:
  // Factors A_FF; false if not numerically positive definite.
  virtual bool factor(const std::vector<char>& free) = 0;
  virtual bool factor_shifted(const std::vector<char>& /*free*/, const Eigen::VectorXd& /*shift*/) { return false; }
  // Backends whose A changes in place must call this.
  void invalidate() { valid_ = false; }

 private:
  std::vector<char> factored_;
  bool valid_ = false;
};

struct BlcpSettings {
  int max_iterations = 500;  // iterations (each one solve with A_FF) per fixed-bounds solve
  int pivot_patience = 3;    // pivoting iterations without fewer infeasible rows before projected Newton
  // Smallest BLCP on which a stall of pivoting runs the interior-point phase before projected
  // Newton (small ones finish in a few cheap factorisations without it).
  int interior_min_rows = 1000;
  // Feasibility tolerance, relative to s = max_j |q_j|: a clamped row is infeasible when its w has
  // the wrong sign by more than tol = tolerance * s, a free row when lambda leaves its bounds by more
  // than tol / A_jj or |w| > tol. tol never drops below the round-off of w = A lambda + q
  // (64 eps max_j A_jj |lambda_j|), so that rows do not swap on noise. At convergence the scaled
  // natural-map residual is below tol / s: 1e-12, unless redundant rows fight over an inconsistent q
  // (lambda ~ q / sigma).
  double tolerance = 1e-12;
  // Warm paths of the coupled friction step on islands of 3000 rows or more (SolverParams).
  int coupled_paths = 2;
};

struct BlcpResult {
  int iterations = 0;      // iterations (each one solve with A_FF)
  int factorizations = 0;  // factorisations (reused factors not counted)
  bool interior = false;   // pivoting stalled and the interior-point phase ran
  bool newton = false;     // pivoting stalled again and projected Newton finished the solve
  bool converged = false;  // false: lambda/state hold the feasible iterate of least f
};

// Buffers of solve_blcp, kept across calls so that the iterations do not allocate.
struct BlcpWorkspace {
  Eigen::VectorXd w, ax, delta, x, gx, step;
  // Interior-point phase: iterate, its gradient, slacks, multipliers, Theta, steps (and the predictor's), rhs.
  Eigen::VectorXd ix, ig, sl, su, zl, zu, theta, dx, dzl, dzu, dx_aff, dzl_aff, dzu_aff, rhs;
  std::vector<char> free;
};

// Solves the BLCP (A, q, lo, hi) with fixed bounds, warm started from `state` (pivoting's first
// sets) and from the values in `lambda` (projected onto the bounds, one of the candidate starts of
// projected Newton; non-finite values count as 0). Rows with lo == hi are clamped throughout; a row
// never clamps at an infinite bound. On return lambda and state are the solution and its sets, and
// ws.w = A lambda + q. Not converged (iteration cap): lambda is feasible and f(lambda) <= f of the
// projection of 0, so an unfinished solve never does more work on the bodies than no impulse.
BlcpResult solve_blcp(BlcpMatrix& A, const Eigen::VectorXd& q, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi,
                      Eigen::VectorXd& lambda, std::vector<RowState>& state, const BlcpSettings& settings,
                      BlcpWorkspace& ws);

// Box friction coupling (DESIGN.md §2): row j with normal_of[j] >= 0 has bounds
// +-mu[j] * max(0, lambda[normal_of[j]]). Indices are the BLCP's own.
struct FrictionCoupling {
  const std::vector<int>* normal_of = nullptr;
  const std::vector<double>* mu = nullptr;
};

inline void set_friction_bounds(const FrictionCoupling& f, const Eigen::VectorXd& lambda, Eigen::VectorXd& lo,
                                Eigen::VectorXd& hi) {
  const std::vector<int>& normal_of = *f.normal_of;
  for (std::size_t j = 0; j < normal_of.size(); ++j) {
    if (normal_of[j] < 0) continue;
    const double bound = (*f.mu)[j] * std::max(0.0, lambda[normal_of[j]]);
    lo[j] = -bound;
    hi[j] = bound;
  }
}

// As set_friction_bounds, and a friction row whose box opens from [0, 0] (its normal impulse was
// zero) starts the next solve free: sticking is the physical first guess, whereas the clamped
// state it had says nothing (a whole pile of new contacts at -mu lambda_n is a start from which
// block pivoting wanders).
inline void update_friction_bounds(const FrictionCoupling& f, const Eigen::VectorXd& lambda, Eigen::VectorXd& lo,
                                   Eigen::VectorXd& hi, std::vector<RowState>& state) {
  const std::vector<int>& normal_of = *f.normal_of;
  for (std::size_t j = 0; j < normal_of.size(); ++j) {
    if (normal_of[j] < 0) continue;
    const bool was_closed = !(lo[j] < hi[j]);
    const double bound = (*f.mu)[j] * std::max(0.0, lambda[normal_of[j]]);
    lo[j] = -bound;
    hi[j] = bound;
    if (was_closed && bound > 0) state[j] = RowState::Free;
  }
}

// Buffers of coupled_friction_step, kept across calls.
struct CoupledWorkspace {
  std::vector<RowState> sets, start_state;    // the path's index sets; sets of a warm start
  std::vector<char> base_free;                // free set of the factored base
  std::vector<signed char> base_sign;         // +-1 on rows the base ties to their normal, else 0
  std::vector<int> column_of, column_row;     // Woodbury columns: row -> column, column -> row
  std::vector<int> friction_start, friction_rows;  // friction rows of each row (CSR)
  std::unordered_set<std::uint64_t> visited;  // hashes of the visited (sets, direction) pairs
  Eigen::VectorXd start, d, e, lambda, w, dl, dw, ga, aga, gd, agd, g, ag, r, t, at, z, lo, hi;
  Eigen::VectorXd v, vb, bc, zb;              // capacitance updates
  Eigen::MatrixXd y, ay, capacitance, inverse;  // M_b^-1 e_j, A M_b^-1 e_j per column; C = I + U^T Y, C^-1
  // Row j of y on rows with mixed_free[j], of ay elsewhere: a piece's direction needs d lambda on
  // its free rows and d w on the others only, so one product with this replaces two.
  Eigen::MatrixXd mixed;
  std::vector<char> mixed_free;
  std::vector<int> violated;                  // rows an end point violates
  std::vector<int> sliding;                   // sliding rows of the base (tied, or krylov()'s)
  std::vector<double> tie;                    // their coefficients: lambda_t = tie * lambda_n
  Eigen::VectorXd kb, kr, kx, kax, kcs, ksn, kgamma;  // GMRES of a jump's solves
  Eigen::MatrixXd kv, ku, kau, kh;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu;
  BlcpWorkspace blcp;                         // fixed-bounds solves of restarts
  int factorizations = 0;  // factorisations over all calls (reused factors not counted)
  int tied_factorizations = 0;  // of them, of tied systems (BlcpMatrix::factor_tied)
  int events = 0;          // pivots along the paths over all calls
  int jumps = 0;           // calls solved by block pivots on the coupled problem, with no path
  int cold_starts = 0;     // calls that needed the cold start
};

// Exact solve of the coupled friction BLCP (DESIGN.md §3: friction bounds +-mu lambda_n of the row's
// own normal impulse). First a jump: block pivots (Judice & Pires) on the coupled problem's own
// equations, from the fixed-bounds solution's sets with its sliding rows tied to their normals
// (lambda_t = +-mu lambda_n), each solved by GMRES on the sliding rows around one factorisation of
// A_FF. They have no guarantee of ending, so after a few rounds, or once they stop reducing the
// violated rows, the guaranteed method runs: complementary pivoting along a piecewise-linear path
// (Lemke's method in the BLCP's own variables). The path follows the solutions of the deformed problem H(s):
//   normal rows  w_j + s d_j  complementary to lambda_j >= 0 (other rows with their fixed bounds),
//   friction     |lambda_t| <= mu lambda_n + s e_t, e_t >= 0, with w_t + s d_t,
// from s = 1 to s = 0 (the problem itself). On a piece the index sets are fixed and lambda is affine
// in s; where a row reaches a bound or its w changes sign it pivots, and the direction of s is
// whatever keeps that row feasible (s may rise for a while). Every piece solves one linear system
// with sliding rows tied to their normals (lambda_t = +-(mu lambda_n + s e_t)), by Woodbury on a
// single factorisation of A_FF: a pivot adds at most one column (one solve), not a factorisation.
// Warm start: d and e make the fixed-bounds solution in `lambda`/`state` (bounds lo/hi) the
// solution of H(1), so the path starts from the last pass's sets. That path can close on itself;
// then the cold start runs: every normal at 0 with d_n = A_nn, e_t = mu_t, the only unbounded
// piece (for s large), from which, with A symmetric positive definite, the path cannot escape to
// another unbounded piece (the copositivity argument of Stewart & Trinkle 1996 for this LCP) and
// must reach s = 0. The answer is polished by refinement against A and accepted only if it
// satisfies the BLCP with the friction bounds of its own normal impulses (the tolerance of
// BlcpSettings): then lambda, state, lo and hi are replaced and true is returned; otherwise
// nothing changes (numerical failure, the event cap).
//
// The paths are not tried (false, nothing changed) when the warm start has more than
// kCoupledMaxSliding sliding friction rows (clamped, with an open normal): each one is a Woodbury
// column from the first piece on, and the dense capacitance then costs O(k^2) per pivot and O(k^3)
// per rebuild. The steps it solved on forming 200-rock piles started with at most 550 such rows; a
// landing 600-rock pile starts with ~2700, where it failed on every step after 2-280 s.
constexpr int kCoupledMaxSliding = 1024;
bool coupled_friction_step(BlcpMatrix& A, const Eigen::VectorXd& q, Eigen::VectorXd& lo, Eigen::VectorXd& hi,
                           const FrictionCoupling& f, Eigen::VectorXd& lambda, std::vector<RowState>& state,
                           const BlcpSettings& settings, CoupledWorkspace& ws);

struct FrictionPassResult {
  int passes = 0;
  bool solved = true;    // every fixed-bounds solve converged
  bool settled = false;  // the coupled BLCP is solved (coupled step or settled normal impulses)
};

// Mismatch, relative to max |lambda_n|, below which a pass's solution solves the coupled BLCP up to
// round-off. Redundant contacts leave a null wrench that only the sigma floor (1e-6 of the diagonal)
// resolves, so round-off moves the normal impulses by about eps * 1e6 ~ 2e-10 of their size (1.1e-10
// seen on a box resting on four corners). Its residual is measured, not assumed.
constexpr double kSettledChange = 1e-9;

// How far a pass's solution (solved with the friction bounds it was given) is from solving the
// coupled BLCP, whose bounds come from its own normal impulses: the largest natural-map residual
// |lambda_j - clamp(lambda_j - w_j / A_jj, -b_j, b_j)| of a friction row under its new bound
// b_j = mu_j max(0, lambda_n). A sliding row needs its bound to stay put, a sticking row only needs
// to lie within it, and a row whose box was closed (lambda_n was 0) needs no slip (w_j = 0) or no
// new bound. So normal impulses may move where the contact does not slip, as the load shares of a
// resting pile's redundant contacts do from step to step, without any effect on the answer.
// `w` = A lambda + q.
inline double friction_mismatch(const FrictionCoupling& f, const Eigen::VectorXd& lambda, const Eigen::VectorXd& w,
                                const Eigen::VectorXd& diag) {
  const std::vector<int>& normal_of = *f.normal_of;
  double mismatch = 0;
  for (std::size_t j = 0; j < normal_of.size(); ++j) {
    if (normal_of[j] < 0) continue;
    const double bound = (*f.mu)[j] * std::max(0.0, lambda[normal_of[j]]);
    mismatch = std::max(mismatch, std::abs(lambda[j] - std::clamp(lambda[j] - w[j] / diag[j], -bound, bound)));
  }
  return mismatch;
}

// The friction outer loop of DESIGN.md §3, shared by every direct solver: the friction bounds are
// fixed for one BLCP solve (`solve_fixed()`, which reads lo/hi, updates lambda and state and returns
// whether it converged; `fixed_w()` then gives its w = A lambda + q) and recomputed from the new
// normal impulses between passes; the first pass uses the normal impulses in `lambda` on entry (the
// warm start). A pass whose friction_mismatch is below `tolerance` * max |lambda_n| (kSettledChange
// at least, round-off) has solved the coupled BLCP to that tolerance. Otherwise `couple()` (the
// solver's coupled_friction_step, from that pass's solution) finishes the loop exactly; it is tried
// once, after the first such pass. Only if it fails do the plain passes go on, until `max_passes`
// or until the mismatch is within tolerance. A BLCP without friction rows takes one pass.
// `previous` is scratch.
template <class SolveFixed, class FixedW, class Couple>
FrictionPassResult friction_passes(const FrictionCoupling& f, const Eigen::VectorXd& diag, Eigen::VectorXd& lambda,
                                   std::vector<RowState>& state, Eigen::VectorXd& lo, Eigen::VectorXd& hi,
                                   int max_passes, double tolerance, Eigen::VectorXd& previous,
                                   SolveFixed&& solve_fixed, FixedW&& fixed_w, Couple&& couple) {
  const std::vector<int>& normal_of = *f.normal_of;
  const bool has_friction = std::any_of(normal_of.begin(), normal_of.end(), [](int n) { return n >= 0; });
  FrictionPassResult result;
  bool coupled_tried = false;
  previous = lambda;  // the normal impulses the bounds are taken from
  for (int pass = 0; pass < std::max(1, max_passes); ++pass) {
    update_friction_bounds(f, previous, lo, hi, state);
    ++result.passes;
    if (!solve_fixed()) {
      result.solved = false;
      return result;
    }
    double size = 0;
    for (std::size_t j = 0; j < normal_of.size(); ++j)
      if (normal_of[j] >= 0) size = std::max(size, std::abs(lambda[normal_of[j]]));
    const double change = friction_mismatch(f, lambda, fixed_w(), diag);
    if (!has_friction || change <= std::max(kSettledChange, tolerance) * size) {
      result.settled = true;
      return result;
    }
    if (!coupled_tried) {
      coupled_tried = true;
      if (couple()) {
        result.settled = true;
        return result;
      }
    }
    // Next bounds: the new normal impulses, averaged with the previous ones after the first passes.
    // Redundant contacts share their load through the small regularisation, and per-point bounds
    // fed straight back can then oscillate between two load shares; the average has the same
    // fixed point and damps the oscillation.
    const double keep = pass < 2 ? 0.0 : 0.5;
    for (std::size_t j = 0; j < normal_of.size(); ++j)
      if (normal_of[j] >= 0) previous[normal_of[j]] = keep * previous[normal_of[j]] + (1 - keep) * lambda[normal_of[j]];
  }
  return result;
}

}  // namespace rbpart
