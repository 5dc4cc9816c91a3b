#include "solve/block_lu.hpp"

#include "solve/island_chunks.hpp"

#include <Eigen/LU>
#include <amd.h>
#include <camd.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace rbpart {

void BlockLU::analyze(int blocks, const std::vector<int>& start, const std::vector<int>& adjacent, int interior) {
  const int nb = blocks_ = blocks;
  interior_ = interior;
  const int leading = interior < 0 ? nb : interior;  // the blocks eliminated by factor() or factor_schur()
  // AMD on the whole graph; with a split, CAMD with the trailing blocks constrained last, so that the
  // leading blocks next to them are eliminated late and carry them into few columns' fill (AMD on
  // the leading blocks alone, blind to the trailing ones, took 1.4 times the block products on the
  // Large Rock Pile's parts). The trailing blocks keep their own order: every two are adjacent.
  block_of_.resize(nb);
  position_of_.resize(nb);
  std::iota(block_of_.begin(), block_of_.end(), 0);
  if (leading > 1) {
    std::vector<int> colptr(1, 0), rowind;
    for (int c = 0; c < nb; ++c) {
      for (int a = start[c]; a < start[c + 1]; ++a) rowind.push_back(adjacent[a]);
      colptr.push_back(static_cast<int>(rowind.size()));
    }
    std::vector<int> order(nb);
    if (leading == nb) {
      if (amd_order(nb, colptr.data(), rowind.data(), order.data(), nullptr, nullptr) < AMD_OK)
        throw std::runtime_error("BlockLU: AMD ordering failed");
    } else {
      std::vector<int> constraint(nb);
      for (int b = 0; b < nb; ++b) constraint[b] = b >= leading;
      if (camd_order(nb, colptr.data(), rowind.data(), order.data(), nullptr, nullptr, constraint.data()) < CAMD_OK)
        throw std::runtime_error("BlockLU: CAMD ordering failed");
    }
    int j = 0;
    for (const int b : order)
      if (b < leading) block_of_[j++] = b;
  }
  for (int j = 0; j < nb; ++j) position_of_[block_of_[j]] = j;

  // The fill, column by column along the elimination tree: column j holds its own entries below j
  // and every child's fill but j. The trailing blocks of a split are made adjacent to each other.
  fill_start_.assign(1, 0);
  fill_.clear();
  std::vector<int> mark(nb, -1), first_child(nb, -1), next_child(nb, -1);
  for (int j = 0; j < nb; ++j) {
    const std::size_t begin = fill_.size();
    mark[j] = j;
    const auto add = [&](int i) {
      if (mark[i] != j) {
        mark[i] = j;
        fill_.push_back(i);
      }
    };
    if (j >= leading) {
      for (int i = j + 1; i < nb; ++i) add(i);
    } else {
      const int b = block_of_[j];
      for (int a = start[b]; a < start[b + 1]; ++a)
        if (position_of_[adjacent[a]] > j) add(position_of_[adjacent[a]]);
      for (int c = first_child[j]; c >= 0; c = next_child[c])
        for (int e = fill_start_[c]; e < fill_start_[c + 1]; ++e)
          if (fill_[e] > j) add(fill_[e]);
    }
    std::sort(fill_.begin() + static_cast<std::ptrdiff_t>(begin), fill_.end());
    fill_start_.push_back(static_cast<int>(fill_.size()));
    if (fill_.size() > begin) {  // the parent is the first position below j
      const int parent = fill_[begin];
      next_child[j] = first_child[parent];
      first_child[parent] = j;
    }
  }

  // Where each pattern entry lands, and the updates of every position that is eliminated (a split's
  // trailing blocks never are).
  source_.resize(adjacent.size());
  for (int c = 0; c < nb; ++c)
    for (int a = start[c]; a < start[c + 1]; ++a) source_[a] = slot(position_of_[adjacent[a]], position_of_[c]);
  update_start_.assign(1, 0);
  update_.clear();
  for (int j = 0; j < leading; ++j) {
    for (int p = fill_start_[j]; p < fill_start_[j + 1]; ++p)
      for (int q = fill_start_[j]; q < fill_start_[j + 1]; ++q)
        update_.push_back({slot(fill_[p], fill_[q]), lower(p), upper(q)});
    update_start_.push_back(static_cast<int>(update_.size()));
  }
  block_.resize(nb + 2 * fill_.size());
  std::vector<char> given(block_.size(), 0);
  for (const int at : source_) given[at] = 1;
  fill_only_.clear();
  for (std::size_t at = 0; at < block_.size(); ++at)
    if (!given[at]) fill_only_.push_back(static_cast<int>(at));
  diagonal_.resize(nb);
  z_.resize(nb);
  eliminated_ = 0;
}

int BlockLU::slot(int i, int k) const {
  if (i == k) return i;
  const int column = std::min(i, k), row = std::max(i, k);
  const int* first = fill_.data() + fill_start_[column];
  const int* last = fill_.data() + fill_start_[column + 1];
  const int* at = std::lower_bound(first, last, row);
  if (at == last || *at != row) throw std::logic_error("BlockLU: a block outside the fill");
  const int e = static_cast<int>(at - fill_.data());
  return i > k ? lower(e) : upper(e);
}

namespace {

// x <- x D^-1 = x U^-1 L^-1 P for D = P^-1 L U, by columns: Eigen's triangular solves with a matrix on
// the right take its general (dynamic-size) kernels, several times slower on 6 x 6 blocks.
void divide_on_the_right(const Eigen::PartialPivLU<BlockLU::Mat6>& lu, BlockLU::Mat6& x) {
  const BlockLU::Mat6& f = lu.matrixLU();
  for (int k = 0; k < 6; ++k) {  // x U^-1
    for (int m = 0; m < k; ++m) x.col(k) -= f(m, k) * x.col(m);
    x.col(k) /= f(k, k);
  }
  for (int k = 4; k >= 0; --k)  // x L^-1 (unit diagonal)
    for (int m = k + 1; m < 6; ++m) x.col(k) -= f(m, k) * x.col(m);
  x = (x * lu.permutationP()).eval();
}

}  // namespace

bool BlockLU::eliminate(const double* values, int count, IslandChunks* chunks) {
  eliminated_ = 0;
  for (const int at : fill_only_) block_[at].setZero();
  for (std::size_t a = 0; a < source_.size(); ++a) block_[source_[a]] = Eigen::Map<const Mat6>(values + 36 * a);
  for (int j = 0; j < count; ++j) {
    Eigen::PartialPivLU<Mat6>& lu = diagonal_[j];
    lu.compute(block_[j]);
    const double pivot = lu.matrixLU().diagonal().cwiseAbs().minCoeff();
    if (!(std::isfinite(pivot) && pivot > 0)) return false;
    // Row p of the column: its L block divided by D_j, then its updates L_pj U_jq for every q (the
    // U blocks are final), so that rows need nothing from each other.
    const int begin = fill_start_[j], fill = fill_start_[j + 1] - begin, first = update_start_[j];
    const auto row = [&](int p) {
      divide_on_the_right(lu, block_[lower(begin + p)]);
      for (int u = first + p * fill, last = u + fill; u < last; ++u) apply_update(update_[u]);
    };
    if (chunks && fill * fill >= kChunkedUpdates) {
      chunks->each(fill, row, fill * fill);
    } else {
      for (int p = 0; p < fill; ++p) row(p);
    }
  }
  eliminated_ = count;
  return true;
}

bool BlockLU::factor(const double* values, IslandChunks* chunks) {
  if (interior_ >= 0) throw std::logic_error("BlockLU::factor on a split analysis");
  return eliminate(values, blocks_, chunks);
}

bool BlockLU::factor_schur(const double* values, Eigen::MatrixXd& schur, IslandChunks* chunks) {
  if (interior_ < 0) throw std::logic_error("BlockLU::factor_schur without an interior");
  const int k = blocks_ - interior_;
  schur.resize(6 * k, 6 * k);
  if (!eliminate(values, interior_, chunks)) return false;
  for (int c = 0; c < k; ++c)
    for (int r = 0; r < k; ++r) schur.block<6, 6>(6 * r, 6 * c) = block_[slot(interior_ + r, interior_ + c)];
  return schur.allFinite();
}

void BlockLU::solve(double* x) {
  if (interior_ >= 0 || eliminated_ != blocks_) throw std::logic_error("BlockLU::solve without factor()");
  for (int j = 0; j < blocks_; ++j) z_[j] = Eigen::Map<const Vec6>(x + 6 * block_of_[j]);
  for (int j = 0; j < blocks_; ++j)
    for (int e = fill_start_[j]; e < fill_start_[j + 1]; ++e) z_[fill_[e]].noalias() -= block_[lower(e)] * z_[j];
  for (int j = blocks_ - 1; j >= 0; --j) {
    Vec6 t = z_[j];
    for (int e = fill_start_[j]; e < fill_start_[j + 1]; ++e) t.noalias() -= block_[upper(e)] * z_[fill_[e]];
    z_[j] = diagonal_[j].solve(t);
  }
  for (int j = 0; j < blocks_; ++j) Eigen::Map<Vec6>(x + 6 * block_of_[j]) = z_[j];
}

void BlockLU::forward_interior(double* b) {
  if (interior_ < 0 || eliminated_ != interior_) throw std::logic_error("BlockLU::forward_interior without factor_schur()");
  for (int j = 0; j < blocks_; ++j) z_[j] = Eigen::Map<const Vec6>(b + 6 * block_of_[j]);
  for (int j = 0; j < interior_; ++j)
    for (int e = fill_start_[j]; e < fill_start_[j + 1]; ++e) z_[fill_[e]].noalias() -= block_[lower(e)] * z_[j];
  for (int j = 0; j < blocks_; ++j) Eigen::Map<Vec6>(b + 6 * block_of_[j]) = z_[j];
}

void BlockLU::back_interior(double* b, const double* u_k) {
  if (interior_ < 0 || eliminated_ != interior_) throw std::logic_error("BlockLU::back_interior without factor_schur()");
  for (int j = 0; j < interior_; ++j) z_[j] = Eigen::Map<const Vec6>(b + 6 * block_of_[j]);
  for (int j = interior_; j < blocks_; ++j) z_[j] = Eigen::Map<const Vec6>(u_k + 6 * (j - interior_));
  for (int j = interior_ - 1; j >= 0; --j) {
    Vec6 t = z_[j];
    for (int e = fill_start_[j]; e < fill_start_[j + 1]; ++e) t.noalias() -= block_[upper(e)] * z_[fill_[e]];
    z_[j] = diagonal_[j].solve(t);
  }
  for (int j = 0; j < blocks_; ++j) Eigen::Map<Vec6>(b + 6 * block_of_[j]) = z_[j];
}

}  // namespace rbpart
