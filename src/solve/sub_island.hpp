#pragma once
// One island split into sub-systems (DESIGN.md §7). Rows whose dynamic bodies all lie in part p
// are p's sub-system rows; a row between two parts is an interface row. Parts share no bodies, so
// A is block-arrowhead and, for fixed sets of the sub-system rows, the interface problem is
//
//   S   = Sigma_I + sum_p J_{I,p} W_p J_{I,p}^T               (W_p: sub_part.hpp)
//   q~  = q_I + sum_p A_{I,p} lambda^_p,   lambda^_p = the part's solution for lambda_I = 0.
//
// solve_fixed() runs the iteration of §7 on one fixed-bounds BLCP: (1) every part, in parallel,
// factors its free block for its current sets and forms W_p on its interface bodies, its block of
// S and its term of q~; (2) the interface BLCP (S, q~) is solved by the BLCP core; (3) every part
// solves its own BLCP with q_p + A_{p,I} lambda_I, warm started from its sets; (4) if no part's
// sets changed, (lambda_p, lambda_I) solves the island's BLCP exactly, else the parts that changed
// redo (1). Only parts whose free set changed refactor; S is re-summed in part order (a fixed
// order: the result does not depend on the thread count).
//
// Safeguard. The plain alternation can cycle (a box sliding on a box in another part: two sets of
// the lower box's contacts, each giving the interface impulses that select the other). The BLCP is
// the optimality condition of min f = 1/2 l^T A l + q^T l over the box, and the parts' answers for
// given lambda_I define the reduced objective phi(lambda_I) = min over lambda_P of f, convex, with
// gradient w_I (Danskin). Step 2 minimises phi's quadratic model on the current sets, which agrees
// with phi and its gradient at the current lambda_I, so lambda_I^new - lambda_I is a descent
// direction; step 3 therefore takes the step to lambda_I^new only if phi decreases enough
// (Armijo), else halves it. The iteration becomes a descent method on phi; a full step whose sets
// do not change still ends it exactly, and on warm-started steps that is the first full step.
//
// Exactness. The assembled S~ carries the round-off of W_p (1/sigma-sized terms cancel), so the
// interface BLCP multiplies by the exact Schur complement instead, S x = A_II x -
// sum_p A_{I,F_p} A_{F_pF_p}^-1 A_{F_p,I} x with refined sub-system solves, and uses the Cholesky
// factor of S~ only as its solver, which the core's face-solve refinement corrects (the pattern of
// the monolithic body-space backend). The sub-system BLCPs refine against their exact A_pp.
//
// The object is also a BlcpMatrix of the whole island whose A_FF is factored by substructuring:
// every part's free block, then S~ on the free interface rows; its solve is the block elimination.
// The friction outer loop's coupled step (blcp.hpp) runs on it unchanged, exactly (it refines
// against the island's A).
#include "core/timer.hpp"
#include "solve/blcp.hpp"
#include "solve/dense_matrix.hpp"
#include "solve/island_system.hpp"
#include "solve/sub_part.hpp"
#include "solve/tied_factor.hpp"

#include <array>
#include <vector>

namespace rbpart {

// Phases of the substructured solve whose work is reported (DESIGN.md §7 steps 1-3, the coupled
// friction step), each in ms summed over threads.
enum SubPhase {
  kFactorPhase,     // Cholesky factorisations: parts' N, the interface S~ on its free rows
  kSchurPhase,      // W_p, blocks of S, terms of q~, assembly of S~ and q~ (step 1)
  kInterfacePhase,  // the interface BLCP (step 2), its exact Schur products included
  kSubsystemPhase,  // the sub-system BLCPs (step 3)
  kCoupledPhase,    // the coupled friction step's solves and products
  kPhaseCount
};

struct SubIslandStats {
  std::array<double, kPhaseCount> phase_ms{};
  // Critical path (ms): the island's wall time with every parallel section over parts replaced by
  // its slowest part; with unlimited cores the island cannot finish sooner.
  double critical_ms = 0;
  double other_ms = 0;       // serial work outside the phases (gathering, set-up, write-back)
  int loop_iterations = 0;   // iterations of steps 1-4, over all fixed-bounds solves
  int blcp_iterations = 0;   // BLCP-core iterations, interface and sub-systems
  int factorizations = 0;    // Cholesky factorisations, parts and interface
  bool newton = false;       // a BLCP needed projected Newton
};

class SubstructuredIsland final : public BlcpMatrix {
 public:
  SubstructuredIsland();
  // Splits `s` (kept by reference) by `part_of_body` (island body -> part 0..parts-1, every part
  // non-empty, parts >= 2). Needs sigma_j > 0 on every row (body-space sub-systems).
  void assign(const IslandSystem& s, const std::vector<int>& part_of_body, int parts);

  int parts() const { return static_cast<int>(parts_.size()); }
  int interface_rows() const { return static_cast<int>(interface_row_.size()); }
  int interface_bodies() const { return interface_bodies_; }

  // Solves the fixed-bounds BLCP (A, s.q, lo, hi) of the island by the iteration of DESIGN.md §7,
  // warm started from lambda/state (island numbering), which receive the solution and its sets.
  // `settings.tolerance` is relative to max |s.q| as for the monolithic solve; every sub-problem
  // uses the same absolute tolerance. False if an iteration's BLCP failed, if `max_iterations`
  // passed without the sets settling, or if the safeguard halved more than `max_halvings` steps;
  // lambda/state are then left as they were.
  bool solve_fixed(const Eigen::VectorXd& lo, const Eigen::VectorXd& hi, Eigen::VectorXd& lambda,
                   std::vector<RowState>& state, const BlcpSettings& settings, int max_iterations,
                   int max_halvings);

  // Runs fn() as serial work of `phase` (nested timed sections are subtracted).
  template <class Fn>
  void serial(SubPhase phase, Fn&& fn);
  // Work and critical path so far; `wall_ms` is the island's wall time.
  SubIslandStats stats(double wall_ms) const;

  // BlcpMatrix of the island: A x exactly; A_FF by substructuring.
  int size() const override { return s_->rows; }
  const Eigen::VectorXd& diagonal() const override { return s_->diag; }
  void multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) override;
  void solve(Eigen::VectorXd& x) override;
  // The coupled step's tied system is not substructured: it is factored whole (tied_factor.hpp),
  // serial work of kCoupledPhase like the rest of the step.
  bool factor_tied(const std::vector<char>& free, const std::vector<int>& sliding,
                   const std::vector<double>& coef) override {
    return tied_.factor(free, sliding, coef);
  }
  void solve_tied(Eigen::VectorXd& x) override { tied_.solve(x); }

 protected:
  bool factor(const std::vector<char>& free) override;

 private:
  struct Part {
    std::vector<int> rows;    // island rows, increasing
    std::vector<int> bodies;  // island bodies: others first, interface bodies (k) last, increasing
    int k = 0;
    // Interface rows touching the part (increasing interface index t), with the slot and the
    // interface body (0..k-1) they act on.
    std::vector<int> touch, touch_slot, touch_body;
    // Part rows acting on an interface body: (part row, slot, interface body).
    std::vector<std::array<int, 3>> coupling;
    PartMatrix a;
    Eigen::VectorXd q, shifted_q, lo, hi, lambda, trial_lambda;
    // Accepted sets, those of a trial step, and the sets S and q~ are formed for.
    std::vector<RowState> state, trial_state, used;
    std::vector<char> used_free, contribution_free, free;
    bool contribution_valid = false;       // w, h, c hold the block of S for contribution_free
    bool refresh = true;                   // step 1 due (sets changed or new bounds)
    bool contribution_changed = false;     // its block of S changed since S~ was summed
    bool ok = true;
    BlcpWorkspace ws;
    BlcpSettings settings;
    double settings_tolerance = 0;         // the island's absolute feasibility tolerance
    Eigen::MatrixXd w, h, c;               // W_p (6k x 6k), J_T W_p, C = J_T W_p J_T^T (|T| x |T|)
    Eigen::VectorXd qc, y, u, v, x, b;     // q~ term and S x term (|T|), scratch
    std::array<double, kPhaseCount> phase_ms{};
    double item_ms = 0;
    int iterations = 0;
    bool newton = false;
  };

  // The BLCP matrix of the interface problem: exact Schur products, the Cholesky factor of S~.
  class InterfaceMatrix final : public BlcpMatrix {
   public:
    explicit InterfaceMatrix(SubstructuredIsland& island) : island_(island) {}
    void assign(const Eigen::VectorXd& diag);
    // S~ to be filled (lower triangle), then changed().
    Eigen::MatrixXd& approximation() { return approx_.matrix(); }
    void changed();
    int factorizations() const { return factorizations_; }
    int size() const override { return static_cast<int>(diag_.size()); }
    const Eigen::VectorXd& diagonal() const override { return diag_; }
    void multiply(const Eigen::VectorXd& x, Eigen::VectorXd& y) override { island_.schur_product(x, y); }
    void solve(Eigen::VectorXd& x) override { approx_.solve(x); }

   protected:
    bool factor(const std::vector<char>& free) override;

   private:
    SubstructuredIsland& island_;
    DenseBlcpMatrix approx_;
    Eigen::VectorXd diag_;  // A_jj of the interface rows (the monolithic solve's row scales)
    int factorizations_ = 0;
  };

  // Runs fn(part) for every part in parallel as work of `phase` (factorisations inside go to
  // kFactorPhase); the section's slowest part counts towards the critical path.
  template <class Fn>
  void for_parts(SubPhase phase, Fn&& fn);
  // Factors part p for `free` and, if its free set changed, forms W_p and its block of S.
  bool factor_part(Part& p, const std::vector<char>& free);
  // lambda^_p for the sets `used` and its term of q~.
  void form_rhs_term(Part& p);
  // Step 3 at interface impulses x: every part's BLCP, warm started from its accepted answer, into
  // its trial_lambda/trial_state. False if one failed.
  bool solve_parts(const Eigen::VectorXd& x);
  // f = 1/2 l^T A l + q^T l of the island for the trial answer and interface impulses x; w = A l + q
  // into w_ and its round-off allowance into `roundoff`.
  double objective(const Eigen::VectorXd& x, double& roundoff);
  // S~ from the parts' blocks, in part order, if any block changed.
  void assemble_schur();
  // y = S x exactly, with the parts' sets `used`.
  void schur_product(const Eigen::VectorXd& x, Eigen::VectorXd& y);
  // u = M^-1 J_{I,p}^T x on p's interface bodies, for interface values x (entries with !mask skipped).
  void interface_velocity(const Part& p, const Eigen::VectorXd& x, const std::vector<char>* mask,
                          Eigen::VectorXd& u) const;

  const IslandSystem* s_ = nullptr;
  std::vector<Part> parts_;
  std::vector<int> part_of_body_, body_index_;
  std::vector<int> interface_row_;  // interface index -> island row
  int interface_bodies_ = 0;
  std::vector<Mat6> mass_;
  InterfaceMatrix interface_;
  Eigen::VectorXd q_i_, q_tilde_, lo_i_, hi_i_, lambda_i_, sigma_i_, g_i_, du_;
  Eigen::VectorXd current_i_, step_i_, trial_i_, w_i_, island_lambda_, w_;
  std::vector<RowState> state_i_;
  std::vector<char> free_i_;
  BlcpWorkspace interface_ws_;
  TiedBodySpaceLu tied_;
  // Timing: serial work per phase, walls of the timed sections, the critical path's share of them.
  std::array<double, kPhaseCount> serial_ms_{};
  double accounted_ms_ = 0, span_ms_ = 0;
  int loop_iterations_ = 0, interface_iterations_ = 0;
  bool interface_newton_ = false;
};

template <class Fn>
void SubstructuredIsland::serial(SubPhase phase, Fn&& fn) {
  const double before = accounted_ms_;
  const Timer timer;
  fn();
  const double wall = timer.ms();
  const double own = wall - (accounted_ms_ - before);
  serial_ms_[phase] += own;
  span_ms_ += own;
  accounted_ms_ = before + wall;
}

}  // namespace rbpart
