#pragma once
// The statistics a stage reports about its work, one record per stage, filled by the stage itself
// and held whole by a step's StepStats (world.hpp; docs/design.md#contracts: the stats CSV's columns).
#include <cstdint>

namespace rbpart {

// The solve stage's (docs/design.md#contact-problem): what solve_newton_direct, solve_pgs and
// solve_newton_substructured return.
struct SolveStats {
  int iterations = 0;      // Newton steps (Newton solver) or sweeps (PGS), summed over islands
  int factorizations = 0;  // matrix factorisations, summed over islands (0 for PGS)
  // The most factorisations one island took: the Newton budget's unit (max_factorizations).
  int island_factorizations = 0;
  // Islands whose answer ended above the residual 1e-9: approximate impulses (Newton solver).
  int unsettled = 0;
  double residual = 0;     // max scaled natural-map residual over all rows (dimensionless)
  double factor_ms = 0;    // time in factorisations, summed over threads and islands
  // Substructured solver only (0 otherwise): all its work summed over threads and islands (ms) ...
  double work_ms = 0;
  // ... and its critical path, each parallel phase replaced by its slowest part (ms): with c cores a
  // solve takes at least max(critical_path_ms, work_ms / c).
  double critical_path_ms = 0;
};

// The partition and refine stages' (docs/design.md#partition, #refine): the quality of the step's
// partition, as measure_partition counts it.
struct PartitionStats {
  int parts = 0;                     // sub-systems (= islands when nothing is partitioned)
  std::int64_t edge_cut = 0;         // constraints (edge weights) between different parts
  std::int64_t interface_rows = 0;   // rows between different parts (the size of the Schur complement S)
  int interface_bodies = 0;          // bodies with a constraint into another part
};

}  // namespace rbpart
