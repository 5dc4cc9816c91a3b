#pragma once
// The fixed-bounds BLCP core (DESIGN.md §3): w = A lambda + q, lo <= lambda <= hi, A symmetric
// positive definite, solved exactly by block principal pivoting (Judice & Pires 1994) with Murty's
// single-swap safeguard. When pivoting stalls with many infeasible rows (box friction on sliding
// piles), it restarts from the index sets of an interior-point solve (solve/interior_point.hpp)
// before resorting to Murty's one-row-per-factorisation swaps. The matrix is reached only through
// BlcpMatrix (products with A, factor and solve with the free block A_FF), so the monolithic solver,
// its sparse backends and the interface problem of the substructured solver (DESIGN.md §7) share
// this one implementation. The friction outer loop (friction_passes) is written once on top of any
// fixed-bounds solve.
#include "assembly/rows.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
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
    valid_ = factor(free, nullptr);
    return valid_ ? 1 : -1;
  }
  // Factors A_FF + diag(shift_F) (shift >= 0) for the interior-point restart; solve() then applies
  // its inverse. Not cached: the next prepare() refactors.
  bool prepare_shifted(const std::vector<char>& free, const Eigen::VectorXd& shift) {
    valid_ = false;
    return factor(free, &shift);
  }

 protected:
  // Factors A_FF (+ diag(shift_F) if shift is given); false if not numerically positive definite.
  virtual bool factor(const std::vector<char>& free, const Eigen::VectorXd* shift) = 0;
  // Backends whose A changes in place must call this.
  void invalidate() { valid_ = false; }

 private:
  std::vector<char> factored_;
  bool valid_ = false;
};

struct BlcpSettings {
  int max_iterations = 500;  // pivoting iterations per fixed-bounds solve
  int murty_after = 3;       // iterations without fewer infeasible rows before Murty's single swaps
  // Feasibility tolerance, relative to s = max_j |q_j|: a clamped row is infeasible when its w has
  // the wrong sign by more than tol = tolerance * s, a free row when lambda leaves its bounds by more
  // than tol / A_jj. tol never drops below the round-off of w = A lambda + q (64 eps max_j A_jj
  // |lambda_j|), so that rows do not swap on noise. At convergence the scaled natural-map residual
  // is below tol / s: 1e-12, unless redundant rows fight over an inconsistent q (lambda ~ q / sigma).
  double tolerance = 1e-12;
  // A stall with more infeasible rows than this restarts, once per solve, from the index sets of an
  // interior-point solve (solve/interior_point.hpp) instead of Murty's one-row-per-factorisation
  // swaps; Murty's rule remains the safeguard that guarantees termination.
  int murty_max_infeasible = 8;
  int interior_point_iterations = 60;
};

struct BlcpResult {
  int iterations = 0;      // pivoting iterations (each one solve with A_FF)
  int factorizations = 0;  // factorisations (reused factors not counted; interior-point ones counted)
  bool murty = false;      // Murty's rule was needed
  bool restarted = false;  // the interior-point restart was needed
  bool converged = false;  // false: lambda/state hold the iterate (pivoting or interior-point) of
                           // smallest natural-map residual, projected onto the bounds
};

struct InteriorPointWorkspace {
  Eigen::VectorXd x, sl, su, zl, zu, g, dx, dzl, dzu, shift, rhs;
  std::vector<char> free;
};

// Buffers of solve_blcp, kept across calls so that the pivoting loop does not allocate.
struct BlcpWorkspace {
  Eigen::VectorXd w, ax, delta, best_lambda;
  std::vector<char> free;
  InteriorPointWorkspace interior;
};

// Solves the BLCP (A, q, lo, hi) with fixed bounds, warm started from `state` (the values of lambda
// are not used: the sets determine the iterate). Rows with lo == hi are clamped throughout; a row
// never clamps at an infinite bound. On return lambda and state are the solution and its sets, and
// ws.w = A lambda + q.
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

struct FrictionPassResult {
  int passes = 0;
  bool solved = true;    // every fixed-bounds solve converged
  bool settled = false;  // the normal impulses settled within the tolerance (not the pass cap)
};

// The friction outer loop of DESIGN.md §3, shared by every direct solver: the friction bounds are
// fixed for one BLCP solve (`solve_fixed()`, which reads lo/hi, updates lambda and returns whether
// it converged) and recomputed from the new normal impulses between passes; the first pass uses
// the normal impulses in `lambda` on entry (the warm start). Stops after `max_passes` or when no
// normal impulse with friction rows changed by more than `tolerance` * max |lambda_n|; a BLCP without
// friction rows takes one pass. `previous` is scratch.
template <class SolveFixed>
FrictionPassResult friction_passes(const FrictionCoupling& f, Eigen::VectorXd& lambda, std::vector<RowState>& state,
                                   Eigen::VectorXd& lo, Eigen::VectorXd& hi, int max_passes, double tolerance,
                                   Eigen::VectorXd& previous, SolveFixed&& solve_fixed) {
  const std::vector<int>& normal_of = *f.normal_of;
  const bool has_friction = std::any_of(normal_of.begin(), normal_of.end(), [](int n) { return n >= 0; });
  FrictionPassResult result;
  previous = lambda;  // the normal impulses the bounds are taken from
  for (int pass = 0; pass < std::max(1, max_passes); ++pass) {
    update_friction_bounds(f, previous, lo, hi, state);
    ++result.passes;
    if (!solve_fixed()) {
      result.solved = false;
      return result;
    }
    double change = 0, size = 0;
    for (std::size_t j = 0; j < normal_of.size(); ++j) {
      if (normal_of[j] < 0) continue;
      const int n = normal_of[j];
      change = std::max(change, std::abs(lambda[n] - previous[n]));
      size = std::max(size, std::abs(lambda[n]));
    }
    if (!has_friction || change <= tolerance * size) {
      result.settled = true;
      return result;
    }
    // Next bounds: the new normal impulses, averaged with the previous ones after the first passes.
    // Redundant contacts (a face on a face) share their load through the small regularisation, and
    // per-point bounds fed straight back can then oscillate between two load shares; the average
    // has the same fixed point and damps the oscillation.
    const double keep = pass < 2 ? 0.0 : 0.5;
    for (std::size_t j = 0; j < normal_of.size(); ++j)
      if (normal_of[j] >= 0) previous[normal_of[j]] = keep * previous[normal_of[j]] + (1 - keep) * lambda[normal_of[j]];
  }
  return result;
}

}  // namespace rbpart
