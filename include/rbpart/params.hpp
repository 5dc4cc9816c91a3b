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
  // Proximal term of a persisting contact's friction rows (docs/design.md#dynamics): sigma_t +=
  // contact_prox (J M^-1 J^T)_tt and q_t -= that times the step before's impulse, so that friction
  // yields only while its impulse changes (no creep at rest) and redundant friction rows do not leave
  // the step's problem near singular.
  double contact_prox = 1e-3;
  // Friction tangent t1 follows the sliding velocity when it exceeds this (m/s).
  double sliding_velocity_eps = 1e-4;
  // Position post-stabilisation (project/position_projection.hpp): after each step, Gauss-Newton
  // projections of the rigid joints' position errors and of contacts deeper than projection_depth
  // (m, pushed back to half of it), until every joint error is below joint_tolerance (m or rad) and
  // no contact is deeper than projection_depth; 0 iterations: Baumgarte only.
  // It runs when the scene has joints, when some body turned by more than projection_turn (rad) in
  // the step (the contacts' linearisation errs by ~ r turn^2 / 2 then: 1 mm at 0.1 rad), or when the
  // solve left an island unsettled (above the residual 1e-9); and before a step's solve when its
  // collide stage finds a contact deeper than projection_depth.
  int joint_projection_iterations = 8;
  double joint_tolerance = 1e-6;
  double projection_depth = 0.002;
  double projection_turn = 0.1;
  // Contacts are reported up to this separation (m), and handled speculatively (b = d/h).
  double contact_margin = 0.01;
};

struct SolverParams {
  SolverKind kind = SolverKind::Direct;  // the step's contact solver
  int max_factorizations = 40;  // Newton budget per island and step (docs/design.md#contact-problem)
  int pgs_iterations = 100;     // PGS sweeps per step
  double pgs_tolerance = 1e-8;  // PGS stops when the largest impulse change (scaled) falls below this
  int threads = 0;              // worker threads; 0: all hardware threads
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
