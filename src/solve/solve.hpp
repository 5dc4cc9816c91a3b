#pragma once
// Solve stage: the contact problem of every island (DESIGN.md §3), by the Newton solver on the
// monolithic backend (the direct solver) or by PGS; the substructured backend is
// newton_substructured.hpp. On return rows.lambda holds the impulses and rows.state the row states
// (the next step's warm start).
#include <rbpart/params.hpp>
#include <rbpart/stats.hpp>

#include "assembly/rows.hpp"
#include "graph/islands.hpp"
#include "scene/bodies.hpp"

namespace rbpart {

template <class Backend>
class IslandCache;
class MonolithicSystem;

// The direct solver: the Newton solver on the coupled problem (solve/newton.hpp) with the monolithic
// body-space backend (solve/monolithic.hpp); islands in parallel. With `cache`
// (solve/island_cache.hpp), the islands' analyses and buffers carry over to the next call.
SolveStats solve_newton_direct(Rows& rows, const Bodies& bodies, const Islands& islands, const SolverParams& params,
                               IslandCache<MonolithicSystem>* cache = nullptr);

// Projected Gauss-Seidel on the same rows (the iterative baseline).
SolveStats solve_pgs(Rows& rows, const Bodies& bodies, const Islands& islands, const SolverParams& params);

// Scaled natural-map residual (solve/residual.hpp): max over rows of
// |lambda_j - clamp(lambda_j - w_j / A_jj, lo_j, hi_j)| * A_jj / s, w = A lambda + q, with friction
// bounds from the current normal impulses and s = max(max |q|, 1e-12) per island (dimensionless).
double natural_map_residual(const Rows& rows, const Bodies& bodies, const Islands& islands);

}  // namespace rbpart
