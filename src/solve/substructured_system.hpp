#pragma once
// The substructured backend of the Newton solver's linear algebra (linear_system.hpp, DESIGN.md §7):
// a piece's system factored part by part and coupled through an interface Schur complement.
//
// A partition of the island's bodies gives the interface: a cover of the rows between two parts
// (cover_cuts: every such row has a body on it, chosen greedily), the interface bodies K. Every other
// body keeps its part (I_i: part i's bodies off the interface; a part left with none is dropped).
// A row with a body of I_i belongs to part i (no row has bodies of two I_i: the cover), a row whose
// dynamic bodies are all on the interface is an interface row; K_i are the interface bodies of part
// i's rows. Peiret et al.'s interface takes both bodies of every row between two parts; a cover
// needs about half of them, and S's factorisation, nearly dense, costs the cube of its bodies.
// The piece's body-space system N u = h (body_space.hpp) is then, part by part,
//   [ N_II,i   N_IK,i          ] [ u_I,i ]   [ h_I,i         ]
//   [ N_KI,i   N_KK,i + ...    ] [ u_K   ] = [ h_K,i + ...   ]
// with N_i = [N_II N_IK; N_KI N_KK] and h_i from part i's rows (N_KK,i without mass), and the
// interface bodies' masses M_K and the interface rows' N_T, h_T on K only. Eliminating every part's
// own bodies, with X_i = N_II,i^-1 N_IK,i and v_i = N_II,i^-1 h_I,i, leaves the interface system on
// the interface bodies' velocities:
//   S u_K = r,   S = M_K + N_T + sum_i (N_KK,i - N_KI,i X_i),   r = h_T + sum_i (h_K,i - N_KI,i v_i),
// and back in the parts u_I,i = v_i - X_i u_K; every row's impulse follows from the velocities of
// its bodies (BodySpaceSystem::recover). S is §7's interface system with the roles of rows and
// bodies exchanged (Woodbury): the same answer, with 6 unknowns per interface body instead of one
// per interface row, and fill only within each K_i and along the interface rows' bodies, where S
// over rows couples every two interface rows of a part. Formed from N_i's own LU rather than by
// inverting an effective mass, it is as accurate as N's own factorisation. S is symmetric positive
// definite when no row of the island is tied, else not symmetric.
//
// factor(): every part, in parallel, assembles N_i and, if its rows' equations, ties or shifts
// changed since it last did, factors it by LU with I_i's bodies first and K_i's last (its assembly
// and its large columns' updates in chunks of its own): the trailing block of that LU is its block
// of S (pattern_factor.hpp, factor_schur), and its forward and back substitutions over I_i give
// h_K - N_KI N_II^-1 h_I and N_II^-1 (h_I - N_IK u_K). Beside the parts, one more task sets S to
// M_K + N_T. Then the parts' blocks are added to S block by block (the K_i overlap), each block's
// in part order, so S does not depend on the thread count. S is factored like N (its large columns
// in chunks): its pattern, the interface rows' body graph with each K_i a clique, is fixed and
// analysed once. solve(): every part, in parallel, substitutes forward over I_i, which leaves its
// terms of r, and beside them one task gathers the interface rows' terms; the interface solves S
// (serial); every part, in parallel, substitutes back for u_I and recovers its rows' impulses, and
// beside them one task recovers the interface rows'.
#include "solve/body_space.hpp"
#include "solve/island_system.hpp"
#include "solve/linear_system.hpp"

#include <Eigen/Core>

#include <array>
#include <vector>

namespace rbpart {

// Cost of assign(), factor() and solve() calls, in ms. Work sums every part's time in the parallel phases
// and the serial interface phases; the critical path replaces every parallel phase by its slowest
// part (the time on unlimited cores); wall is the calls' wall time.
struct SubstructuredCost {
  double work_ms = 0, critical_path_ms = 0, wall_ms = 0;
  int parts_refactored = 0;  // parts whose N_i was factored
};

class SubstructuredSystem final : public LinearSystem {
 public:
  // Splits `s` (kept by reference; it must outlive the solves) by `part_of_body` (island body ->
  // part id >= 0; parts() counts the ids with a body off the interface) and builds the patterns.
  // Throws std::invalid_argument if a friction row and its normal lie in different parts or the
  // interface.
  void assign(const IslandSystem& s, const std::vector<int>& part_of_body);
  bool factor(const Piece& piece) override;
  void solve(const Eigen::VectorXd& g, Eigen::VectorXd& x) override;

  int parts() const { return static_cast<int>(parts_.size()); }
  int interface_rows() const { return interface_rows_; }
  int interface_bodies() const { return interface_.bodies(); }
  // The part (0..parts()-1) whose system holds row j, -1 for the interface; whether island body b
  // is on the interface.
  int part_of_row(int j) const { return split_.owner[j]; }
  bool on_interface(int b) const { return split_.on_interface[b] != 0; }
  // The last assign(), factor() or solve() call, and assign() with all calls since.
  const SubstructuredCost& last() const { return last_; }
  const SubstructuredCost& total() const { return total_; }

 private:
  struct Part {
    // N_i on the part's bodies (I_i's first, then K_i's) and sub-system rows, factored with K_i's
    // last (BodySpaceSystem::factor_schur).
    BodySpaceSystem n;
    int interior = 0;                   // |I_i|
    bool refactored = false, ok = false;
    Eigen::MatrixXd schur;              // N_KK - N_KI N_II^-1 N_IK, the part's block of S
    // h_i, then [y_I; h_K - N_KI N_II^-1 h_I] after the forward substitution over I_i, then u_i; u_K.
    Eigen::VectorXd h, u_k;
    // N_i's assembly, block column by block column, and the elimination's large columns run in
    // these (BodySpaceSystem::assemble, BlockLU::kChunkedUpdates), as many as the part's rows
    // allow (chunks_for_rows).
    IslandChunks chunks;
    std::array<double, 2> cost{};       // work and critical path in the current parallel phase
  };

  // K_i's positions among the interface system's bodies.
  const std::vector<int>& boundary(const Part& p) const { return split_.cliques[&p - parts_.data()]; }
  // Refactors part p if its rows changed (N_i's LU and the part's block of S).
  void factor_part(Part& p, const Piece& piece);
  // Runs fn(part) for every part in parallel, and beside() as one more task, timing each; the
  // slowest counts to the critical path.
  template <class Fn, class Beside>
  void for_parts(Fn&& fn, Beside&& beside);
  template <class Fn>
  void for_parts(Fn&& fn);
  // Runs fn() as serial work.
  template <class Fn>
  void serial(Fn&& fn);
  // Ends an assign(), factor() or solve() call of wall time `wall_ms`: adds last() to total().
  void finish_call(double wall_ms);

  // cover_cuts()'s buffers: the pairs of bodies in two parts that rows join; each body's pairs (CSR);
  // each body's pairs not yet covered; a heap of {uncovered pairs, -body}.
  struct Cover {
    std::vector<std::array<int, 2>> pairs, heap;
    std::vector<int> start, other, uncovered;
  };
  static void cover_cuts(const IslandSystem& s, const std::vector<int>& part_of_body, Cover& c,
                         std::vector<char>& on_interface);

  // assign()'s split of the island, kept so that assigning again allocates nothing.
  struct Split {
    std::vector<int> owner;                      // per row: its part, -1 the interface
    std::vector<std::vector<int>> bodies, rows;  // per part: its bodies (I_i's, then K_i's) and rows
    std::vector<std::vector<int>> cliques;       // per part: K_i's positions among S's bodies
    std::vector<int> interface_rows, interface_bodies;
    std::vector<int> part_of_id;                 // per partition id in the island: its part, -1 none
    std::vector<int> clique_of;                  // per island body: the last part whose K_i took it
    std::vector<char> on_interface;              // per island body
    std::vector<Mat6> mass, part_mass;           // per island body: M, and M off the interface (else 0)
    Cover cover;
  };

  std::vector<Part> parts_;
  Split split_;
  int interface_rows_ = 0;
  BodySpaceSystem interface_;  // S on the interface bodies: their masses and N_T from the interface rows
  // S's factorisation runs the updates of its large columns (nearly dense: every K_i is a clique) in
  // kMaxChunks chunks (BlockLU::kChunkedUpdates).
  IslandChunks interface_chunks_;
  // {slot in S, part, row and column of its block} of every part's block of S, by slot, then part;
  // the first of each slot's.
  std::vector<std::array<int, 4>> adds_;
  std::vector<int> add_start_;
  Eigen::VectorXd r_;
  SubstructuredCost last_, total_;
};

}  // namespace rbpart
