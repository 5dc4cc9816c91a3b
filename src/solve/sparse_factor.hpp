#pragma once
// SuiteSparse factorisations of a fixed-pattern sparse matrix held in caller-owned compressed
// columns (DESIGN.md §3): CHOLMOD's supernodal Cholesky for symmetric positive definite systems
// and KLU's sparse LU for the non-symmetric ones (tied friction rows). Both analyse the pattern
// once and then refactor numerically as often as the values change. Each object owns its own
// workspace (neither library's common block is thread safe), so islands solve in parallel with one
// object each.
#include <memory>

namespace rbpart {

// The arrays a factorisation reads: n columns, colptr[n + 1], rowind[colptr[n]] sorted within each
// column, values beside rowind. They must outlive the factorisation and keep their addresses.
struct CscView {
  int n = 0;
  const int* colptr = nullptr;
  const int* rowind = nullptr;
  const double* values = nullptr;
};

class CholmodFactor {
 public:
  CholmodFactor();
  ~CholmodFactor();
  CholmodFactor(const CholmodFactor&) = delete;
  CholmodFactor& operator=(const CholmodFactor&) = delete;
  // Symbolic analysis of the pattern; only the lower triangle of `a` is read (entries above the
  // diagonal may be stored and are ignored).
  void analyze(const CscView& a);
  // Numeric factorisation of the current values; false if not positive definite.
  bool factorize();
  // x <- A^-1 x.
  void solve(double* x);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

class KluFactor {
 public:
  KluFactor();
  ~KluFactor();
  KluFactor(const KluFactor&) = delete;
  KluFactor& operator=(const KluFactor&) = delete;
  // Symbolic analysis (block triangular form, AMD ordering) of the pattern of `a`, both triangles.
  void analyze(const CscView& a);
  // Symbolic analysis for an LU that eliminates the first `interior` unknowns I first (AMD on their
  // own block) and the others K last, in order, with no block triangular form: the trailing block
  // of such an LU is the Schur complement of K (trailing_schur()). factorize() then factors the
  // matrix with K's rows scaled by 2^-200 (exactly; in place, restored after), so that partial
  // pivoting takes the pivots of I's columns from I's rows, as an LU of A_II alone would.
  void analyze(const CscView& a, int interior);
  // Numeric LU of the current values with partial pivoting; false if singular.
  bool factorize();
  // The next factorize() searches its pivots afresh instead of reusing the last ones.
  void repivot();
  // x <- A^-1 x for `columns` vectors stored one after another (KLU takes them four at a time).
  void solve(double* x, int columns = 1);
  // After factorize() of a matrix analysed with `interior`: schur (column-major, |K| x |K|) <-
  // A_KK - A_KI A_II^-1 A_IK, read off the LU's trailing block, whose factors it keeps for
  // forward_interior() and back_interior(). False if a pivot of I's columns came from a row of K
  // (A_II numerically singular): the trailing block is then not that Schur complement.
  bool trailing_schur(double* schur);
  // After trailing_schur(): b (n entries) <- [y_I; b_K - A_KI A_II^-1 b_I], the LU's forward
  // substitution over I's columns (y_I is what back_interior() takes).
  void forward_interior(double* b) const;
  // After forward_interior(b): b <- [A_II^-1 (b_I - A_IK u_K); u_K] for the given u_K.
  void back_interior(double* b, const double* u_k) const;

 private:
  bool factorize_values();  // the LU of the values as they stand
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rbpart
