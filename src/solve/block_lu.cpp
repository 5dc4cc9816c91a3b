#include "solve/block_lu.hpp"

#include "core/parallel.hpp"
#include "core/timer.hpp"
#include "solve/island_chunks.hpp"

#include <tbb/task_group.h>

#include <Eigen/LU>
#include <amd.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace rbpart {

void BlockLU::analyze(int blocks, const std::vector<int>& start, const std::vector<int>& adjacent, int interior) {
  const int nb = blocks_ = blocks;
  interior_ = interior;
  const int leading = interior < 0 ? nb : interior;  // the blocks AMD orders
  // AMD on the leading blocks' graph; the trailing ones follow in their own order.
  block_of_.resize(nb);
  position_of_.resize(nb);
  std::iota(block_of_.begin(), block_of_.end(), 0);
  if (leading > 1) {
    std::vector<int> colptr(1, 0), rowind;
    for (int c = 0; c < leading; ++c) {
      for (int a = start[c]; a < start[c + 1]; ++a)
        if (adjacent[a] < leading) rowind.push_back(adjacent[a]);
      colptr.push_back(static_cast<int>(rowind.size()));
    }
    if (amd_order(leading, colptr.data(), rowind.data(), block_of_.data(), nullptr, nullptr) < AMD_OK)
      throw std::runtime_error("BlockLU: AMD ordering failed");
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

  // Where each pattern entry lands.
  source_.resize(adjacent.size());
  for (int c = 0; c < nb; ++c)
    for (int a = start[c]; a < start[c + 1]; ++a) source_[a] = slot(position_of_[adjacent[a]], position_of_[c]);

  // Eliminating position j (j < leading: a split's trailing blocks never are) updates every pair of
  // blocks (p, q) of its fill: block (p, q) -= L (p, j) U (j, q). Each update goes to its target's
  // owner, min(p, q), and to its target there, in increasing j (a counting sort by target). An
  // owner's targets: its diagonal block, then its column's L and U blocks.
  std::vector<std::array<int, 3>> updates;  // {target, L block, U block}, in increasing j
  for (int j = 0; j < leading; ++j)
    for (int p = fill_start_[j]; p < fill_start_[j + 1]; ++p)
      for (int q = fill_start_[j]; q < fill_start_[j + 1]; ++q) updates.push_back({slot(fill_[p], fill_[q]), lower(p), upper(q)});
  std::vector<int> at(nb + 2 * fill_.size(), 0);  // per slot: its updates, then where the next goes
  for (const auto& u : updates) ++at[u[0]];
  target_start_.assign(1, 0);
  target_slot_.clear();
  gather_start_.assign(1, 0);
  const auto add_target = [&](int s) {
    if (at[s] == 0) return;
    target_slot_.push_back(s);
    gather_start_.push_back(gather_start_.back() + at[s]);
    at[s] = gather_start_[gather_start_.size() - 2];
  };
  for (int m = 0; m < nb; ++m) {
    add_target(m);
    for (int e = fill_start_[m]; e < fill_start_[m + 1]; ++e) {
      add_target(lower(e));
      add_target(upper(e));
    }
    target_start_.push_back(static_cast<int>(target_slot_.size()));
  }
  gather_.resize(updates.size());
  for (const auto& u : updates) gather_[at[u[0]]++] = {u[1], u[2]};
  tree_updates_ = static_cast<long long>(gather_.size());
  block_.resize(nb + 2 * fill_.size());
  diagonal_.resize(nb);
  z_.resize(nb);
  eliminated_ = 0;

  // The tasks of factor() with chunks: a position whose subtree has less than kChunkedUpdates work
  // (updates and divisions) joins its parent's subtree task if the parent's subtree has too;
  // otherwise it is the top of a task (alone if its own subtree is large).
  task_start_.clear();
  task_node_.clear();
  task_parent_.clear();
  task_children_.clear();
  if (interior >= 0) return;
  std::vector<long long> subtree(nb, 0);
  std::vector<int> parent(nb, -1), top(nb, -1), task_of(nb, -1);
  for (int j = 0; j < nb; ++j) {
    subtree[j] += (gather_start_[target_start_[j + 1]] - gather_start_[target_start_[j]]) +
                  (fill_start_[j + 1] - fill_start_[j]) + 1;
    if (fill_start_[j + 1] > fill_start_[j]) {
      parent[j] = fill_[fill_start_[j]];
      subtree[parent[j]] += subtree[j];
    }
  }
  const auto small = [&](int j) { return subtree[j] < kChunkedUpdates; };
  for (int j = nb - 1; j >= 0; --j) top[j] = small(j) && parent[j] >= 0 && small(parent[j]) ? top[parent[j]] : j;
  for (int j = 0; j < nb; ++j)
    if (top[j] == j) {
      task_of[j] = static_cast<int>(task_start_.size());
      task_start_.push_back(0);
    }
  const int tasks = static_cast<int>(task_start_.size());
  task_start_.assign(tasks + 1, 0);
  for (int j = 0; j < nb; ++j) ++task_start_[task_of[top[j]] + 1];
  for (int k = 0; k < tasks; ++k) task_start_[k + 1] += task_start_[k];
  task_node_.resize(nb);
  at.assign(task_start_.begin(), task_start_.end() - 1);
  for (int j = 0; j < nb; ++j) task_node_[at[task_of[top[j]]]++] = j;
  task_parent_.assign(tasks, -1);
  task_children_.assign(tasks, 0);
  task_work_.assign(tasks, 0.0);
  task_path_.assign(tasks, 0.0);
  task_longest_.assign(tasks, 0.0);
  pending_.reset(new std::atomic<int>[tasks]);
  for (int j = 0; j < nb; ++j)
    if (top[j] == j && parent[j] >= 0) {
      task_parent_[task_of[j]] = task_of[top[parent[j]]];
      ++task_children_[task_of[top[parent[j]]]];
    }
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

bool BlockLU::pivot(int m) {
  Eigen::PartialPivLU<Mat6>& lu = diagonal_[m];
  lu.compute(block_[m]);
  const double least = lu.matrixLU().diagonal().cwiseAbs().minCoeff();
  if (!(std::isfinite(least) && least > 0)) return false;
  for (int e = fill_start_[m]; e < fill_start_[m + 1]; ++e) divide_on_the_right(lu, block_[lower(e)]);
  return true;
}

void BlockLU::load(const double* values) {
  eliminated_ = 0;
  for (Mat6& b : block_) b.setZero();
  for (std::size_t a = 0; a < source_.size(); ++a) block_[source_[a]] = Eigen::Map<const Mat6>(values + 36 * a);
}

bool BlockLU::eliminate(int count) {
  for (int m = 0; m < blocks_; ++m) {
    update(target_start_[m], target_start_[m + 1]);
    if (m < count && !pivot(m)) return false;
  }
  eliminated_ = count;
  return true;
}

bool BlockLU::eliminate_tree(IslandChunks& chunks) {
  const Timer wall;
  const int tasks = static_cast<int>(task_parent_.size());
  for (int k = 0; k < tasks; ++k) pending_[k].store(task_children_[k], std::memory_order_relaxed);
  std::atomic<bool> failed{false};
  // Owner m's time into a task's work and critical path: a large owner's updates in kMaxChunks
  // ranges of targets with about as many updates each, in parallel if the owner has
  // IslandChunks::kMinParallelItems of them, each range timed.
  const auto owner = [&](int m, double& work, double& path) {
    const int first = target_start_[m], last = target_start_[m + 1];
    const int updates = gather_start_[last] - gather_start_[first];
    if (updates >= kChunkedUpdates) {
      std::array<double, kMaxChunks> ms{};
      const auto range = [&](std::size_t c) {
        const Timer timer;
        const auto bound = [&](std::size_t k) {  // the first target of range k
          const long long share = static_cast<long long>(updates) * static_cast<long long>(k) / kMaxChunks;
          return static_cast<int>(std::lower_bound(gather_start_.begin() + first, gather_start_.begin() + last,
                                                   gather_start_[first] + share) -
                                  gather_start_.begin());
        };
        update(bound(c), c + 1 == kMaxChunks ? last : bound(c + 1));
        ms[c] = timer.ms();
      };
      if (updates >= IslandChunks::kMinParallelItems) {
        parallel_for_each(kMaxChunks, range);
      } else {
        for (std::size_t c = 0; c < kMaxChunks; ++c) range(c);
      }
      for (const double v : ms) work += v;
      path += *std::max_element(ms.begin(), ms.end());
      const Timer timer;
      if (!pivot(m)) failed = true;
      const double ms_pivot = timer.ms();
      work += ms_pivot;
      path += ms_pivot;
    } else {
      const Timer timer;
      update(first, last);
      if (!pivot(m)) failed = true;
      const double ms = timer.ms();
      work += ms;
      path += ms;
    }
  };
  // Task k, then its parent when k was the parent's last child to finish.
  const auto run = [&](int k) {
    while (true) {
      double work = 0, path = 0;
      for (int i = task_start_[k]; i < task_start_[k + 1] && !failed; ++i) owner(task_node_[i], work, path);
      task_work_[k] = work;
      task_path_[k] = path;
      const int p = task_parent_[k];
      if (p < 0 || pending_[p].fetch_sub(1) != 1) return;
      k = p;
    }
  };
  if (tree_updates_ >= IslandChunks::kMinParallelItems) {
    tbb::task_group group;
    for (int k = 0; k < tasks; ++k)
      if (task_children_[k] == 0) group.run([&run, k] { run(k); });
    group.wait();
  } else {
    for (int k = 0; k < tasks; ++k)
      if (task_children_[k] == 0) run(k);
  }
  if (failed) return false;
  // The critical path: the longest chain of tasks (a task's children come before it).
  task_longest_.assign(tasks, 0.0);
  double longest = 0;
  for (int k = 0; k < tasks; ++k) {
    task_longest_[k] += task_path_[k];
    longest = std::max(longest, task_longest_[k]);
    chunks.work_ms += task_work_[k];
    if (task_parent_[k] >= 0) task_longest_[task_parent_[k]] = std::max(task_longest_[task_parent_[k]], task_longest_[k]);
  }
  chunks.critical_path_ms += longest;
  chunks.wall_ms += wall.ms();
  eliminated_ = blocks_;
  return true;
}

bool BlockLU::factor(const double* values, IslandChunks* chunks) {
  if (interior_ >= 0) throw std::logic_error("BlockLU::factor on a split analysis");
  load(values);
  return chunks ? eliminate_tree(*chunks) : eliminate(blocks_);
}

bool BlockLU::factor_schur(const double* values, Eigen::MatrixXd& schur) {
  if (interior_ < 0) throw std::logic_error("BlockLU::factor_schur without an interior");
  const int k = blocks_ - interior_;
  schur.resize(6 * k, 6 * k);
  load(values);
  if (!eliminate(interior_)) return false;
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
