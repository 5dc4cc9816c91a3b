#pragma once
// Replay: every configuration solves every recorded step's problem (study/capture.hpp) — partition, refine
// and the substructured solve (docs/design.md#partition, #refine, #substructured), each timed on its own —
// and the direct solver (the same Newton solver on the monolithic backend) solves it once more as the
// baseline. Times are medians over repeats.
#include <rbpart/params.hpp>

#include <functional>
#include <vector>

#include "study/capture.hpp"

namespace rbpart {

// One column of the study. Partitioner None is the direct solver (the baseline).
struct StudyConfig {
  PartitionerKind partitioner = PartitionerKind::None;
  RefinerKind refiner = RefinerKind::None;
  int nmax = 0;     // 0 for the direct baseline
  int threads = 1;  // tbb::global_control limit during its solves
  bool direct() const { return partitioner == PartitionerKind::None; }
};

// One configuration on one recorded step. The times are medians over the repeats, each taken on
// its own; the counts are the same in every repeat (the solvers are deterministic).
struct StepMeasure {
  double partition_ms = 0, refine_ms = 0, solve_ms = 0;
  // Substructured only (its SolveStats): the solve's work summed over threads, and its
  // critical path (the slowest part of each parallel section), which bound its time on more cores.
  double work_ms = 0, critical_path_ms = 0;
  int parts = 0;                // sub-systems (islands for the direct baseline)
  int interface_rows = 0, interface_bodies = 0, edge_cut = 0;
  int factorizations = 0;       // the solve's factorisations, summed over islands (its cost, DESIGN.md §3)
  int unsettled = 0;            // islands whose answer ended above the residual 1e-9
  // max_j |lambda_j - live lambda_j| / max_j |live lambda_j|: the answer is the live run's.
  double lambda_error = 0;
};

struct ReplayResult {
  std::vector<std::vector<StepMeasure>> measures;  // [config][recorded step]
  // Recorded steps whose replayed direct solve did not reproduce the live impulses bit for bit
  // (counted per direct configuration): 0 unless a recording is incomplete.
  int direct_mismatches = 0;
};

// The median of v (reordered in place); 0 if v is empty.
double median(std::vector<double>& v);

// Solves every recorded step with every configuration, `repeats` times. Within a step the
// configurations take turns, in an order rotated by one each repeat, so slow drifts of the
// machine's load touch them all alike. `on_run` is called after each solve.
ReplayResult replay_trajectory(const Trajectory& trajectory, const std::vector<StudyConfig>& configs, int repeats,
                               const SolverParams& solver_params, const PartitionParams& partition_params,
                               const std::function<void()>& on_run = {});

}  // namespace rbpart
