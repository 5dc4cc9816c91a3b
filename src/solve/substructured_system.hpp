#pragma once
// The substructured backend of the Newton solver's linear algebra (linear_system.hpp, DESIGN.md §7):
// a piece's system factored part by part and coupled through the interface Schur complement.
//
// A partition of the island's bodies splits the rows: a row whose bodies lie in one part is a
// sub-system row of that part, a row touching two parts an interface row. With u = M^-1 J^T x, part
// i's bodies obey N_i u_i = h_i + J_{I,i}^T x_I: N_i and h_i are the monolithic backend's on the
// part's bodies and sub-system rows (body_space.hpp), and the interface impulses x_I act on the part
// from outside. The interface rows keep their impulses as unknowns, with their own equations:
//   Free   J_t u + s_t x_t = g_t      (J_t u = sum over its two parts of J_{t,i} u_i)
//   Fixed  x_t = g_t
//   Tied   x_t = g_t + c_t x_n        (a tie stays within one contact: n is an interface row too).
// Known parts move to the right: h'_i = h_i + sum over the part's Fixed and Tied interface rows of
// J_{t,i}^T g_t, and a tie's c_t x_n joins its normal's column, e_{b,i} = J_{b,i}^T + sum over
// Tied t with n(t) = b of c_t J_{t,i}^T. Eliminating u_i = N_i^-1 (h'_i + sum_b e_{b,i} x_b) leaves
// the free interface impulses and
//   S x_I = r,  S_ab = s_a delta_ab + sum_i J_{a,i} N_i^-1 e_{b,i},  r_a = g_a - sum_i J_{a,i} N_i^-1 h'_i,
// symmetric positive definite when no row of the island is tied, else not symmetric. N_i^-1 e_{b,i}
// lives on the part's interface bodies: with X_i = N_i^-1 U_i for the unit columns U_i of their 6 k_i
// unknowns (the effective inverse mass W_i of §7 is X_i's rows on them), N_i^-1 e_{b,i} = X_i e_{b,i}.
//
// factor(): every part, in parallel, refactors N_i and solves for X_i if its sub-system rows'
// equations, ties or shifts changed since its last factorisation, and forms its block
// C_i = J_{T,i} X_i E_{T,i} over the interface rows T_i touching it if N_i or their equations or ties
// changed. S is then assembled in part order (the result does not depend on the thread count) over
// all interface rows, a row that is not free being an identity row, so that its pattern, the union of
// the blocks T_i x T_i (two interface rows couple only through a part both touch), is fixed and
// analysed once; it is factored like N (pattern_factor.hpp), dense up to 6 * dense_max_bodies rows,
// the size of the largest dense N. solve(): every part, in parallel, solves N_i v_i = h'_i and forms
// its terms of r; the interface solves S (serial); every part, in parallel, back-substitutes
// u_i = v_i + X_i E_{T,i} x_I and recovers its sub-system rows' impulses.
#include "solve/body_space.hpp"
#include "solve/island_system.hpp"
#include "solve/linear_system.hpp"
#include "solve/pattern_factor.hpp"

#include <Eigen/Core>

#include <vector>

namespace rbpart {

// Cost of factor() and solve() calls, in ms. Work sums every part's time in the parallel phases
// and the serial interface phases; the critical path replaces every parallel phase by its slowest
// part (the time on unlimited cores); wall is the calls' wall time.
struct SubstructuredCost {
  double work_ms = 0, critical_path_ms = 0, wall_ms = 0;
  int parts_refactored = 0;  // parts whose N_i was factored
};

class SubstructuredSystem final : public LinearSystem {
 public:
  // Splits `s` (kept by reference; it must outlive the solves) by `part_of_body` (island body ->
  // part 0..P-1, every part non-empty) and builds the patterns. Throws std::invalid_argument if a
  // friction row and its normal lie in different parts or interfaces.
  void assign(const IslandSystem& s, const std::vector<int>& part_of_body, int dense_max_bodies);
  bool factor(const Piece& piece) override;
  void solve(const Eigen::VectorXd& g, Eigen::VectorXd& x) override;

  int parts() const { return static_cast<int>(parts_.size()); }
  int interface_rows() const { return static_cast<int>(interface_row_.size()); }
  int interface_bodies() const { return interface_bodies_; }
  // The last factor() or solve() call, and all calls since assign().
  const SubstructuredCost& last() const { return last_; }
  const SubstructuredCost& total() const { return total_; }

 private:
  struct Part {
    BodySpaceSystem n;
    // The interface rows touching the part (interface index, increasing): the slot acting on the
    // part, the interface body (0..k-1) it acts on, the position here of its normal (-1 if none).
    std::vector<int> touch, slot, touch_body, touch_normal;
    std::vector<int> interface_bodies;  // local bodies (n's numbering) with an interface row, increasing
    std::vector<int> entry;             // S's value index of (touch a, touch b), at a + |T| b
    // The interface rows' equations and ties C was formed for.
    std::vector<RowEquation> touch_equation;
    std::vector<double> touch_tie;
    bool formed = false, refactored = false, ok = true;
    Eigen::MatrixXd x;                  // X_i = N_i^-1 U_i (6 n_i x 6 k)
    Eigen::MatrixXd jx;                 // J_{T,i} X_i on the interface bodies' rows (|T| x 6k)
    Eigen::MatrixXd c;                  // C_i (|T| x |T|)
    Eigen::VectorXd h, y, term;         // h'_i then v_i and u_i; E_{T,i} x_I (6k); J_{a,i} v_i (|T|)
    double ms = 0;                      // the part's time in the current parallel phase
  };

  // J_{t,i}, interface row touch[a] of part p on the part.
  const Vec6& jac(const Part& p, int a) const { return s_->jac[interface_row_[p.touch[a]]][p.slot[a]]; }
  // Refactors part p if its rows changed, then forms C_i if it or its interface rows changed.
  void factor_part(Part& p, const Piece& piece);
  // Runs fn(part) for every part in parallel, timing each; the slowest counts to the critical path.
  template <class Fn>
  void for_parts(Fn&& fn);
  // Runs fn() as serial work.
  template <class Fn>
  void serial(Fn&& fn);
  // Ends a factor() or solve() call of wall time `wall_ms`: adds last() to total().
  void finish_call(double wall_ms);

  const IslandSystem* s_ = nullptr;
  std::vector<Part> parts_;
  std::vector<int> interface_row_;  // interface index -> island row, increasing
  std::vector<int> diagonal_;       // S's value index of (t, t)
  int interface_bodies_ = 0;
  PatternFactor s_factor_;
  std::vector<RowEquation> equation_i_;  // per interface row, the piece of the last factor()
  std::vector<double> tie_i_;
  std::vector<char> coupled_;  // interface rows whose coupling to their normal is in S (factor())
  Eigen::VectorXd r_;
  SubstructuredCost last_, total_;
};

}  // namespace rbpart
