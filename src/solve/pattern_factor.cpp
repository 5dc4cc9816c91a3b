#include "solve/pattern_factor.hpp"

#include <Eigen/SparseCore>

#include <algorithm>
#include <vector>

#include "core/validate.hpp"
#include "solve/solve_check.hpp"

namespace rbpart {

void PatternFactor::assign_blocks(int blocks, const std::vector<std::array<int, 2>>& pairs) {
  std::vector<int> start(blocks + 1, 0), adjacent(pairs.size());
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    ++start[pairs[k][0] + 1];
    adjacent[k] = pairs[k][1];
  }
  for (int b = 0; b < blocks; ++b) start[b + 1] += start[b];
  if (blocks == blocks_ && start == adjacent_start_ && adjacent == adjacent_) return;
  blocks_ = blocks;
  adjacent_start_ = std::move(start);
  adjacent_ = std::move(adjacent);
  values_.assign(36 * adjacent_.size(), 0.0);
  analysed_ = false;
}

PatternFactor::Slot PatternFactor::slot(int r, int c) const {
  // Pairs are stored by block column, each block's 36 entries column-major.
  const int* first = adjacent_.data() + adjacent_start_[c];
  const int* last = adjacent_.data() + adjacent_start_[c + 1];
  return 36 * static_cast<int>(std::lower_bound(first, last, r) - adjacent_.data());
}

void PatternFactor::set_zero() { std::fill(values_.begin(), values_.end(), 0.0); }

void PatternFactor::set_zero_column(int c) {
  std::fill(values_.begin() + 36 * adjacent_start_[c], values_.begin() + 36 * adjacent_start_[c + 1], 0.0);
}

void PatternFactor::analyse(int interior) {
  if (analysed_ && lu_.interior() == interior) return;
  lu_.analyze(blocks_, adjacent_start_, adjacent_, interior);
  analysed_ = true;
}

bool PatternFactor::factor(IslandChunks* chunks) {
  analyse(-1);
  return lu_.factor(values_.data(), chunks);
}

bool PatternFactor::factor_schur(int interior, Eigen::MatrixXd& schur, IslandChunks* chunks) {
  analyse(interior);
  return lu_.factor_schur(values_.data(), schur, chunks);
}

void PatternFactor::solve(double* x, int columns) {
  Eigen::MatrixXd rhs;
  if constexpr (kValidate) rhs = Eigen::Map<const Eigen::MatrixXd>(x, size(), columns);
  for (int c = 0; c < columns; ++c) lu_.solve(x + static_cast<std::ptrdiff_t>(c) * size());
  if constexpr (kValidate) {  // against the values as they are now
    std::vector<Eigen::Triplet<double>> entries;
    for (int c = 0; c < blocks_; ++c)
      for (int a = adjacent_start_[c]; a < adjacent_start_[c + 1]; ++a)
        for (int k = 0; k < 36; ++k) entries.emplace_back(6 * adjacent_[a] + k % 6, 6 * c + k / 6, values_[36 * a + k]);
    Eigen::SparseMatrix<double> a(size(), size());
    a.setFromTriplets(entries.begin(), entries.end());
    RBPART_CHECK(solve_violation(a, Eigen::Map<const Eigen::MatrixXd>(x, size(), columns), rhs));
  }
}

}  // namespace rbpart
