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
  // Numeric LU of the current values with partial pivoting; false if singular.
  bool factorize();
  // The next factorize() searches its pivots afresh instead of reusing the last ones.
  void repivot();
  // x <- A^-1 x for `columns` vectors stored one after another (KLU takes them four at a time).
  void solve(double* x, int columns = 1);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rbpart
