#pragma once
// The body-space form of a Newton piece's system (linear_system.hpp, DESIGN.md §3) on a set of
// bodies and the rows among them: a whole island for the monolithic backend (monolithic.hpp), one
// part's bodies and sub-system rows for the substructured one (substructured_system.hpp). With
// u = M^-1 J^T x, a Free row gives x_j = (g_j + c_j x_n - J_j u) / s_j (s_j = sigma_j + shift_j; c_j,
// its coupling to its normal, is 0 but in the interior-point steps), a Fixed row x_j = g_j and a
// Tied row x_t = g_t + c_t x_n. With a row's tie weight t_j = c_j / s_j (Free), c_t (Tied), M u = J^T x becomes
//   N u = h,  N = M + sum_Free J_j^T J_j / s_j + sum_tied (t_j / s_n) J_j^T J_n,
//   h = sum_Free J_j^T g_j / s_j + sum_Fixed J_j^T g_j + sum_Tied J_t^T g_t + sum_tied t_j J_j^T g_n / s_n
// (plus whatever impulses of other rows act on the bodies: the substructured backend's interface).
// N has 6 x 6 blocks on the body graph: 6 unknowns per body against ~20 rows per body on a pile.
// A tie adds a non-symmetric 12 x 12 term on its contact's two bodies, whose blocks N already has,
// so the pattern depends on the rows alone and is analysed once; N is factored by the block sparse LU
// of pattern_factor.hpp.
#include "solve/island_system.hpp"
#include "solve/linear_system.hpp"
#include "solve/pattern_factor.hpp"

#include <Eigen/Core>

#include <array>
#include <vector>

namespace rbpart {

class BodySpaceSystem {
 public:
  // `bodies` (distinct island bodies, in the order of N's block rows) and `rows` (island rows,
  // increasing); every body of a row is in `bodies`. `mass` is M per island body. `s` must outlive
  // the solves. `cliques` (positions among `bodies`) add blocks between every two bodies of each to
  // N's pattern, for terms the caller adds between assemble() and factor_assembled() (the
  // substructured backend's interface).
  // Assigned again, it reuses its buffers' capacity, and N's pattern when that is unchanged.
  void assign(const IslandSystem& s, const std::vector<int>& bodies, const std::vector<int>& rows,
              const std::vector<Mat6>& mass, const std::vector<std::vector<int>>& cliques = {});

  int bodies() const { return static_cast<int>(bodies_.size()); }
  // Position of island body b among the bodies (b must be one of them).
  int local_body(int b) const;

  // Factors N of `piece` on the rows (whose equations, ties and shifts it keeps); false if
  // numerically singular. The same as assemble() then factor_assembled().
  bool factor(const Piece& piece);
  // N of `piece` assembled, not factored; with `chunks`, its loops over rows and bodies in them.
  void assemble(const Piece& piece, IslandChunks* chunks = nullptr);
  // N's block of (local body r, local body c), both adjacent in its pattern: to add to after assemble().
  PatternFactor::Block block(int r, int c) { return n_.block(r, c); }
  // The same through its slot, which holds until the next assign().
  PatternFactor::Slot slot(int r, int c) const { return n_.slot(r, c); }
  PatternFactor::Block block(PatternFactor::Slot at) { return n_.block(at); }
  bool factor_assembled(IslandChunks* chunks = nullptr);
  // The substructured backend's part (pattern_factor.hpp, factor_schur): N factored by LU with its
  // first `interior` bodies eliminated first, `schur` <- the Schur complement of the others; then
  // h (6 entries per body) <- [y_I; h_K - N_KI N_II^-1 h_I], and <- [N_II^-1 (h_I - N_IK u_K); u_K].
  bool factor_schur(int interior, Eigen::MatrixXd& schur, IslandChunks* chunks = nullptr);
  void forward_interior(Eigen::VectorXd& h) { n_.forward_interior(h.data()); }
  void back_interior(Eigen::VectorXd& h, const Eigen::VectorXd& u_k) { n_.back_interior(h.data(), u_k.data()); }
  // Whether `piece` gives the rows the equations, ties and shifts of the last assemble(), and N
  // was factored since.
  bool factored_for(const Piece& piece) const { return factored_ && assembled_for(piece); }
  bool assembled_for(const Piece& piece) const;
  // h += the rows' terms of h for right-hand side g (island rows); h has 6 entries per local body.
  void add_rhs(const Eigen::VectorXd& g, Eigen::VectorXd& h) const;
  // h <- N^-1 h for `columns` vectors of 6 * bodies() entries stored one after another.
  void solve(double* h, int columns = 1) { n_.solve(h, columns); }
  // The rows' x (island numbering) from g and the bodies' u = N^-1 h.
  void recover(const Eigen::VectorXd& g, const Eigen::VectorXd& u, Eigen::VectorXd& x) const;

 private:
  static constexpr int kMaxRun = 16;  // rows in one run (see run_start_), at most
  // N's pattern from the rows' bodies and `cliques`.
  void assign_pattern(const std::vector<std::vector<int>>& cliques);
  // Adds run i's terms to N: those of block column b (one of the run's bodies), or all (b < 0).
  void add_run(int i, int b);
  // J_j u for local row k.
  double velocity(int k, const Eigen::VectorXd& u) const;

  const IslandSystem* s_ = nullptr;
  std::vector<int> bodies_, rows_;
  std::vector<std::array<int, 2>> by_body_;  // {island body, position}, by island body
  std::vector<std::array<int, 2>> body_;  // local body per slot of each local row, -1 = none
  std::vector<int> normal_;               // local row of a row's normal, -1 if none
  std::vector<Mat6> mass_;                // per local body
  std::vector<std::vector<int>> cliques_;  // assign()'s, part of the pattern
  std::vector<std::array<int, 2>> pairs_;  // assign_pattern()'s scratch: N's adjacent blocks
  // Where N's blocks lie, looked up once per pattern: each body's diagonal block; per run of
  // consecutive rows on the same bodies (a contact's three rows, a manifold's contacts), starting
  // at local row run_start_[i], the blocks (slot p, slot q) of their J_p^T J_q (index 2p + q;
  // -1: none), which their ties' J_p^T J_n,q share. A run's terms are summed before they
  // are added to N.
  std::vector<PatternFactor::Slot> diagonal_;
  std::vector<int> run_start_;
  std::vector<std::array<PatternFactor::Slot, 4>> own_;
  std::vector<int> runs_of_body_start_, runs_of_body_;  // per local body: the runs on it, in order
  // The piece of the last factor() on the rows; 1 / s_j on Free rows.
  std::vector<RowEquation> equation_;
  std::vector<double> tie_, shift_, inv_s_, tie_weight_;
  bool assembled_ = false, factored_ = false;
  PatternFactor n_;
};

}  // namespace rbpart
