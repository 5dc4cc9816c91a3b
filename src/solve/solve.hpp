#pragma once
// Solve stage: the contact problem of every island (DESIGN.md §3), by the Newton solver on the
// monolithic backend (the direct solver) or by PGS; the substructured backend is
// newton_substructured.hpp. On return rows.lambda holds the impulses and rows.state the row states
// (the next step's warm start).
#include <rbpart/params.hpp>

#include "assembly/rows.hpp"
#include "graph/islands.hpp"
#include "scene/bodies.hpp"

namespace rbpart {

struct SolveReport {
  int iterations = 0;      // Newton steps (direct) or sweeps (PGS), summed over islands
  int factorizations = 0;  // matrix factorisations, summed over islands
  int unsettled = 0;       // islands whose answer ended above the residual 1e-9 (Newton solver)
  double residual = 0;     // max scaled natural-map residual over all rows (DESIGN.md §3)
  double factor_ms = 0;    // time in factorisations, summed over islands
};

class IslandCache;

// The direct solver: the Newton solver on the coupled problem (solve/newton.hpp) with the monolithic
// body-space backend (solve/monolithic.hpp); islands in parallel. With `cache`
// (solve/island_cache.hpp), the islands' analyses and buffers carry over to the next call.
SolveReport solve_newton_direct(Rows& rows, const Bodies& bodies, const Islands& islands, const SolverParams& params,
                                IslandCache* cache = nullptr);

// Projected Gauss-Seidel on the same rows (the iterative baseline).
SolveReport solve_pgs(Rows& rows, const Bodies& bodies, const Islands& islands, const SolverParams& params);

// Scaled natural-map residual (solve/residual.hpp): max over rows of
// |lambda_j - clamp(lambda_j - w_j / A_jj, lo_j, hi_j)| * A_jj / s, w = A lambda + q, with friction
// bounds from the current normal impulses and s = max(max |q|, 1e-12) per island (dimensionless).
double natural_map_residual(const Rows& rows, const Bodies& bodies, const Islands& islands);

}  // namespace rbpart
