#pragma once
// Every numerical parameter of the step, with its named default, in one place (docs/design.md#dynamics,
// #contact-problem). They are reported in the outputs (stats header, state file) so a run can be reproduced.
#include <string>

namespace rbpart {

// Direct: the one contact solver (docs/design.md#contact-problem) on the monolithic backend;
// Substructured: the same solver on the substructured backend (docs/design.md#substructured), which
// needs a partitioner; Pgs: projected Gauss-Seidel on the same rows, the iterative baseline.
enum class SolverKind { Direct, Pgs, Substructured };

struct StepParams {
  // Stabilisation (docs/design.md#dynamics): contact b = (erp/h) min(0, d + slop); joint b = (erp/h) drift.
  double erp = 0.2;
  double slop = 0.0001;          // m of penetration tolerated without correction
  // Regularisation floor: sigma_j >= sigma_floor * (J M^-1 J^T)_jj keeps A SPD with redundant rows.
  double sigma_floor = 1e-6;
  // Friction tangent t1 follows the sliding velocity when it exceeds this (m/s).
  double sliding_velocity_eps = 1e-4;
  // Position post-stabilisation (integrate/position_projection.hpp): after each step, Gauss-Newton
  // projections of the rigid joints' position errors and of contacts deeper than projection_depth
  // (m), until every joint error is below joint_tolerance (m or rad); 0 iterations: Baumgarte only.
  // It runs when the scene has joints, when some body turned by more than projection_turn (rad) in
  // the step (the contacts' linearisation errs by ~ r turn^2 / 2 then: 1 mm at 0.1 rad), or when the
  // direct solvers' friction loop ended unsettled (above friction_tolerance).
  int joint_projection_iterations = 8;
  double joint_tolerance = 1e-6;
  double projection_depth = 0.002;
  double projection_turn = 0.1;
  // Contacts are reported up to this separation (m), and handled speculatively (b = d/h).
  double contact_margin = 0.01;
};

struct SolverParams {
  SolverKind kind = SolverKind::Direct;
  // Newton solver (--solver newton, solve/newton.hpp): the budget (docs/design.md#contact-problem):
  // factorisations per island and step; past it the iterate of least residual is kept and the step counted
  // unsettled.
  int max_factorizations = 40;
  // Islands of at most this many bodies factor their body-space system dense, larger ones sparse.
  int dense_max_bodies = 8;
  // Direct (block principal pivoting, docs/design.md#contact-problem).
  int dense_max_rows = 300;        // islands up to this many rows use dense Cholesky, larger CHOLMOD
  int max_pivot_iterations = 500;  // per BLCP solve
  // Pivoting iterations without fewer infeasible rows before projected Newton takes over (the name
  // is that of the former Murty safeguard, kept because outputs report it under this key).
  int murty_after = 3;
  int friction_passes = 6;         // outer fixed-point passes for the friction bounds
  // The passes end when the friction rows' natural-map residual under the bounds from the new normal
  // impulses (friction_mismatch) is below this times max |lambda_n|. A resting 200-rock pile's
  // lagged pass is within 1.6e-6 (226 creeping contacts on their friction bound); the coupled step
  // took ~140 pivots (about 90 ms a step) to remove that.
  double friction_tolerance = 1e-5;
  // Warm paths the coupled friction step tries on islands of 3000 rows or more before it keeps the
  // lagged bounds (smaller islands: eight, then the cold path). Over the first 200 steps of the
  // 200-rock pile, on its islands of 1000+ rows, 42 of its 54 solved paths were the first or
  // second, 12 came later, and 61 calls failed after eight, costing 178 of the run's 229 s; the
  // cold path was tried 10 times, solving none. Two and no cold path: 500 steps' solve 206 -> 117
  // s, with 74 instead of 62 steps ending on the lagged bounds.
  int coupled_paths = 2;
  // PGS (the iterative baseline).
  int pgs_iterations = 100;
  double pgs_tolerance = 1e-8;     // stop when the largest impulse change (scaled) falls below
  // Substructured (docs/design.md#substructured): interface/sub-system iterations per BLCP before the counted
  // fallback to the monolithic backend. Resting steps settle in 1-3; while a pile lands the loop
  // rarely settles, and each iteration costs ~100 ms on the Large Rock Pile. Steps 10-150 of it
  // (MIX+FM, n_max 32, 1 thread, `rbpart bench ... --every 10`) took 2.09x the monolithic time
  // with a cap of 30, 1.44x with 10, 1.27x with 5.
  int substructured_max_iterations = 5;
  // Halved steps of the safeguard (docs/design.md#substructured) allowed per BLCP before the same fallback. A
  // full step that the safeguard rejects marks a loop far from its answer: on the first 150 steps of the
  // Large Rock Pile (as above, cap 5) falling back at the first one took MIX+FM from 1.27x to 1.13x the
  // monolithic time, MinDP from 1.68x to 1.35x. A large value keeps the descent method going to the answer,
  // which the tests use.
  int substructured_max_halvings = 0;
  int threads = 0;                 // 0: all hardware threads
};

// Partitioners and refiners (docs/design.md#partition, #refine). Partitioner None: no partition is made (the
// monolithic solvers' parts are the islands); any other partitioner runs every step, for the substructured
// solver or only to report its quality beside a monolithic solve.
enum class PartitionerKind { None, Bfs, MinDp, MaxDp, Mr, Mix, Metis };
// FmRollback is classic Fiduccia-Mattheyses (non-positive moves taken, best prefix kept), an
// extension beyond the paper's greedy KL and FM.
enum class RefinerKind { None, Kl, Fm, FmRollback };

struct PartitionParams {
  PartitionerKind partitioner = PartitionerKind::None;
  RefinerKind refiner = RefinerKind::None;
  int nmax = 32;          // most bodies in one sub-system
  double tau_mr = 10;     // MR: a body joins only if the part's mass ratio stays below this
  double tau_mix = 0.5;   // MIX: MinDP growth up to tau_mix * nmax bodies, then max-gain growth
  // Recompute gains and cut from scratch after every refinement move and check the partition's
  // properties (docs/design.md#partition) after every step; slow, for tests and debugging.
  bool debug_checks = false;
};

}  // namespace rbpart
