#pragma once
// Solve stage: the BLCP of every island (DESIGN.md §3), by the monolithic direct solver or PGS.
// On return rows.lambda holds the impulses and rows.state the index sets (next step's warm start).
#include <rbpart/params.hpp>

#include "assembly/rows.hpp"
#include "graph/islands.hpp"
#include "scene/bodies.hpp"

namespace rbpart {

struct SolveReport {
  int iterations = 0;        // block-pivoting iterations (direct) or sweeps (PGS), summed over islands
  int friction_passes = 0;   // outer passes for the friction bounds, max over islands
  int factorizations = 0;    // matrix factorisations, summed over islands
  int newton_islands = 0;    // islands where pivoting stalled and projected Newton finished
  int failures = 0;          // islands whose BLCP did not converge within the caps
  int unsettled = 0;         // islands whose friction loop ended above friction_tolerance
  double residual = 0;       // max scaled natural-map residual over all rows (DESIGN.md §3)
  double factor_ms = 0;      // time in factorisations, summed over islands (Newton solver)
};

// Monolithic direct solver: block principal pivoting per island (projected Newton when it stalls), dense Cholesky for small islands,
// CHOLMOD for large ones; islands in parallel.
SolveReport solve_direct(Rows& rows, const Bodies& bodies, const Islands& islands, const SolverParams& params);

class IslandCache;

// The Newton solver on the coupled problem (solve/newton.hpp) with the monolithic body-space
// backend (solve/monolithic.hpp); islands in parallel. `--solver newton`, under construction: it is
// to replace solve_direct (see docs/pipeline.md for its measured state). With `cache`
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
