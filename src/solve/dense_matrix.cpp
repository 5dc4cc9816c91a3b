#include "solve/dense_matrix.hpp"

namespace rbpart {

void DenseBlcpMatrix::assign(Eigen::MatrixXd a) {
  a_ = std::move(a);
  finalize();
}

void DenseBlcpMatrix::resize(int n) { a_.resize(n, n); }

void DenseBlcpMatrix::finalize() {
  const Eigen::Index n = a_.rows();
  diag_ = a_.diagonal();
  l_.resize(n, n);
  rhs_.resize(n);
  index_.reserve(n);
  llt_.reset();
  invalidate();
}

void DenseBlcpMatrix::multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) {
  y.noalias() = a_.selfadjointView<Eigen::Lower>() * x;
}

bool DenseBlcpMatrix::factor(const std::vector<char>& free) { return factor_gathered(free, nullptr); }

bool DenseBlcpMatrix::factor_shifted(const std::vector<char>& free, const Eigen::VectorXd& shift) {
  return factor_gathered(free, &shift);
}

bool DenseBlcpMatrix::factor_gathered(const std::vector<char>& free, const Eigen::VectorXd* shift) {
  index_.clear();
  for (int j = 0; j < size(); ++j)
    if (free[j]) index_.push_back(j);
  const int nf = static_cast<int>(index_.size());
  // Gather the lower triangle of A_FF; LLT reads nothing else.
  for (int c = 0; c < nf; ++c)
    for (int r = c; r < nf; ++r) l_(r, c) = a_(index_[r], index_[c]);
  if (shift)
    for (int c = 0; c < nf; ++c) l_(c, c) += (*shift)[index_[c]];
  Eigen::Ref<Eigen::MatrixXd> block = l_.topLeftCorner(nf, nf);
  // In place: factors the gathered block without a copy. (GCC 12 reports a false
  // -Wmaybe-uninitialized inside Eigen's AVX-512 norm reduction here.)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
  llt_.emplace(block);
#pragma GCC diagnostic pop
  return llt_->info() == Eigen::Success;
}

void DenseBlcpMatrix::solve(Eigen::VectorXd& x) {
  const int nf = static_cast<int>(index_.size());
  if (nf == 0) return;
  auto b = rhs_.head(nf);
  for (int i = 0; i < nf; ++i) b[i] = x[index_[i]];
  llt_->solveInPlace(b);
  for (int i = 0; i < nf; ++i) x[index_[i]] = b[i];
}

}  // namespace rbpart
