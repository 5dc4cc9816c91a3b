#include "solve/sparse_matrix.hpp"

#include <dlfcn.h>
#include <suitesparse/cholmod.h>

#include <algorithm>
#include <mutex>
#include <stdexcept>

namespace rbpart {

// Debian's CHOLMOD is built with OpenMP and a fixed team size: each supernode's assembly wakes the
// team, and on these small factors the wake-ups (futex calls) cost more than they save - a third
// of the direct solver's time on a forming 100-rock pile (perf) - and they compete with the TBB
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

// One CHOLMOD supernodal Cholesky factorisation of a fixed-pattern symmetric matrix whose lower
// triangle lives in caller-owned arrays: analyse once, refactor and solve many times, reusing the
// factor's storage and the solve workspaces.
class CholmodFactor {
 public:
  CholmodFactor() {
    blas_needs_lock();  // configures the runtimes before the first call
    cholmod_start(&c_);
    c_.supernodal = CHOLMOD_SUPERNODAL;
    // AMD only (skips CHOLMOD's trial of METIS: the analysis runs every step), and coarser relaxed
    // supernode amalgamation than the defaults {4, 16, 48}: the factors here are small, and fewer,
    // larger dense blocks beat the BLAS call overhead (measured ~15% on 200-body piles).
    c_.nmethods = 1;
    c_.method[0].ordering = CHOLMOD_AMD;
    c_.postorder = true;
    c_.nrelax[0] = 16;
    c_.nrelax[1] = 64;
    c_.nrelax[2] = 128;
    c_.zrelax[0] = 0.8;
    c_.zrelax[1] = 0.3;
    c_.zrelax[2] = 0.1;
    c_.quick_return_if_not_posdef = true;
    c_.print = 0;  // a non-positive-definite A_FF is reported through the return value
  }
  ~CholmodFactor() {
    cholmod_free_factor(&l_, &c_);
    cholmod_free_dense(&x_, &c_);
    cholmod_free_dense(&y_, &c_);
    cholmod_free_dense(&e_, &c_);
    cholmod_finish(&c_);
  }
  CholmodFactor(const CholmodFactor&) = delete;
  CholmodFactor& operator=(const CholmodFactor&) = delete;

  // Symbolic analysis of the pattern (values are not read).
  void analyze(const LowerCsc& pattern, double* values) {
    cholmod_free_factor(&l_, &c_);
    a_ = cholmod_sparse{};
    a_.nrow = a_.ncol = pattern.n;
    a_.nzmax = pattern.rowind.size();
    a_.p = const_cast<int*>(pattern.colptr.data());
    a_.i = const_cast<int*>(pattern.rowind.data());
    a_.x = values;
    a_.stype = -1;
    a_.itype = CHOLMOD_INT;
    a_.xtype = CHOLMOD_REAL;
    a_.dtype = CHOLMOD_DOUBLE;
    a_.sorted = true;
    a_.packed = true;
    l_ = cholmod_analyze(&a_, &c_);
    if (!l_) throw std::runtime_error("CHOLMOD analysis failed");
    b_ = cholmod_dense{};
    b_.nrow = b_.d = b_.nzmax = pattern.n;
    b_.ncol = 1;
    b_.xtype = CHOLMOD_REAL;
    b_.dtype = CHOLMOD_DOUBLE;
  }

  // Numeric factorisation of the current values; false if not positive definite.
  bool factorize() {
    const std::unique_lock<std::mutex> hold = blas_guard();
    cholmod_factorize(&a_, l_, &c_);
    return c_.status == CHOLMOD_OK && l_->minor == l_->n;
  }

  // x <- A^-1 x.
  void solve(double* x) {
    b_.x = x;
    const std::unique_lock<std::mutex> hold = blas_guard();
    if (!cholmod_solve2(CHOLMOD_A, l_, &b_, nullptr, &x_, nullptr, &y_, &e_, &c_))
      throw std::runtime_error("CHOLMOD solve failed");
    std::copy_n(static_cast<const double*>(x_->x), l_->n, x);
  }

 private:
  cholmod_common c_;
  cholmod_sparse a_{};
  cholmod_dense b_{};
  cholmod_factor* l_ = nullptr;
  cholmod_dense *x_ = nullptr, *y_ = nullptr, *e_ = nullptr;
};

// --- SparseBlcpMatrix ------------------------------------------------------------------------------

SparseBlcpMatrix::SparseBlcpMatrix() : chol_(std::make_unique<CholmodFactor>()) {}
SparseBlcpMatrix::~SparseBlcpMatrix() = default;

void SparseBlcpMatrix::assign(LowerCsc a) {
  a_ = std::move(a);
  masked_ = a_.values;
  diag_.resize(a_.n);
  for (int c = 0; c < a_.n; ++c) diag_[c] = a_.values[a_.colptr[c]];  // rows sorted: diagonal first
  rhs_.resize(a_.n);
  chol_->analyze(a_, masked_.data());
  invalidate();
}

void SparseBlcpMatrix::multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) {
  y.setZero(a_.n);
  for (int c = 0; c < a_.n; ++c) {
    double yc = 0;
    for (int p = a_.colptr[c]; p < a_.colptr[c + 1]; ++p) {
      const int r = a_.rowind[p];
      const double v = a_.values[p];
      yc += v * x[r];
      if (r != c) y[r] += v * x[c];
    }
    y[c] += yc;
  }
}

bool SparseBlcpMatrix::factor(const std::vector<char>& free) {
  for (int c = 0; c < a_.n; ++c)
    for (int p = a_.colptr[c]; p < a_.colptr[c + 1]; ++p) {
      const int r = a_.rowind[p];
      masked_[p] = (free[r] && free[c]) || r == c ? a_.values[p] : 0.0;
    }
  free_ = &free;
  return chol_->factorize();
}

void SparseBlcpMatrix::solve(Eigen::VectorXd& x) {
  // The clamped block is diagonal and decoupled: a zero right-hand side there stays zero.
  const std::vector<char>& free = *free_;
  for (int j = 0; j < a_.n; ++j) rhs_[j] = free[j] ? x[j] : 0.0;
  chol_->solve(rhs_.data());
  for (int j = 0; j < a_.n; ++j)
    if (free[j]) x[j] = rhs_[j];
}

// --- BodySpaceBlcpMatrix -----------------------------------------------------------------------------

BodySpaceBlcpMatrix::BodySpaceBlcpMatrix() : chol_(std::make_unique<CholmodFactor>()) {}
BodySpaceBlcpMatrix::~BodySpaceBlcpMatrix() = default;

void BodySpaceBlcpMatrix::assign(const IslandSystem& s) {
  s_ = &s;
  const int nb = s.bodies;
  // Body graph: the lower block (max, min) of every row with two bodies, per column body.
  std::vector<std::vector<int>> below(nb);
  for (int r = 0; r < s.rows; ++r)
    if (s.body[r][1] >= 0) {
      const int lo_b = std::min(s.body[r][0], s.body[r][1]), hi_b = std::max(s.body[r][0], s.body[r][1]);
      below[lo_b].push_back(hi_b);
    }
  for (auto& list : below) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  // Scalar CSC of N: column 6c + t holds the six rows of every block of body c (diagonal first).
  n_.n = 6 * nb;
  n_.colptr.assign(1, 0);
  n_.rowind.clear();
  stride_.resize(nb);
  diag_base_.resize(nb);
  for (int c = 0; c < nb; ++c) {
    stride_[c] = 6 * (1 + static_cast<int>(below[c].size()));
    diag_base_[c] = n_.colptr.back();
    for (int t = 0; t < 6; ++t) {
      for (int i = 0; i < 6; ++i) n_.rowind.push_back(6 * c + i);
      for (int r : below[c])
        for (int i = 0; i < 6; ++i) n_.rowind.push_back(6 * r + i);
      n_.colptr.push_back(static_cast<int>(n_.rowind.size()));
    }
  }
  n_.values.assign(n_.rowind.size(), 0.0);
  off_base_.assign(s.rows, -1);
  for (int r = 0; r < s.rows; ++r)
    if (s.body[r][1] >= 0) {
      const int c = std::min(s.body[r][0], s.body[r][1]), hi_b = std::max(s.body[r][0], s.body[r][1]);
      const int position = static_cast<int>(std::lower_bound(below[c].begin(), below[c].end(), hi_b) - below[c].begin());
      off_base_[r] = diag_base_[c] + 6 * (1 + position);
    }
  mass_ = body_masses(s);
  g_.resize(6 * nb);
  du_.resize(6 * nb);
  chol_->analyze(n_, n_.values.data());
  tied_.assign(s);
  invalidate();
}

void BodySpaceBlcpMatrix::multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) { apply_a(*s_, x, du_, y); }

bool BodySpaceBlcpMatrix::factor(const std::vector<char>& free) {
  sigma_ = s_->sigma;
  return factor_n(free);
}

// A_FF + Theta_F = J_F M^-1 J_F^T + (Sigma + Theta)_F: the same form with larger compliances.
bool BodySpaceBlcpMatrix::factor_shifted(const std::vector<char>& free, const Eigen::VectorXd& shift) {
  sigma_ = s_->sigma + shift;
  return factor_n(free);
}

bool BodySpaceBlcpMatrix::factor_n(const std::vector<char>& free) {
  using Block = Eigen::Map<Eigen::Matrix<double, 6, 6>, 0, Eigen::OuterStride<>>;
  const IslandSystem& s = *s_;
  std::fill(n_.values.begin(), n_.values.end(), 0.0);
  for (int b = 0; b < s.bodies; ++b) Block(&n_.values[diag_base_[b]], 6, 6, Eigen::OuterStride<>(stride_[b])) = mass_[b];
  // N += J_j^T J_j / sigma_j for every free row j.
  for (int j = 0; j < s.rows; ++j) {
    if (!free[j]) continue;
    const double inv_sigma = 1.0 / sigma_[j];
    const int a = s.body[j][0], b = s.body[j][1];
    const Vec6 ja = inv_sigma * s.jac[j][0];
    Block(&n_.values[diag_base_[a]], 6, 6, Eigen::OuterStride<>(stride_[a])).noalias() += ja * s.jac[j][0].transpose();
    if (b < 0) continue;
    Block(&n_.values[diag_base_[b]], 6, 6, Eigen::OuterStride<>(stride_[b])).noalias() +=
        (inv_sigma * s.jac[j][1]) * s.jac[j][1].transpose();
    // Off-diagonal block (rows of the higher body, columns of the lower one).
    const bool a_low = a < b;
    const int c = a_low ? a : b;
    const Vec6& j_row = s.jac[j][a_low ? 1 : 0];
    const Vec6& j_col = s.jac[j][a_low ? 0 : 1];
    Block(&n_.values[off_base_[j]], 6, 6, Eigen::OuterStride<>(stride_[c])).noalias() +=
        (inv_sigma * j_row) * j_col.transpose();
  }
  free_ = &free;
  return chol_->factorize();
}

void BodySpaceBlcpMatrix::solve(Eigen::VectorXd& x) {
  // Woodbury: u = N^-1 J_F^T Sigma_F^-1 b, x_F = Sigma_F^-1 (b_F - J_F u).
  const IslandSystem& s = *s_;
  const std::vector<char>& free = *free_;
  g_.setZero();
  for (int j = 0; j < s.rows; ++j) {
    if (!free[j]) continue;
    const double xs = x[j] / sigma_[j];
    for (int slot = 0; slot < 2; ++slot)
      if (s.body[j][slot] >= 0) g_.segment<6>(6 * s.body[j][slot]) += s.jac[j][slot] * xs;
  }
  chol_->solve(g_.data());
  for (int j = 0; j < s.rows; ++j)
    if (free[j]) x[j] = (x[j] - row_velocity(s, j, g_)) / sigma_[j];
}

}  // namespace rbpart
