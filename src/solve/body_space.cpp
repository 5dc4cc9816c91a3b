#include "solve/body_space.hpp"

#include "solve/island_chunks.hpp"

#include <algorithm>
#include <stdexcept>

namespace rbpart {

void BodySpaceSystem::assign(const IslandSystem& s, const std::vector<int>& bodies, const std::vector<int>& rows,
                             const std::vector<Mat6>& mass, const std::vector<std::vector<int>>& cliques) {
  s_ = &s;
  bodies_ = bodies;
  rows_ = rows;
  const int nb = this->bodies(), nr = static_cast<int>(rows_.size());
  by_body_.resize(nb);
  for (int b = 0; b < nb; ++b) by_body_[b] = {bodies_[b], b};
  std::sort(by_body_.begin(), by_body_.end());
  mass_.resize(nb);
  for (int b = 0; b < nb; ++b) mass_[b] = mass[bodies_[b]];
  // N's pattern follows from the bodies and each row's bodies: unchanged (a resting island assigned
  // again), it is not rebuilt.
  bool same_pattern = 6 * nb == n_.size() && nr == static_cast<int>(body_.size()) && cliques == cliques_;
  body_.resize(nr);
  normal_.resize(nr);
  for (int k = 0; k < nr; ++k) {
    const int j = rows_[k];
    for (int p = 0; p < 2; ++p) {
      const int b = s.body[j][p] < 0 ? -1 : local_body(s.body[j][p]);
      same_pattern = same_pattern && body_[k][p] == b;
      body_[k][p] = b;
    }
    normal_[k] = s.normal_of[j] < 0 ? -1
                                    : static_cast<int>(std::lower_bound(rows_.begin(), rows_.end(), s.normal_of[j]) -
                                                       rows_.begin());
  }
  // A tie's term J_j^T J_n lies on the row's own blocks: a friction row acts on its normal's bodies.
  for (int k = 0; k < nr; ++k)
    if (normal_[k] >= 0 && body_[normal_[k]] != body_[k])
      throw std::logic_error("BodySpaceSystem: a friction row and its normal act on different bodies");
  equation_.assign(nr, RowEquation::Fixed);
  tie_.assign(nr, 0.0);
  shift_.assign(nr, 0.0);
  inv_s_.assign(nr, 0.0);
  tie_weight_.assign(nr, 0.0);
  assembled_ = factored_ = false;
  if (same_pattern) return;  // the blocks' slots hold as well
  cliques_ = cliques;
  assign_pattern(cliques);
  diagonal_.resize(nb);
  for (int b = 0; b < nb; ++b) diagonal_[b] = n_.slot(b, b);
  run_start_.clear();
  own_.clear();
  for (int k = 0; k < nr; ++k) {
    if (k > 0 && body_[k] == body_[k - 1] && k - run_start_.back() < kMaxRun) continue;
    run_start_.push_back(k);
    std::array<PatternFactor::Slot, 4>& own = own_.emplace_back();
    for (int p = 0; p < 2; ++p)
      for (int q = 0; q < 2; ++q)
        own[2 * p + q] = body_[k][p] < 0 || body_[k][q] < 0 ? -1
                                                            : n_.slot(body_[k][p], body_[k][q]);
  }
  run_start_.push_back(nr);
  // Each body's runs, in run order.
  runs_of_body_start_.assign(nb + 1, 0);
  for (std::size_t i = 0; i < own_.size(); ++i)
    for (int p = 0; p < 2 && body_[run_start_[i]][p] >= 0; ++p) ++runs_of_body_start_[body_[run_start_[i]][p] + 1];
  for (int b = 0; b < nb; ++b) runs_of_body_start_[b + 1] += runs_of_body_start_[b];
  runs_of_body_.resize(runs_of_body_start_[nb]);
  std::vector<int> next(runs_of_body_start_.begin(), runs_of_body_start_.end() - 1);
  for (std::size_t i = 0; i < own_.size(); ++i)
    for (int p = 0; p < 2 && body_[run_start_[i]][p] >= 0; ++p) runs_of_body_[next[body_[run_start_[i]][p]]++] = static_cast<int>(i);
}

void BodySpaceSystem::assign_pattern(const std::vector<std::vector<int>>& cliques) {
  const int nb = bodies();
  std::vector<std::array<int, 2>>& pairs = pairs_;
  pairs.clear();
  for (int b = 0; b < nb; ++b) pairs.push_back({b, b});
  for (const auto& slot : body_)
    if (slot[1] >= 0) {
      pairs.push_back({slot[0], slot[1]});
      pairs.push_back({slot[1], slot[0]});
    }
  for (const std::vector<int>& clique : cliques)
    for (const int a : clique)
      for (const int b : clique) pairs.push_back({a, b});
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  n_.assign_blocks(nb, pairs);
}

int BodySpaceSystem::local_body(int b) const {
  return std::lower_bound(by_body_.begin(), by_body_.end(), std::array<int, 2>{b, -1})->at(1);
}

bool BodySpaceSystem::factor(const Piece& piece) {
  assemble(piece);
  return factor_assembled();
}

bool BodySpaceSystem::factor_assembled(IslandChunks* chunks) {
  factored_ = n_.factor(chunks);
  return factored_;
}

bool BodySpaceSystem::factor_schur(int interior, Eigen::MatrixXd& schur, IslandChunks* chunks) {
  factored_ = n_.factor_schur(interior, schur, chunks);
  return factored_;
}

void BodySpaceSystem::assemble(const Piece& piece, IslandChunks* chunks) {
  const IslandSystem& s = *s_;
  factored_ = false;
  assembled_ = true;
  IslandChunks serial;
  IslandChunks& loops = chunks ? *chunks : serial;
  const int nr = static_cast<int>(rows_.size());
  loops.each(nr, [&](int k) {
    const int j = rows_[k];
    equation_[k] = piece.equation[j];
    tie_[k] = piece.tie[j];
    shift_[k] = piece.shift[j];
    if (equation_[k] == RowEquation::Free) inv_s_[k] = 1.0 / (s.sigma[j] + shift_[k]);
    // A row's tie to its normal enters its impulse as tie_weight_k x_n: c_t (Tied), c_j / s_j
    // (Free). (A row without a tie has none, even where 1 / s_j is not finite.)
    tie_weight_[k] = tie_[k] == 0 ? 0.0
                     : equation_[k] == RowEquation::Tied ? tie_[k]
                     : equation_[k] == RowEquation::Free ? tie_[k] * inv_s_[k]
                                                         : 0.0;
  });
  // Each block: the mass on the diagonal, then, run by run, the terms of every run on it. Serially
  // run after run, each run's blocks at once; in several chunks, block column by block column:
  // body b's column (., b) from the runs on b, b as their slot q, so that every column is written
  // by one body. Every block gets the same sums in the same order either way.
  if (loops.count() == 1) {
    n_.set_zero();
    for (int b = 0; b < bodies(); ++b) n_.block(diagonal_[b]) = mass_[b];
    for (int i = 0; i + 1 < static_cast<int>(run_start_.size()); ++i) add_run(i, -1);
    return;
  }
  chunks->each(bodies(), [&](int b) {
    n_.set_zero_column(b);
    n_.block(diagonal_[b]) = mass_[b];
    for (int r = runs_of_body_start_[b]; r < runs_of_body_start_[b + 1]; ++r) add_run(runs_of_body_[r], b);
  }, nr);
}

void BodySpaceSystem::add_run(int i, int b) {
  const IslandSystem& s = *s_;
  // A run's rows k add J_k,p^T (w_k J_k,q + c_k J_n(k),q) to block (p, q): w_k = 1 / s_k on Free
  // rows, c_k = tie_weight_k / s_n on ties (the normal acts on the same bodies). Gathered as
  // columns, each block's terms are summed in one fixed-size accumulator and added to N once
  // (Eigen's product of these small dynamic shapes would take its general GEMM path).
  using Columns = Eigen::Matrix<double, 6, Eigen::Dynamic, 0, 6, kMaxRun>;
  std::array<Columns, 2> jp, bq;
  const int begin = run_start_[i], end = run_start_[i + 1];
  const int slots = body_[begin][1] >= 0 ? 2 : 1;
  // The slots q of the columns written: both, or b's.
  const int q_first = b < 0 || body_[begin][0] == b ? 0 : 1, q_last = b < 0 ? slots : q_first + 1;
  for (int p = 0; p < slots; ++p) {
    jp[p].resize(6, end - begin);
    bq[p].resize(6, end - begin);
  }
  int m = 0;
  for (int k = begin; k < end; ++k) {
    const double w = equation_[k] == RowEquation::Free ? inv_s_[k] : 0.0;
    const double c = tie_weight_[k] != 0 ? tie_weight_[k] * inv_s_[normal_[k]] : 0.0;
    if (w == 0 && c == 0) continue;
    const int j = rows_[k];
    for (int p = 0; p < slots; ++p) jp[p].col(m) = s.jac[j][p];
    for (int q = q_first; q < q_last; ++q) {
      bq[q].col(m) = w * s.jac[j][q];
      if (c != 0) bq[q].col(m) += c * s.jac[rows_[normal_[k]]][q];
    }
    ++m;
  }
  for (int p = 0; p < slots && m > 0; ++p)
    for (int q = q_first; q < q_last; ++q) {
      Mat6 sum = jp[p].col(0) * bq[q].col(0).transpose();
      for (int c = 1; c < m; ++c) sum.noalias() += jp[p].col(c) * bq[q].col(c).transpose();
      n_.block(own_[i][2 * p + q]) += sum;
    }
}

bool BodySpaceSystem::assembled_for(const Piece& piece) const {
  if (!assembled_) return false;
  for (std::size_t k = 0; k < rows_.size(); ++k) {
    const int j = rows_[k];
    if (piece.equation[j] != equation_[k] || piece.tie[j] != tie_[k] || piece.shift[j] != shift_[k]) return false;
  }
  return true;
}

void BodySpaceSystem::add_rhs(const Eigen::VectorXd& g, Eigen::VectorXd& h) const {
  const IslandSystem& s = *s_;
  for (std::size_t k = 0; k < rows_.size(); ++k) {
    const int j = rows_[k];
    double value = equation_[k] == RowEquation::Free ? g[j] * inv_s_[k] : g[j];
    if (tie_weight_[k] != 0) value += tie_weight_[k] * g[rows_[normal_[k]]] * inv_s_[normal_[k]];
    for (int p = 0; p < 2; ++p)
      if (body_[k][p] >= 0) h.segment<6>(6 * body_[k][p]) += s.jac[j][p] * value;
  }
}

double BodySpaceSystem::velocity(int k, const Eigen::VectorXd& u) const {
  double v = 0;
  for (int p = 0; p < 2; ++p)
    if (body_[k][p] >= 0) v += s_->jac[rows_[k]][p].dot(u.segment<6>(6 * body_[k][p]));
  return v;
}

void BodySpaceSystem::recover(const Eigen::VectorXd& g, const Eigen::VectorXd& u, Eigen::VectorXd& x) const {
  for (std::size_t k = 0; k < rows_.size(); ++k) {
    const int j = rows_[k];
    x[j] = equation_[k] == RowEquation::Free ? (g[j] - velocity(static_cast<int>(k), u)) * inv_s_[k] : g[j];
  }
  for (std::size_t k = 0; k < rows_.size(); ++k)
    if (tie_weight_[k] != 0) x[rows_[k]] += tie_weight_[k] * x[rows_[normal_[k]]];
}

}  // namespace rbpart
