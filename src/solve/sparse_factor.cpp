#include "solve/sparse_factor.hpp"

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <dlfcn.h>
#include <suitesparse/cholmod.h>
#include <suitesparse/klu.h>

#include <algorithm>
#include <mutex>
#include <vector>
#include <stdexcept>

#include "core/validate.hpp"
#include "solve/solve_check.hpp"

namespace rbpart {

// The matrix a factorisation was analysed for, as Eigen reads it.
static Eigen::Map<const Eigen::SparseMatrix<double>> eigen_view(const CscView& a) {
  return Eigen::Map<const Eigen::SparseMatrix<double>>(a.n, a.n, a.colptr[a.n], a.colptr, a.rowind, a.values);
}

// Debian's CHOLMOD is built with OpenMP and a fixed team size: each supernode's assembly wakes the
// team, and on these small factors the wake-ups (futex calls) cost more than they save - a third
// of the solve on a forming 100-rock pile (perf, with an earlier solver) - and they compete with the TBB
// workers that already run islands and sub-systems in parallel. So its parallel regions get one
// thread, and so does a threaded OpenBLAS.
//
// CHOLMOD's BLAS calls come from several TBB workers at once when islands are solved in parallel.
// A single-threaded OpenBLAS (Debian's libopenblas0-serial) has no locks: concurrent calls share
// its packing buffers and corrupt each other's results - two 60-step runs of the 200-rock pile at
// 2 threads parted at steps 36-40 - so with it every factorisation and solve holds one process-wide
// lock. Its pthreads build (what scripts/install_deps.sh installs) locks its buffers itself; its
// OpenMP build is not trusted with non-OpenMP callers. The runtimes are looked up rather than
// linked: another BLAS, or a CHOLMOD without OpenMP, has none of these symbols.
static bool blas_needs_lock() {
  static const bool lock = [] {
    using SetInt = void (*)(int);
    using GetInt = int (*)();
    if (auto set_levels = reinterpret_cast<SetInt>(dlsym(RTLD_DEFAULT, "omp_set_max_active_levels")))
      set_levels(0);
    const auto openblas_parallel = reinterpret_cast<GetInt>(dlsym(RTLD_DEFAULT, "openblas_get_parallel"));
    if (!openblas_parallel) return false;
    if (auto set_threads = reinterpret_cast<SetInt>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads")))
      set_threads(1);
    return openblas_parallel() != 1;  // 0: single-threaded, 1: pthreads, 2: OpenMP
  }();
  return lock;
}

// Holds the process-wide BLAS lock if the BLAS needs one, else nothing.
static std::unique_lock<std::mutex> blas_guard() {
  static std::mutex m;
  return blas_needs_lock() ? std::unique_lock<std::mutex>(m) : std::unique_lock<std::mutex>();
}

// --- CHOLMOD ---------------------------------------------------------------------------------------

struct CholmodFactor::Impl {
  cholmod_common c;
  CscView view;  // what `a` points to
  cholmod_sparse a{};
  cholmod_dense b{};
  cholmod_factor* l = nullptr;
  cholmod_dense *x = nullptr, *y = nullptr, *e = nullptr;
};

CholmodFactor::CholmodFactor() : impl_(std::make_unique<Impl>()) {
  blas_needs_lock();  // configures the runtimes before the first call
  cholmod_common& c = impl_->c;
  cholmod_start(&c);
  c.supernodal = CHOLMOD_SUPERNODAL;
  // AMD only (skips CHOLMOD's trial of METIS: the analysis runs every step), and coarser relaxed
  // supernode amalgamation than the defaults {4, 16, 48}: the factors here are small, and fewer,
  // larger dense blocks beat the BLAS call overhead (measured ~15% on 200-body piles).
  c.nmethods = 1;
  c.method[0].ordering = CHOLMOD_AMD;
  c.postorder = true;
  c.nrelax[0] = 16;
  c.nrelax[1] = 64;
  c.nrelax[2] = 128;
  c.zrelax[0] = 0.8;
  c.zrelax[1] = 0.3;
  c.zrelax[2] = 0.1;
  c.quick_return_if_not_posdef = true;
  c.print = 0;  // a matrix that is not positive definite is reported through the return value
}

CholmodFactor::~CholmodFactor() {
  Impl& m = *impl_;
  cholmod_free_factor(&m.l, &m.c);
  cholmod_free_dense(&m.x, &m.c);
  cholmod_free_dense(&m.y, &m.c);
  cholmod_free_dense(&m.e, &m.c);
  cholmod_finish(&m.c);
}

void CholmodFactor::analyze(const CscView& view) {
  Impl& m = *impl_;
  cholmod_free_factor(&m.l, &m.c);
  m.view = view;
  m.a = cholmod_sparse{};
  m.a.nrow = m.a.ncol = view.n;
  m.a.nzmax = view.colptr[view.n];
  m.a.p = const_cast<int*>(view.colptr);
  m.a.i = const_cast<int*>(view.rowind);
  m.a.x = const_cast<double*>(view.values);
  m.a.stype = -1;
  m.a.itype = CHOLMOD_INT;
  m.a.xtype = CHOLMOD_REAL;
  m.a.dtype = CHOLMOD_DOUBLE;
  m.a.sorted = true;
  m.a.packed = true;
  m.l = cholmod_analyze(&m.a, &m.c);
  if (!m.l) throw std::runtime_error("CHOLMOD analysis failed");
  m.b = cholmod_dense{};
  m.b.nrow = m.b.d = m.b.nzmax = view.n;
  m.b.ncol = 1;
  m.b.xtype = CHOLMOD_REAL;
  m.b.dtype = CHOLMOD_DOUBLE;
}

bool CholmodFactor::factorize() {
  Impl& m = *impl_;
  const std::unique_lock<std::mutex> hold = blas_guard();
  cholmod_factorize(&m.a, m.l, &m.c);
  return m.c.status == CHOLMOD_OK && m.l->minor == m.l->n;
}

void CholmodFactor::solve(double* x) {
  Impl& m = *impl_;
  m.b.x = x;
  const std::unique_lock<std::mutex> hold = blas_guard();
  if (!cholmod_solve2(CHOLMOD_A, m.l, &m.b, nullptr, &m.x, nullptr, &m.y, &m.e, &m.c))
    throw std::runtime_error("CHOLMOD solve failed");
  const double* solution = static_cast<const double*>(m.x->x);
  // Against the symmetric matrix of the lower triangle, the one CHOLMOD reads; x still holds b.
  RBPART_CHECK(solve_violation(Eigen::SparseMatrix<double>(eigen_view(m.view).selfadjointView<Eigen::Lower>()),
                               Eigen::Map<const Eigen::VectorXd>(solution, m.view.n),
                               Eigen::Map<const Eigen::VectorXd>(x, m.view.n)));
  std::copy_n(solution, m.l->n, x);
}

// --- KLU -------------------------------------------------------------------------------------------

// K's rows are scaled by this before an LU that eliminates K last (a power of two: exact).
constexpr double kTrailingScale = 0x1p-200;

// Column k of L below its unit diagonal, or of U above its diagonal (U's diagonal is the numeric
// object's Udiag), read where KLU keeps it: in LUbx[0] from offset start[k] (in doubles), length[k]
// row indices (in pivot order) padded to whole doubles, then as many values. This is the layout of
// klu_internal.h's GET_POINTER, which klu_extract reads; reading it in place spares a copy of the
// whole factor per factorisation when only a few trailing columns are wanted (a sixth of a
// part's factorisation time on the Large Rock Pile). Only for a factor of one block (no BTF).
struct KluColumn {
  const int* row;
  const double* value;
  int size;
};
static KluColumn klu_column(const klu_numeric* numeric, const int* start, const int* length, int k) {
  const double* at = static_cast<const double*>(numeric->LUbx[0]) + start[k];
  const int size = length[k];
  const std::size_t index_doubles = (size * sizeof(int) + sizeof(double) - 1) / sizeof(double);
  return {reinterpret_cast<const int*>(at), at + index_doubles, size};
}

struct KluFactor::Impl {
  klu_common c;
  CscView a;
  klu_symbolic* symbolic = nullptr;
  klu_numeric* numeric = nullptr;
  double full_rcond = 0;  // crude reciprocal condition of the last factorisation with pivoting
  int interior = -1;      // analyze(a, interior): I's size; -1 for analyze(a)
  std::vector<int> order;  // analyze(a, interior): the elimination order
  mutable std::vector<double> work;
  std::vector<int> trailing_entries;  // analyze(a, interior): the entries in K's rows
  Eigen::MatrixXd l, u, lu;           // trailing_schur()'s L_KK, U_KK and their product
};

KluFactor::KluFactor() : impl_(std::make_unique<Impl>()) {
  klu_defaults(&impl_->c);
  // No row scaling, and no check of the matrix on every factorisation (scale -1): its scan of every
  // entry took a tenth of the factorisations' time, and without it the replay sets (rbpart_bench_newton_replay)
  // kept their factorisation counts and unsettled islands (39/16/1/9/40 against 40/16/1/9/40).
  // Our matrices are assembled on a pattern KLU analysed once.
  impl_->c.scale = -1;
}

KluFactor::~KluFactor() {
  Impl& m = *impl_;
  klu_free_numeric(&m.numeric, &m.c);
  klu_free_symbolic(&m.symbolic, &m.c);
}

void KluFactor::analyze(const CscView& view) {
  Impl& m = *impl_;
  klu_free_numeric(&m.numeric, &m.c);
  klu_free_symbolic(&m.symbolic, &m.c);
  m.a = view;
  m.interior = -1;
  m.trailing_entries.clear();
  m.c.btf = 1;
  m.symbolic = klu_analyze(view.n, const_cast<int*>(view.colptr), const_cast<int*>(view.rowind), &m.c);
  if (!m.symbolic) throw std::runtime_error("KLU analysis failed");
}

void KluFactor::analyze(const CscView& view, int interior) {
  Impl& m = *impl_;
  klu_free_numeric(&m.numeric, &m.c);
  klu_free_symbolic(&m.symbolic, &m.c);
  m.a = view;
  m.interior = interior;
  // A block triangular form would reorder K among I.
  m.c.btf = 0;
  m.order.clear();
  if (interior > 0) {
    // AMD on I's own block: its entries' pattern, as KLU analyses it.
    std::vector<int> colptr(1, 0), rowind;
    for (int c = 0; c < interior; ++c) {
      for (int e = view.colptr[c]; e < view.colptr[c + 1]; ++e)
        if (view.rowind[e] < interior) rowind.push_back(view.rowind[e]);
      colptr.push_back(static_cast<int>(rowind.size()));
    }
    klu_symbolic* block = klu_analyze(interior, colptr.data(), rowind.data(), &m.c);
    if (!block) throw std::runtime_error("KLU analysis failed");
    m.order.assign(block->Q, block->Q + interior);
    klu_free_symbolic(&block, &m.c);
  }
  for (int j = interior; j < view.n; ++j) m.order.push_back(j);
  m.symbolic = klu_analyze_given(view.n, const_cast<int*>(view.colptr), const_cast<int*>(view.rowind), m.order.data(),
                                 m.order.data(), &m.c);
  if (!m.symbolic) throw std::runtime_error("KLU analysis failed");
  m.trailing_entries.clear();
  for (int e = 0; e < view.colptr[view.n]; ++e)
    if (view.rowind[e] >= interior) m.trailing_entries.push_back(e);
}

bool KluFactor::trailing_schur(double* schur) {
  Impl& m = *impl_;
  const int n = m.a.n, from = m.interior, k = n - from;
  if (!m.numeric || from < 0) throw std::logic_error("KluFactor::trailing_schur: no factor analysed with an interior");
  if (m.symbolic->nblocks != 1) throw std::logic_error("KluFactor::trailing_schur: a factor of more than one block");
  const int* pivot_row = m.numeric->Pnum;
  for (int i = 0; i < from; ++i)
    if (pivot_row[i] >= from) return false;
  // L_KK U_KK (L's unit diagonal included) is the Schur complement with its rows in pivot order:
  // row r of the product is row pivot_row[from + r] of A.
  const double* u_diagonal = static_cast<const double*>(m.numeric->Udiag);
  Eigen::MatrixXd &l = m.l, &u = m.u;
  l.setIdentity(k, k);
  u.setZero(k, k);
  for (int c = from; c < n; ++c) {
    const KluColumn lc = klu_column(m.numeric, m.numeric->Lip, m.numeric->Llen, c);
    for (int e = 0; e < lc.size; ++e) l(lc.row[e] - from, c - from) = lc.value[e];
    const KluColumn uc = klu_column(m.numeric, m.numeric->Uip, m.numeric->Ulen, c);
    for (int e = 0; e < uc.size; ++e)
      if (uc.row[e] >= from) u(uc.row[e] - from, c - from) = uc.value[e];
    u(c - from, c - from) = u_diagonal[c];
  }
  m.lu.resize(k, k);
  m.lu.noalias() = l * u;
  Eigen::Map<Eigen::MatrixXd> out(schur, k, k);
  for (int r = 0; r < k; ++r) out.row(pivot_row[from + r] - from) = m.lu.row(r) / kTrailingScale;
  return true;
}

bool KluFactor::factorize() {
  Impl& m = *impl_;
  // K's rows are scaled in place for the LU and restored after: a power of two, so both ways are
  // exact (for entries above 2^-822 in magnitude), and no copy of the values is made.
  double* values = const_cast<double*>(m.a.values);
  for (const int e : m.trailing_entries) values[e] *= kTrailingScale;
  const bool factored = factorize_values();
  for (const int e : m.trailing_entries) values[e] /= kTrailingScale;
  return factored;
}

bool KluFactor::factorize_values() {
  Impl& m = *impl_;
  int* p = const_cast<int*>(m.a.colptr);
  int* i = const_cast<int*>(m.a.rowind);
  double* x = const_cast<double*>(m.a.values);
  // Later factorisations of a Newton solve reuse the pivot order of the first (klu_refactor: no
  // pivot search, several times faster); if the reused pivots lose three digits of the crude
  // condition estimate against the last pivoted factorisation, it pivots afresh.
  if (m.numeric && klu_refactor(p, i, x, m.symbolic, m.numeric, &m.c) && klu_rcond(m.symbolic, m.numeric, &m.c) &&
      m.c.rcond >= 1e-3 * m.full_rcond)
    return true;
  klu_free_numeric(&m.numeric, &m.c);
  m.numeric = klu_factor(p, i, x, m.symbolic, &m.c);
  if (!m.numeric || m.c.status != KLU_OK) {
    klu_free_numeric(&m.numeric, &m.c);
    return false;
  }
  klu_rcond(m.symbolic, m.numeric, &m.c);
  m.full_rcond = m.c.rcond;
  return m.c.rcond > 0;
}

void KluFactor::forward_interior(double* b) const {
  const Impl& m = *impl_;
  const int n = m.a.n, from = m.interior;
  const int* pivot_row = m.numeric->Pnum;
  std::vector<double>& t = m.work;
  t.resize(n);
  for (int k = 0; k < n; ++k) t[k] = b[pivot_row[k]] * (k < from ? 1.0 : kTrailingScale);
  for (int j = 0; j < from; ++j) {
    const double tj = t[j];  // (the column's rows lie below j)
    if (tj == 0) continue;
    const KluColumn lc = klu_column(m.numeric, m.numeric->Lip, m.numeric->Llen, j);
    for (int e = 0; e < lc.size; ++e) t[lc.row[e]] -= lc.value[e] * tj;
  }
  for (int k = 0; k < from; ++k) b[k] = t[k];
  for (int k = from; k < n; ++k) b[pivot_row[k]] = t[k] / kTrailingScale;
}

void KluFactor::back_interior(double* b, const double* u_k) const {
  const Impl& m = *impl_;
  const int n = m.a.n, from = m.interior;
  const double* u_diagonal = static_cast<const double*>(m.numeric->Udiag);
  std::vector<double>& w = m.work;
  w.assign(b, b + from);
  for (int c = from; c < n; ++c) {
    const double uc_k = u_k[c - from];
    const KluColumn uc = klu_column(m.numeric, m.numeric->Uip, m.numeric->Ulen, c);
    for (int e = 0; e < uc.size; ++e)
      if (uc.row[e] < from) w[uc.row[e]] -= uc.value[e] * uc_k;
  }
  for (int j = from - 1; j >= 0; --j) {
    const double wj = w[j] /= u_diagonal[j];  // (the column's rows lie above j)
    if (wj == 0) continue;
    const KluColumn uc = klu_column(m.numeric, m.numeric->Uip, m.numeric->Ulen, j);
    for (int e = 0; e < uc.size; ++e) w[uc.row[e]] -= uc.value[e] * wj;
  }
  for (int j = 0; j < from; ++j) b[m.order[j]] = w[j];
  for (int c = from; c < n; ++c) b[c] = u_k[c - from];
}

void KluFactor::repivot() { klu_free_numeric(&impl_->numeric, &impl_->c); }

void KluFactor::solve(double* x, int columns) {
  Impl& m = *impl_;
  Eigen::MatrixXd b;
  if constexpr (kValidate) b = Eigen::Map<const Eigen::MatrixXd>(x, m.a.n, columns);
  if (!m.numeric || !klu_solve(m.symbolic, m.numeric, m.a.n, columns, x, &m.c))
    throw std::runtime_error("KLU solve failed");
  RBPART_CHECK(solve_violation(eigen_view(m.a), Eigen::Map<const Eigen::MatrixXd>(x, m.a.n, columns), b));
}

}  // namespace rbpart
